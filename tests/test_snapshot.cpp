// Snapshots (include/hail/snapshot.h, World::save / restore): a world saved and restored into
// another, on another thread count or SIMD path, steps on bitwise as the original (state hash,
// events, and its own snapshot after the steps: every saved byte); the free list, pending
// forces, planes, static spheres and touching keys carry over; a truncated, corrupt,
// future-version, wrong-terrain or inconsistent snapshot is refused naming the problem, with
// the world unchanged.

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "catch.h"
#include "file_faults.h"
#include "fuzz/snapshot_harness.h"
#include "hail/world.h"
#include "kernel/world/fnv1a.h"
#include "kernel/world/snapshot_format.h"
#include "sample_count.h"
#include "scenes/scene_run.h"
#include "scenes/scenes.h"
#include "simd_paths.h"

using namespace hail;

namespace {

using Bytes = std::vector<std::byte>;

Bytes saved(const World& world) {
  Bytes bytes;
  world.save(bytes);
  return bytes;
}

bench::Scene terrain_rain(int threads, std::size_t spheres = 4000) {
  bench::SceneParams params;
  params.spheres = spheres;
  params.threads = threads;
  return bench::find_scene("terrain-rain").build(params);
}

void step(World& world, int steps, float dt = 1.0f / 60.0f) {
  for (int k = 0; k < steps; ++k) world.step(dt);
}

/// Puts a correct checksum on bytes changed after save (to reach the checks past it).
void rechecksum(Bytes& bytes) {
  const std::uint64_t sum = snapshot::fnv1a(std::span<const std::byte>(bytes).subspan(snapshot::kHeaderBytes));
  std::memcpy(bytes.data() + snapshot::kChecksumAt, &sum, sizeof sum);
}

template <class T>
T read_at(const Bytes& bytes, std::size_t at) {
  T v{};
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

template <class T>
void write_at(Bytes& bytes, std::size_t at, T v) {
  std::memcpy(bytes.data() + at, &v, sizeof v);
}

/// `bytes` labelled `version`, `added` bytes longer in its payload and in the section at
/// `section` (WRLD's by default; inserted or, negative, removed by the caller), with the
/// checksum to match.
void relabel(Bytes& bytes, std::uint32_t version, std::int64_t added, std::size_t section = snapshot::kHeaderBytes);

/// A version 8 snapshot of a world with rolling resistance as version 7 wrote it: its CACH
/// section without the rolling impulses at its end (u64 count, then the floats).
Bytes without_rolling_impulses(const Bytes& bytes) {
  Bytes old = bytes;
  std::size_t at = snapshot::kHeaderBytes;
  while (std::memcmp(old.data() + at, snapshot::kCacheTag, 4) != 0)
    at += snapshot::kSectionHeaderBytes + read_at<std::uint64_t>(old, at + 8);
  const std::size_t section = at;
  at += snapshot::kSectionHeaderBytes;
  at += 8 + 20 * read_at<std::uint64_t>(old, at);  // entries: u32 partner, 4 floats
  at += 8 + 20 * read_at<std::uint64_t>(old, at);  // ranges: 5 u32
  const std::size_t removed = 8 + sizeof(float) * read_at<std::uint64_t>(old, at);
  old.erase(old.begin() + static_cast<std::ptrdiff_t>(at), old.begin() + static_cast<std::ptrdiff_t>(at + removed));
  relabel(old, 7, -static_cast<std::int64_t>(removed), section);
  return old;
}

/// restore(bytes) must throw InvalidArgument containing `needle`, leaving `world` as it was (every byte it saves).
void expect_refused(World& world, const Bytes& bytes, const std::string& needle) {
  const Bytes before = saved(world);
  const std::uint64_t hash = world.state_hash();
  try {
    world.restore(bytes);
    FAIL("expected hail::InvalidArgument mentioning '" << needle << "'");
  } catch (const InvalidArgument& e) {
    INFO("message: " << e.what());
    CHECK(std::string(e.what()).find(needle) != std::string::npos);
  }
  CHECK(world.state_hash() == hash);
  CHECK(saved(world) == before);
}

/// A small world with everything a snapshot keeps: a plane, static spheres, removed spheres
/// (a free list), touch and hit events on, user data, filters, gravity scales, forces pending.
std::unique_ptr<World> busy_world(int threads) {
  auto world = std::make_unique<World>(WorldSettings{.threads = threads, .reorder_interval = 8});
  world->add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.3f});
  world->add_plane({.normal = {1, 0, 0}, .offset = -6, .restitution = 0.8f});
  std::vector<SphereId> ids;
  for (int k = 0; k < 6; ++k)
    ids.push_back(world->add_sphere({.position = {-4.0f + 1.6f * float(k), 0.5f, 0.0f}, .is_static = true}));
  for (int k = 0; k < 240; ++k) {
    const float x = -3.0f + 0.55f * float(k % 12), z = -1.5f + 0.55f * float((k / 12) % 6);
    const float y = 1.5f + 0.6f * float(k / 72);
    ids.push_back(world->add_sphere({.position = {x, y, z},
                                     .velocity = {0.1f * float(k % 5), -1.0f, 0.0f},
                                     .radius = 0.22f + 0.01f * float(k % 4),
                                     .mass = 1.0f + float(k % 3),
                                     .restitution = 0.4f,
                                     .friction = 0.5f,
                                     .filter = {.category = 1u << (k % 3), .mask = k % 7 == 0 ? 0x3u : 0xFFFFFFFFu}}));
  }
  world->set_events({.touch = true, .hits = true, .hit_speed = 0.3f});
  // Category 0x4 (every third sphere) falls through the planes: a restore that lost the ground
  // filter would stop them there.
  world->set_ground_filter({.category = kDefaultCategory, .mask = ~0x4u});
  for (int k = 0; k < 240; k += 9) world->set_user_data(ids[6 + k], 1000u + k);
  for (int k = 0; k < 240; k += 11) world->set_gravity_scale(ids[6 + k], 0.5f);
  step(*world, 30);
  for (int k = 3; k < 240; k += 17) world->remove_sphere(ids[6 + k]);  // a free list, in this order
  step(*world, 20);
  for (int k = 1; k < 240; k += 13)
    if (world->slot_of(ids[6 + k]) >= 0) world->apply_force(ids[6 + k], {3.0f, 20.0f, -2.0f});
  return world;
}

