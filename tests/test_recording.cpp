// Recordings (include/hail/recording.h): frames read back are exactly the positions (and
// velocities) the world had when they were written, from bytes and from a file, whatever the
// world's re-sorting did to its slots; a truncated, corrupt, future-version or foreign file is
// refused naming the problem; the writer refuses a header or frame out of its domain.

#include <sys/stat.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "catch.h"
#include "file_faults.h"
#include "fuzz/recording_harness.h"
#include "hail/recording.h"
#include "hail/world.h"
#include "kernel/world/recording_format.h"

using namespace hail;

namespace {

using Bytes = std::vector<std::byte>;

/// A box of spheres falling on a plane, re-sorted every 4 steps (so slots move under the handles).
std::unique_ptr<World> falling_world() {
  auto world = std::make_unique<World>(WorldSettings{.threads = 1, .reorder_interval = 4});
  world->add_plane({.normal = {0, 1, 0}, .offset = 0});
  for (int k = 0; k < 150; ++k)
    world->add_sphere({.position = {float(k % 6) * 1.1f, 1.0f + float(k / 36) * 1.1f, float((k / 6) % 6) * 1.1f},
                       .velocity = {0.1f * float(k % 3), 0, 0},
                       .radius = 0.3f + 0.01f * float(k % 5)});
  return world;
}

Bytes bytes_of(const std::string& s) {
  Bytes b(s.size());
  std::memcpy(b.data(), s.data(), s.size());
  return b;
}

struct Recorded {
  Bytes bytes;
  RecordingHeader header;
  std::vector<RecordingFrame> frames;  // what the world held at each frame, read by handle
};

/// Records `steps` steps of falling_world every `every` steps; the frames are taken apart
/// from the writer, through World::position / velocity.
Recorded record(int steps, std::uint32_t every, bool velocities) {
  auto world = falling_world();
  Recorded r;
  std::ostringstream out;
  r.header = recording_header(*world, {}, "falling", 1.0f / 60.0f, every, velocities);
  RecordingWriter writer(out, r.header);
  auto expected_frame = [&](std::uint64_t step) {
    RecordingFrame f;
    f.step = step;
    for (const SphereId id : r.header.handles) {
      const Vec3 p = world->position(id), v = world->velocity(id);
      f.positions.insert(f.positions.end(), {p.x(), p.y(), p.z()});
      if (velocities) f.velocities.insert(f.velocities.end(), {v.x(), v.y(), v.z()});
    }
    return f;
  };
  for (int step = 0; step <= steps; ++step) {
    if (step > 0) world->step(1.0f / 60.0f);
    if (step % int(every) != 0) continue;
    r.frames.push_back(expected_frame(std::uint64_t(step)));
    writer.write_frame(recording_frame(*world, r.header, std::uint64_t(step)));
  }
  writer.finish();
  r.bytes = bytes_of(out.str());
  return r;
}

void expect_refused(const Bytes& bytes, const std::string& needle) {
  try {
    RecordingReader reader(bytes);
    for (std::size_t k = 0; k < reader.frame_count(); ++k) (void)reader.frame(k);
    FAIL("expected hail::InvalidArgument mentioning '" << needle << "'");
  } catch (const InvalidArgument& e) {
    INFO("message: " << e.what());
    CHECK(std::string(e.what()).find(needle) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("A recording reads back exactly the positions and velocities recorded", "[recording]") {
  for (const bool velocities : {false, true}) {
    const Recorded r = record(40, 5, velocities);
    const RecordingReader reader(r.bytes);
    CHECK(reader.header() == r.header);
    CHECK(reader.header().handles.size() == 150);
    CHECK(reader.header().radii[7] == 0.3f + 0.01f * 2.0f);  // sphere 7, as added
    REQUIRE(reader.frame_count() == 9);                      // steps 0, 5, ..., 40
    for (std::size_t k = 0; k < r.frames.size(); ++k) CHECK(reader.frame(k) == r.frames[k]);
    CHECK(reader.frame(8).step == 40);
    CHECK(reader.frame(8).positions != reader.frame(0).positions);  // the spheres did move
    CHECK(reader.frame_bytes() == recording::frame_bytes(150, velocities));
    CHECK_THROWS_AS(reader.frame(9), InvalidArgument);
  }
}

TEST_CASE("A recording file reads back frame by frame", "[recording]") {
  const Recorded r = record(12, 3, true);
  const auto path = std::filesystem::temp_directory_path() / "hail-test-recording.hailrec";
  {
    std::ofstream file(path, std::ios::binary);
    file.write(reinterpret_cast<const char*>(r.bytes.data()), std::streamsize(r.bytes.size()));
  }
  RecordingReader reader = RecordingReader::open_file(path.string());
  REQUIRE(reader.frame_count() == r.frames.size());
  for (std::size_t k = r.frames.size(); k-- > 0;) CHECK(reader.frame(k) == r.frames[k]);  // any order
  std::filesystem::resize_file(path, r.bytes.size() - 3);
  try {
    (void)RecordingReader::open_file(path.string());
    FAIL("a truncated file was read");
  } catch (const InvalidArgument& e) {
    CHECK(std::string(e.what()).find("truncated") != std::string::npos);
    CHECK(std::string(e.what()).find(path.string()) != std::string::npos);
  }
  std::filesystem::remove(path);
  CHECK_THROWS_AS(RecordingReader::open_file(path.string()), FileError);
}

TEST_CASE("A truncated recording is refused, naming truncation", "[recording]") {
  const Recorded r = record(10, 2, false);
  const std::size_t header_end = recording::kHeaderBytes + 16;
  for (const std::size_t keep : {std::size_t{0}, std::size_t{7}, std::size_t{31}, header_end, r.bytes.size() / 2,
                                 r.bytes.size() - recording::kEndBytes, r.bytes.size() - 1}) {
    INFO("kept " << keep << " of " << r.bytes.size() << " bytes");
    expect_refused(Bytes(r.bytes.begin(), r.bytes.begin() + std::ptrdiff_t(keep)), "truncated");
  }
  // A whole frame more than the end marker counts.
  Bytes longer(r.bytes.begin(), r.bytes.end() - recording::kEndBytes);
  const std::size_t frame = recording::frame_bytes(150, false);
  longer.insert(longer.end(), longer.end() - std::ptrdiff_t(frame), longer.end());
  longer.insert(longer.end(), r.bytes.end() - recording::kEndBytes, r.bytes.end());
  expect_refused(longer, "the end marker counts 6 frames");
}

TEST_CASE("A corrupt, foreign or future-version recording is refused, naming the problem", "[recording]") {
  const Recorded r = record(10, 5, true);
  auto changed = [&](std::size_t at, std::byte value) {
    Bytes b = r.bytes;
    b[at] = value;
    return b;
  };
  expect_refused(changed(0, std::byte{'X'}), "not a hail recording");
  Bytes future = r.bytes;
  const std::uint32_t next = kRecordingVersion + 1;
  std::memcpy(future.data() + 8, &next, sizeof next);
  expect_refused(future, "version 3 is newer than this hail reads (it reads version 2)");
  expect_refused(changed(12, std::byte{0x80}), "unknown flags");
  expect_refused(changed(recording::kHeaderBytes + 9, std::byte{'!'}), "the header's checksum does not match");
  const std::size_t frame1 = r.bytes.size() - recording::kEndBytes - recording::frame_bytes(150, true) + 100;
  expect_refused(changed(frame1, std::byte{0x5a}), "frame 2's checksum does not match");
  expect_refused(changed(r.bytes.size() - 12, std::byte{'x'}), "no end marker");
  // An empty header payload with its (right) checksum: refused at its first field (the fuzzer's
  // first find was this input reading from an empty buffer).
  Bytes empty_header(r.bytes.begin(), r.bytes.begin() + recording::kHeaderBytes);
  const std::uint64_t zero = 0, sum = fnv1a({});
  std::memcpy(empty_header.data() + recording::kPayloadBytesAt, &zero, sizeof zero);
  std::memcpy(empty_header.data() + recording::kChecksumAt, &sum, sizeof sum);
  empty_header.insert(empty_header.end(), r.bytes.end() - recording::kEndBytes, r.bytes.end());
  expect_refused(empty_header, "truncated: the scene name's length needs 8 bytes, 0 left");
}

TEST_CASE("The recording writer refuses a header or a frame out of its domain", "[recording]") {
  auto world = falling_world();
  std::ostringstream out;
  const RecordingHeader good = recording_header(*world, {}, "falling", 0.01f, 1, false);
  for (auto [field, needle] : {std::pair{0, "dt"}, std::pair{1, "every"}, std::pair{2, "radius"}}) {
    RecordingHeader bad = good;
    if (field == 0) bad.dt = 0.0f;
    if (field == 1) bad.every = 0;
    if (field == 2) bad.radii[3] = -1.0f;
    try {
      RecordingWriter writer(out, bad);
      FAIL("accepted a bad " << needle);
    } catch (const InvalidArgument& e) {
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
    }
  }
  RecordingWriter writer(out, good);
  RecordingFrame frame = recording_frame(*world, good, 0);
  frame.positions.pop_back();
  CHECK_THROWS_AS(writer.write_frame(frame), InvalidArgument);
  const SphereId gone = good.handles[5];
  world->remove_sphere(gone);
  CHECK_THROWS_WITH(recording_frame(*world, good, 1), Catch::Contains("was removed"));
}

namespace {

const std::filesystem::path kCorpus = std::filesystem::path(HAIL_SOURCE_DIR) / "tests/fuzz/corpus/recording";

/// A few spheres falling, recorded: small seeds that reach every field of the format.
Bytes seed(int spheres, int frames, bool velocities, bool with_name) {
  World world(WorldSettings{.threads = 1});
  for (int k = 0; k < spheres; ++k)
    world.add_sphere({.position = {float(k), 2.0f, 0.0f}, .radius = 0.25f + 0.1f * float(k)});
  std::ostringstream out;
  RecordingWriter writer(out, recording_header(world, {}, with_name ? "seed" : "", 0.02f, 2, velocities));
  for (int f = 0; f < frames; ++f) {
    if (f > 0) world.step(0.02f), world.step(0.02f);
    writer.write_frame(recording_frame(world, writer.header(), std::uint64_t(2 * f)));
  }
  writer.finish();
  return bytes_of(out.str());
}

std::vector<std::pair<std::string, Bytes>> corpus_seeds() {
  return {{"three-frames.hailrec", seed(3, 3, false, true)},
          {"velocities.hailrec", seed(2, 2, true, true)},
          {"no-frames.hailrec", seed(1, 0, false, false)}};
}

Bytes read_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  const std::string s((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  return bytes_of(s);
}

}  // namespace

TEST_CASE("Write the recording fuzzer's seed corpus", "[.write-recording-corpus]") {
  std::filesystem::create_directories(kCorpus);
  for (const auto& [name, bytes] : corpus_seeds()) {
    std::ofstream file(kCorpus / name, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
}

TEST_CASE("The recording fuzzer's seeds are what this hail writes, and each reads and writes back",
          "[recording][fuzz]") {
  for (const auto& [name, bytes] : corpus_seeds()) {
    INFO(name << " (after a format change: hail-tests \"[.write-recording-corpus]\" rewrites the seeds)");
    CHECK(read_bytes(kCorpus / name) == bytes);
    CHECK(fuzz::read_and_compare(bytes) == fuzz::RecordingOutcome::Read);
    CHECK(fuzz::with_right_checksums(bytes) == bytes);  // the harness finds the checksums where the writer put them
    Bytes broken = bytes;
    broken[broken.size() - 20] ^= std::byte{1};  // the last frame's checksum, or the header's (no frames)
    CHECK(fuzz::read_and_compare(broken) == fuzz::RecordingOutcome::Refused);
  }
}

TEST_CASE("A version 1 recording (the old checksum basis) still reads", "[recording]") {
  // tests/data/recording-v1-three-frames.hailrec is the fuzzer's three-frames seed as version 1
  // wrote it: the same layout, its checksums made from FNV-1a's offset basis a digit short.
  const std::string legacy = std::string(HAIL_SOURCE_DIR) + "/tests/data/recording-v1-three-frames.hailrec";
  const RecordingReader old = RecordingReader::open_file(legacy);
  const Bytes now = [] {
    for (const auto& [name, bytes] : corpus_seeds())
      if (name == "three-frames.hailrec") return bytes;
    return Bytes{};
  }();
  const RecordingReader current{Bytes(now)};
  REQUIRE(old.frame_count() == current.frame_count());
  CHECK(old.header().handles == current.header().handles);
  for (std::size_t k = 0; k < old.frame_count(); ++k) {
    CHECK(old.frame(k).positions == current.frame(k).positions);
    CHECK(old.frame(k).step == current.frame(k).step);
  }
}

TEST_CASE("A recording that is a FIFO, a device or a folder is refused before it is read", "[recording][files]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-test-recording-files";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  using hail::testing::message_of;
  // /dev/zero read gigabytes; a FIFO (hail-view --replay FIFO) hung.
  CHECK_THAT(message_of<FileError>([] { (void)RecordingReader::open_file("/dev/zero"); }), Catch::Contains("device"));
  CHECK_THAT(message_of<FileError>([&] { (void)RecordingReader::open_file(dir.string()); }),
             Catch::Contains("directory"));
  const std::string fifo = (dir / "fifo").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::optional<std::string> thrown = hail::testing::thrown_within<FileError>(
      std::chrono::seconds(10), [fifo] { (void)RecordingReader::open_file(fifo); });
  REQUIRE(thrown.has_value());
  CHECK_THAT(*thrown, Catch::Contains("FIFO"));
  std::filesystem::remove_all(dir);
}