bool same_touches(std::span<const TouchEvent> x, std::span<const TouchEvent> y) {
  if (x.size() != y.size()) return false;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (!(x[k].a == y[k].a && x[k].b == y[k].b && x[k].with == y[k].with && x[k].surface == y[k].surface)) return false;
  return true;
}

}  // namespace

TEST_CASE("terrain-rain 4k saved at step 100 and restored on 1 and 2 threads steps on to the same state",
          "[snapshot][threads]") {
  // 4,000 spheres; a fifth of them under the sanitizers (HAIL_TEST_SAMPLE_DIVISOR, sample_count.h):
  // at 4,000 this case alone took 118 s of the ThreadSanitizer stage, and the races and memory
  // faults it looks for are the same at 800.
  const std::size_t spheres = static_cast<std::size_t>(hail::test::sample_count(4000));
  bench::Scene original = terrain_rain(2, spheres);
  World& a = *original.world;
  step(a, 100);
  const Bytes at_100 = saved(a);
  step(a, 200);
  const std::uint64_t expected = a.state_hash();
  const Bytes at_300 = saved(a);

  for (int threads : {1, 2}) {
    INFO(threads << " threads");
    bench::Scene copy = terrain_rain(threads, spheres);  // same terrain; its own spheres are replaced
    step(*copy.world, 7);                                // not a fresh World: its scratch has been used
    copy.world->restore(at_100);
    CHECK(copy.world->thread_count() == threads);
    step(*copy.world, 200);
    CHECK(copy.world->state_hash() == expected);
    CHECK(saved(*copy.world) == at_300);
  }
}

TEST_CASE("A pile with rolling resistance restored on 1 and 2 threads steps on to the same state", "[snapshot][rolling]") {
  // The warm-start cache carries each contact's rolling impulse (snapshot version 8): restored
  // without them, the next step's rolling resistance would start from zero and differ.
  auto bowl_pile = [](int threads) {
    bench::SceneParams params;
    params.spheres = 400;
    params.threads = threads;
    params.set = {"rolling_resistance=0.1"};
    return bench::find_scene("bowl-pile").build(params);
  };
  bench::Scene original = bowl_pile(2);
  step(*original.world, 90);  // landed (at about step 60) and rolling
  const Bytes at_90 = saved(*original.world);
  step(*original.world, 30);
  const std::uint64_t expected = original.world->state_hash();
  for (int threads : {1, 2}) {
    INFO(threads << " threads");
    bench::Scene copy = bowl_pile(threads);
    copy.world->restore(at_90);
    step(*copy.world, 30);
    CHECK(copy.world->state_hash() == expected);
  }
  // As version 7 saved it (no rolling impulses, which then start from zero) it still restores,
  // and steps on to another state: the impulses carried matter.
  bench::Scene cold = bowl_pile(2);
  cold.world->restore(without_rolling_impulses(at_90));
  step(*cold.world, 30);
  CHECK(cold.world->state_hash() != expected);
}

TEST_CASE("A snapshot restored under another SIMD path steps on to the same state", "[snapshot]") {
  bench::Scene original = terrain_rain(1, 1000);
  step(*original.world, 40);
  const Bytes at_40 = saved(*original.world);
  step(*original.world, 60);
  const std::uint64_t expected = original.world->state_hash();
  for (SimdPath path : testing::supported_paths()) {
    testing::ScopedSimdPath scoped(path);
    INFO("SIMD " << simd_path_name(path));
    bench::Scene copy = terrain_rain(1, 1000);
    copy.world->restore(at_40);
    step(*copy.world, 60);
    CHECK(copy.world->state_hash() == expected);
  }
}

TEST_CASE("Free list, static spheres, planes, forces pending and touch events carry over a snapshot",
          "[snapshot][threads]") {
  std::unique_ptr<World> a = busy_world(2);
  const Bytes bytes = saved(*a);
  World b(WorldSettings{.threads = 1});  // fresh, other settings: all replaced but threads
  b.restore(bytes);
  CHECK(saved(b) == bytes);
  CHECK(b.settings().threads == 1);
  CHECK(b.settings().reorder_interval == 8);
  CHECK(b.planes().size() == 2);
  CHECK(b.event_settings().touch);
  CHECK(b.ground_filter() == a->ground_filter());
  REQUIRE(b.sphere_count() == a->sphere_count());
  for (std::size_t k = 0; k < a->sphere_count(); ++k) {
    CHECK(b.id_at(k) == a->id_at(k));
    CHECK(b.user_data(b.id_at(k)) == a->user_data(a->id_at(k)));
  }
  std::size_t touches = 0;
  for (int k = 0; k < 120; ++k) {
    a->step(1.0f / 60.0f);
    b.step(1.0f / 60.0f);
    REQUIRE(b.state_hash() == a->state_hash());
    CHECK(same_touches(a->touch_begin_events(), b.touch_begin_events()));
    CHECK(same_touches(a->touch_end_events(), b.touch_end_events()));
    CHECK(a->hit_events().size() == b.hit_events().size());
    touches += a->touch_begin_events().size() + a->touch_end_events().size();
    if (k == 10) {  // a sphere added after the restore takes the same freed handle in both
      const SphereDesc d{.position = {0.0f, 6.0f, 0.0f}};
      CHECK(a->add_sphere(d) == b.add_sphere(d));
    }
  }
  CHECK(touches > 0);  // the touching keys were saved: a restore that lost them begins every touch again
  CHECK(saved(b) == saved(*a));
}

TEST_CASE("A world restored from a snapshot saves the same bytes, and a file round trip is the same", "[snapshot]") {
  std::unique_ptr<World> a = busy_world(1);
  const Bytes bytes = saved(*a);
  const std::string path = (std::filesystem::temp_directory_path() / "hail-test-snapshot.bin").string();
  a->save_file(path);
  World b(WorldSettings{.threads = 1});
  b.restore_file(path);
  CHECK(saved(b) == bytes);
  std::filesystem::remove(path);
  CHECK_THROWS_AS(b.restore_file(path), FileError);
  CHECK_THROWS_AS(a->save_file((std::filesystem::temp_directory_path() / "no-such-dir" / "x.bin").string()), FileError);
  CHECK(saved(b) == bytes);
}

TEST_CASE("A truncated, corrupt, future-version or foreign snapshot is refused, the world unchanged", "[snapshot]") {
  std::unique_ptr<World> source = busy_world(1);
  const Bytes good = saved(*source);
  std::unique_ptr<World> target = busy_world(1);
  target->step(1.0f / 60.0f);  // differs from source

  SECTION("truncated") {
    for (std::size_t length : {std::size_t{0}, std::size_t{5}, std::size_t{20}, std::size_t{40}, good.size() - 1})
      expect_refused(*target, Bytes(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length)), "truncated");
  }
  SECTION("not a snapshot") {
    Bytes bad = good;
    bad[0] = std::byte{'X'};
    expect_refused(*target, bad, "not a hail snapshot");
  }
  SECTION("corrupt: one bit of the payload flipped") {
    for (std::size_t at : {snapshot::kHeaderBytes + 3, good.size() / 2, good.size() - 1}) {
      Bytes bad = good;
      bad[at] ^= std::byte{0x10};
      expect_refused(*target, bad, "checksum mismatch");
    }
  }
  SECTION("a newer format version") {
    Bytes bad = good;
    const std::uint32_t future = kSnapshotVersion + 1;
    std::memcpy(bad.data() + 8, &future, sizeof future);
    expect_refused(*target, bad, "newer than this hail reads");
  }
  SECTION("bytes after the payload") {
    Bytes bad = good;
    bad.push_back(std::byte{0});
    expect_refused(*target, bad, "bytes after the payload");
  }
  SECTION("inconsistent handles (checksum made right)") {
    // The first handle of the sphere section: WRLD's header and body, PLNS, then SPHR's
    // header and its three counts.
    Bytes bad = good;
    std::uint64_t world_length, planes_length;
    std::memcpy(&world_length, bad.data() + snapshot::kHeaderBytes + 8, 8);
    const std::size_t planes_at = snapshot::kHeaderBytes + snapshot::kSectionHeaderBytes + world_length;
    std::memcpy(&planes_length, bad.data() + planes_at + 8, 8);
    const std::size_t spheres_at = planes_at + snapshot::kSectionHeaderBytes + planes_length;
    REQUIRE(std::memcmp(bad.data() + spheres_at, "SPHR", 4) == 0);
    const std::size_t first_handle = spheres_at + snapshot::kSectionHeaderBytes + 3 * sizeof(std::uint64_t);
    const std::uint32_t generation = 999;
    std::memcpy(bad.data() + first_handle + 4, &generation, 4);
    rechecksum(bad);
    expect_refused(*target, bad, "is not its index's generation");
  }
  SECTION("unknown sphere flags, or a kinematic sphere with a mass (checksum made right)") {
    // One kinematic sphere against the same sphere made dynamic (1 kg): the saves differ in its
    // inverse mass (1.0f), inverse inertia (10.0f) and flags (1), and only the flags' first
    // byte is 0x01 in one and 0x00 in the other.
    World kinematic(WorldSettings{.threads = 1}), dynamic(WorldSettings{.threads = 1});
    for (World* w : {&kinematic, &dynamic}) w->add_sphere({.radius = 0.5f, .is_kinematic = true});
    dynamic.set_dynamic(dynamic.id_at(0), 1.0f);
    const Bytes k = saved(kinematic), d = saved(dynamic);
    REQUIRE(k.size() == d.size());
    std::size_t flags_at = 0, found = 0;
    for (std::size_t i = snapshot::kHeaderBytes; i < k.size(); ++i)
      if (k[i] == std::byte{1} && d[i] == std::byte{0}) flags_at = i, ++found;
    REQUIRE(found == 1);
    Bytes bad = d;
    bad[flags_at] = std::byte{1};
    rechecksum(bad);
    expect_refused(*target, bad, "is kinematic with an inverse mass > 0");
    bad[flags_at] = std::byte{0x80};
    rechecksum(bad);
    expect_refused(*target, bad, "has unknown bits");
  }
  SECTION("another terrain, or none") {
    bench::Scene rain = terrain_rain(1, 200);
    const Bytes with_terrain = saved(*rain.world);
    expect_refused(*target, with_terrain, "has none");  // target has no terrain
    bench::SceneParams params;
    params.spheres = 200;
    params.threads = 1;
    bench::Scene dem = bench::find_scene("terrain-rain-dem").build(params);
    expect_refused(*dem.world, with_terrain, "wrong terrain");
    expect_refused(*rain.world, good, "without a terrain");
  }
}

TEST_CASE("SphereSoA::for_each_array lists every per-sphere array once", "[snapshot][soa]") {
  SphereSoA soa;
  soa.add({1, 2, 3, 0, 0, 0, 0, 0, 0, 0.5f, 1, 1, 0.5f, 0.5f, kSphereFlagNone});
  std::set<std::string> names;
  std::set<const void*> arrays;
  std::size_t visited = 0;
  soa.for_each_array([&](const char* name, const auto& array) {
    ++visited;
    names.insert(name);
    arrays.insert(&array);
    CHECK(array.size() == soa.padded_size());
  });
  CHECK(visited == SphereSoA::kArrayCount);
  CHECK(names.size() == visited);
  CHECK(arrays.size() == visited);
}

namespace {

const std::filesystem::path kCorpus = std::filesystem::path(HAIL_SOURCE_DIR) / "tests/fuzz/corpus/snapshot";

/// The seed corpus of the snapshot fuzzer: small valid snapshots of the fuzzer's two worlds.
std::vector<std::pair<std::string, Bytes>> corpus_seeds() {
  std::vector<std::pair<std::string, Bytes>> seeds;
  seeds.emplace_back("empty.snap", saved(*fuzz::snapshot_fuzz_world(false)));
  {
    std::unique_ptr<World> w = fuzz::snapshot_fuzz_world(false);
    w->add_plane({});
    std::vector<SphereId> ids;
    for (int k = 0; k < 8; ++k)
      ids.push_back(w->add_sphere(
          {.position = {0.3f * float(k % 3), 0.6f + 1.1f * float(k), 0.2f * float(k % 2)}, .radius = 0.5f}));
    w->set_events({.touch = true, .hits = true});
    step(*w, 40);
    w->remove_sphere(ids[2]);
    w->remove_sphere(ids[5]);
    step(*w, 3);
    w->apply_force(ids[0], {1.0f, 2.0f, 3.0f});
    seeds.emplace_back("planes-events-8.snap", saved(*w));
  }
  {
    std::unique_ptr<World> w = fuzz::snapshot_fuzz_world(true);
    for (int k = 0; k < 6; ++k) w->add_sphere({.position = {-2.0f + 0.8f * float(k), 1.0f, 0.5f}, .radius = 0.3f});
    step(*w, 30);
    seeds.emplace_back("terrain-6.snap", saved(*w));
  }
  {
    // Rolling resistance: the cache's rolling impulses (version 8).
    WorldSettings settings;
    settings.threads = 1;
    settings.rolling_resistance = 0.1f;
    World w(settings);
    w.set_terrain(fuzz::snapshot_fuzz_terrain());
    for (int k = 0; k < 6; ++k)
      w.add_sphere({.position = {-2.0f + 0.8f * float(k), 1.0f, 0.5f}, .angular_velocity = {0, 0, 3}, .radius = 0.3f});
    step(w, 60);  // landed at about step 26, and rolling down the slope
    seeds.emplace_back("rolling-terrain-6.snap", saved(w));
  }
  return seeds;
}

Bytes read_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  const std::vector<char> chars((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const auto* p = reinterpret_cast<const std::byte*>(chars.data());
  return Bytes(p, p + chars.size());
}

/// tests/data/snapshot-v6-terrain-6.snap: the world of snapshot-v4-terrain-6.snap as version 6
/// saves it. Both were the fuzzer's terrain-6 seed when they were written (a fresh run of the
/// seed's 30 steps gave these bytes); the seed itself moves whenever a physics change moves
/// those steps, the old files' world does not.
Bytes version6_as_this(const Bytes& bytes);  // below, with the other version helpers

Bytes legacy_as_version6() {
  return read_bytes(std::filesystem::path(HAIL_SOURCE_DIR) / "tests/data/snapshot-v6-terrain-6.snap");
}

}  // namespace

TEST_CASE("Write the snapshot fuzzer's seed corpus", "[.write-snapshot-corpus]") {
  std::filesystem::create_directories(kCorpus);
  for (const auto& [name, bytes] : corpus_seeds()) {
    std::ofstream file(kCorpus / name, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
}

TEST_CASE("The snapshot fuzzer's seeds are what this hail saves, and each restores and saves back",
          "[snapshot][fuzz]") {
  for (const auto& [name, bytes] : corpus_seeds()) {
    INFO(name << " (after a format change: hail-tests \"[.write-snapshot-corpus]\" rewrites the seeds)");
    CHECK(read_bytes(kCorpus / name) == bytes);
  }
  std::size_t restored = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kCorpus)) {
    const Bytes bytes = read_bytes(entry.path());
    for (bool terrain : {false, true}) {
      const fuzz::SnapshotOutcome outcome = fuzz::restore_and_compare(*fuzz::snapshot_fuzz_world(terrain), bytes);
      CHECK(outcome != fuzz::SnapshotOutcome::Misread);
      restored += outcome == fuzz::SnapshotOutcome::Restored ? 1 : 0;
    }
  }
  CHECK(restored == 4);  // each seed into the world of its terrain
}

TEST_CASE("A version 4 snapshot (the old checksum basis) still restores, and saves as this version", "[snapshot]") {
  // tests/data/snapshot-v4-terrain-6.snap is the fuzzer's terrain-6 seed as version 4 wrote it:
  // the same layout, its checksum and terrain hash made from FNV-1a's offset basis a digit short.
  const Bytes legacy = read_bytes(std::filesystem::path(HAIL_SOURCE_DIR) / "tests/data/snapshot-v4-terrain-6.snap");
  std::uint32_t version = 0;
  REQUIRE(legacy.size() > 12);
  std::memcpy(&version, legacy.data() + 8, sizeof version);
  REQUIRE(version == 4);
  std::unique_ptr<World> world = fuzz::snapshot_fuzz_world(true);
  world->restore(legacy);
  CHECK(saved(*world) == version6_as_this(legacy_as_version6()));
  CHECK(world->settings().rolling_resistance == 0.0f);  // version 4 had none
}

namespace {

/// Where a setting lies in a snapshot of this version: past the header, WRLD's section header
/// and the settings before it in the table, each as many bytes as the snapshot gives it.
/// Versions 4 and 5 have their warm_start byte where warm_start_factor lies, and the factor
/// after it; version 6 has no rolling_resistance (the table lists it after warm_start_factor).
std::size_t setting_at(const void* WorldSettings_field_of_defaults, const WorldSettings& s) {
  std::size_t at = 0;
  bool reached = false;
  snapshot::for_each_setting(s, [&](const auto& field, const SettingSpec&) {
    using T = std::remove_cvref_t<decltype(field)>;
    reached = reached || static_cast<const void*>(&field) == WorldSettings_field_of_defaults;
    if (!reached) at += std::is_same_v<T, bool> ? 1 : std::is_enum_v<T> ? 4 : sizeof(T);
  });
  return snapshot::kHeaderBytes + snapshot::kSectionHeaderBytes + at;
}
const WorldSettings kDefaults;
std::size_t warm_start_factor_at() { return setting_at(&kDefaults.warm_start_factor, kDefaults); }
std::size_t rolling_resistance_at() { return setting_at(&kDefaults.rolling_resistance, kDefaults); }

void relabel(Bytes& bytes, std::uint32_t version, std::int64_t added, std::size_t section) {
  write_at(bytes, 8, version);
  // The payload's length and the section's.
  for (std::size_t at : {snapshot::kPayloadBytesAt, section + 8})
    write_at(bytes, at, static_cast<std::uint64_t>(static_cast<std::int64_t>(read_at<std::uint64_t>(bytes, at)) + added));
  rechecksum(bytes);
}

/// A snapshot of this version as version 6 wrote the same world: no rolling_resistance (the
/// world's must be 0, all version 6 knew).
Bytes as_version6(const Bytes& bytes) {
  Bytes old = bytes;
  const auto at = static_cast<std::ptrdiff_t>(rolling_resistance_at());
  old.erase(old.begin() + at, old.begin() + at + static_cast<std::ptrdiff_t>(sizeof(float)));
  relabel(old, 6, -static_cast<std::int64_t>(sizeof(float)));
  return old;
}

/// A version 6 snapshot as this version saves the same world: rolling_resistance 0 added.
Bytes version6_as_this(const Bytes& bytes) {
  Bytes now = bytes;
  now.insert(now.begin() + static_cast<std::ptrdiff_t>(rolling_resistance_at()), sizeof(float), std::byte{0});
  relabel(now, hail::kSnapshotVersion, static_cast<std::int64_t>(sizeof(float)));
  return now;
}

/// A snapshot of this version as version 5 wrote the same world: version 6's layout with its
/// warm_start byte before warm_start_factor, and the lengths and checksum to match.
Bytes as_version5(const Bytes& bytes, bool warm_start) {
  Bytes old = as_version6(bytes);
  old.insert(old.begin() + static_cast<std::ptrdiff_t>(warm_start_factor_at()), std::byte{warm_start});
  relabel(old, 5, 1);
  return old;
}

/// `bytes` with warm_start_factor set to `factor` (this version's layout).
Bytes with_warm_start_factor(const Bytes& bytes, float factor) {
  Bytes edited = bytes;
  std::memcpy(edited.data() + warm_start_factor_at(), &factor, sizeof factor);
  rechecksum(edited);
  return edited;
}

}  // namespace

TEST_CASE("A version 6 snapshot (no rolling resistance) restores with rolling_resistance 0", "[snapshot]") {
  std::unique_ptr<World> source = busy_world(1);
  const Bytes now = saved(*source);
  WorldSettings rolling;
  rolling.threads = 1;
  rolling.rolling_resistance = 0.3f;
  auto world = std::make_unique<World>(rolling);
  world->restore(as_version6(now));
  CHECK(world->settings().rolling_resistance == 0.0f);
  CHECK(saved(*world) == now);
  CHECK(version6_as_this(as_version6(now)) == now);
}

TEST_CASE("A version 4 or 5 snapshot saved with warm starting off restores with warm_start_factor 0", "[snapshot]") {
  SECTION("version 5, warm starting on and off") {
    std::unique_ptr<World> source = busy_world(1);
    const Bytes now = saved(*source);
    REQUIRE(source->settings().warm_start_factor == 1.0f);
    std::unique_ptr<World> world = busy_world(1);
    world->restore(as_version5(now, true));
    CHECK(world->settings().warm_start_factor == 1.0f);
    CHECK(saved(*world) == now);
    world->restore(as_version5(now, false));
    CHECK(world->settings().warm_start_factor == 0.0f);
    CHECK(saved(*world) == with_warm_start_factor(now, 0.0f));  // the same world, as this version saves it
  }
  SECTION("version 4: the file of tests/data with its warm_start byte cleared") {
    Bytes legacy = read_bytes(std::filesystem::path(HAIL_SOURCE_DIR) / "tests/data/snapshot-v4-terrain-6.snap");
    const std::size_t at = warm_start_factor_at();
    REQUIRE(legacy.size() > at + 5);
    REQUIRE(legacy[at] == std::byte{1});  // saved with warm starting on
    legacy[at] = std::byte{0};
    const std::uint64_t sum =
        snapshot::fnv1a(std::span<const std::byte>(legacy).subspan(snapshot::kHeaderBytes), kLegacyFnvOffsetBasis);
    std::memcpy(legacy.data() + snapshot::kChecksumAt, &sum, sizeof sum);
    std::unique_ptr<World> world = fuzz::snapshot_fuzz_world(true);
    world->restore(legacy);
    CHECK(world->settings().warm_start_factor == 0.0f);
    CHECK(saved(*world) == with_warm_start_factor(version6_as_this(legacy_as_version6()), 0.0f));
  }
}

TEST_CASE("FNV-1a 64 gives the published test vectors", "[snapshot][hash]") {
  // The FNV reference's vectors (Fowler, Noll, Vo: "FNV-1a 64", test_fnv.c): "" is the offset basis.
  auto hash = [](const std::string& text) { return fnv1a(std::as_bytes(std::span<const char>(text))); };
  CHECK(hash("") == 0xcbf29ce484222325ull);
  CHECK(hash("a") == 0xaf63dc4c8601ec8cull);
  CHECK(hash("foobar") == 0x85944171f73967e8ull);
}

TEST_CASE("Spans from spheres() and handles() stay valid across restore, showing the restored state", "[snapshot]") {
  std::unique_ptr<World> world = busy_world(1);
  const Bytes at_start = saved(*world);
  std::vector<float> saved_x(world->spheres().px.begin(), world->spheres().px.end());
  std::vector<SphereId> saved_ids(world->handles().begin(), world->handles().end());
  step(*world, 20);
  const SphereState view = world->spheres();
  const std::span<const SphereId> handles = world->handles();
  REQUIRE(view.px.size() == saved_x.size());
  CHECK(std::vector<float>(view.px.begin(), view.px.end()) != saved_x);  // the step moved them
  world->restore(at_start);
  // The same buffers: a rollback reads through the spans it holds (they dangled before).
  CHECK(world->spheres().px.data() == view.px.data());
  CHECK(world->spheres().inv_mass.data() == view.inv_mass.data());
  CHECK(world->handles().data() == handles.data());
  CHECK(std::vector<float>(view.px.begin(), view.px.end()) == saved_x);
  CHECK(std::vector<SphereId>(handles.begin(), handles.end()) == saved_ids);
  CHECK(saved(*world) == at_start);
}

namespace {

/// Where the values of the sphere array `name` start in a snapshot (its name length, name and
/// element size come before them).
std::size_t sphere_array_at(const Bytes& bytes, const std::string& name) {
  std::vector<std::byte> key{std::byte(name.size())};
  for (char c : name) key.push_back(std::byte(c));
  const auto found = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
  REQUIRE(found != bytes.end());
  return static_cast<std::size_t>(found - bytes.begin()) + key.size() + 1;
}

}  // namespace

TEST_CASE("A snapshot's sphere fields are checked as add_sphere checks them", "[snapshot]") {
  // Before, a movable sphere with inverse inertia 0, or inverse mass 1e38, restored, and the
  // kinetic energy became NaN while a run reported no NaN.
  World one(WorldSettings{.threads = 1});
  one.add_sphere({.position = {0, 1, 0}, .velocity = {1, 0, 0}, .radius = 0.5f, .mass = 2.0f});
  const Bytes good = saved(one);
  std::unique_ptr<World> target = busy_world(1);
  auto edited = [&](const std::string& array, float value) {
    Bytes bad = good;
    std::memcpy(bad.data() + sphere_array_at(bad, array), &value, sizeof value);
    rechecksum(bad);
    return bad;
  };
  expect_refused(*target, edited("inv_inertia", 0.0f), "inverse inertia");
  expect_refused(*target, edited("inv_inertia", 1e30f), "inverse inertia");
  expect_refused(*target, edited("inv_mass", 1e38f), "out of [kMinSphereMass, kMaxSphereMass]");
  expect_refused(*target, edited("vx", 3e6f), "kMaxSphereSpeed");
  expect_refused(*target, edited("py", std::numeric_limits<float>::infinity()), "position");
  expect_refused(*target, edited("wy", 3e6f), "kMaxSphereSpin");
  expect_refused(*target, edited("force_x", 3e38f), "force of 3e+38");
  expect_refused(*target, edited("gravity_scale", 1e5f), "gravity scale");
  expect_refused(*target, edited("sleep_timer", -1.0f), "sleep_timer");
  expect_refused(*target, edited("radius", 1e-7f), "1e-07");  // %g: no longer "0.000000"
  World copy(WorldSettings{.threads = 1});
  copy.restore(good);  // the unedited bytes restore
  CHECK(copy.kinetic_energy() == one.kinetic_energy());
}

TEST_CASE("restore_file refuses a folder, a FIFO and a device before reading them", "[snapshot][files]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-test-snapshot-files";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  World world(WorldSettings{.threads = 1});
  // A folder threw std::ios_base::failure, not FileError; /dev/zero read gigabytes; a FIFO hung.
  using hail::testing::message_of;
  CHECK_THAT(message_of<FileError>([&] { world.restore_file(dir.string()); }), Catch::Contains("is a directory"));
  CHECK_THAT(message_of<FileError>([&] { world.restore_file("/dev/zero"); }), Catch::Contains("is a device"));
  const std::string fifo = (dir / "fifo").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::optional<std::string> thrown =
      hail::testing::thrown_within<FileError>(std::chrono::seconds(10), [&] { world.restore_file(fifo); });
  REQUIRE(thrown.has_value());  // returned: did not block on the FIFO
  CHECK_THAT(*thrown, Catch::Contains("FIFO"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("save_file replaces the old snapshot only once the new one is whole", "[snapshot][files]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-test-snapshot-save";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "world.snap").string();
  std::unique_ptr<World> world = busy_world(1);
  world->save_file(path);
  const Bytes before = read_bytes(path);
  step(*world, 5);
  // A write that fails part-way (a full disk, here the file size limit): the old file stays.
  // save_file truncated the file in place and left it cut short.
  {
    const hail::testing::FileSizeLimit limit(before.size() / 2);
    CHECK_THROWS_AS(world->save_file(path), FileError);
  }
  CHECK(read_bytes(path) == before);
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    CHECK(entry.path().filename() == "world.snap");  // no temporary left behind
  CHECK_THAT(hail::testing::message_of<FileError>([&] { world->save_file("/dev/full"); }),
             Catch::Contains("/dev/full") && Catch::Contains("a write failed"));
  world->save_file(path);
  CHECK(read_bytes(path) == saved(*world));
  std::filesystem::remove_all(dir);
}
