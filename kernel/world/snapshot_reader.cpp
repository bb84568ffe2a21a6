// World::restore: the snapshot layout of kernel/world/snapshot_format.h, read. Everything is
// parsed and checked into temporaries first (the header, the checksum, each section, the
// settings by World::validate, the handle tables, the cache's ranges, the touching keys), and
// only then moved into the World, by steps that cannot throw: a refused snapshot leaves the
// world as it was.

#include <cmath>

#include "hail/world.h"
#include "kernel/files/regular_file.h"
#include "kernel/mesh/mesh_set.h"
#include "kernel/world/snapshot_format.h"
#include "kernel/world/step_scratch.h"
#include "kernel/world/world_checks.h"
#include "kernel/world/world_services.h"

namespace hail {
namespace {

/// The snapshot version whose checksums and terrain hash start from kLegacyFnvOffsetBasis
/// (kernel/world/fnv1a.h); its layout is version 5's.
constexpr std::uint32_t kLegacyChecksumVersion = 4;
/// The last version with a warm_start bool among the settings, just before warm_start_factor
/// (versions 4 and 5); since then a factor of 0 is warm starting off.
constexpr std::uint32_t kLastWarmStartByteVersion = 5;
/// The last version without rolling_resistance among the settings (it reads as 0, none).
constexpr std::uint32_t kLastWithoutRollingVersion = 6;
/// The last version whose cache holds no rolling impulses (they start from zero).
constexpr std::uint32_t kLastWithoutRollingImpulsesVersion = 7;

/// What differs between the versions this hail reads.
struct Layout {
  std::uint64_t basis = kFnvOffsetBasis;  ///< of the checksum and the terrain hash
  bool warm_start_byte = false;           ///< the settings hold warm_start before warm_start_factor
  bool rolling_resistance = true;         ///< the settings hold rolling_resistance
  bool rolling_impulses = true;           ///< with rolling_resistance > 0, the cache holds rolling impulses
};

/// An InvalidArgument's message without its "hail: ", to be quoted inside another.
std::string reason(const InvalidArgument& e) {
  const std::string text = e.what();
  return text.rfind("hail: ", 0) == 0 ? text.substr(6) : text;
}

std::string hex(std::uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

/// Reads one setting as save wrote it (snapshot_writer.cpp), refusing bools other than 0 or 1
/// and enums out of the table's values; World::validate checks the values afterwards.
template <class T>
void read_setting(snapshot::Reader& r, T& field, const SettingSpec& spec) {
  const char* name = spec.name;
  if constexpr (std::is_same_v<T, bool>) {
    field = r.flag(name);
  } else if constexpr (std::is_enum_v<T>) {
    const auto v = r.value<std::uint32_t>(name);
    if (v >= setting_value_count(spec))
      r.refuse(std::string("setting ") + name + " is " + std::to_string(v) + ", not one of its values");
    field = static_cast<T>(v);
  } else if constexpr (std::is_same_v<T, std::size_t>) {
    field = static_cast<std::size_t>(r.value<std::uint64_t>(name));
  } else if constexpr (std::is_same_v<T, Vec3>) {
    const auto x = r.value<float>(name), y = r.value<float>(name), z = r.value<float>(name);
    field = Vec3(x, y, z);
  } else {
    field = r.value<T>(name);
  }
}

/// A sphere's every field, by the rules add_sphere and the control calls apply (a snapshot
/// with a movable sphere of inverse inertia 0, or of inverse mass 1e38, restored and turned the
/// kinetic energy NaN). Positions need only be finite: a step does not stop a sphere flying
/// past where add_sphere would place it, and its snapshot must restore.
void check_sphere(const snapshot::Reader& r, const SphereSoA& s, std::size_t k, const WorldSettings& settings) {
  const SphereId id = s.id_at(k);
  auto refuse = [&](const std::string& what) {
    r.refuse("sphere " + std::to_string(id.index) + "/" + std::to_string(id.generation) + " (slot " +
             std::to_string(k) + "): " + what);
  };
  auto checked = [&](auto&& check) {
    try {
      check();
    } catch (const InvalidArgument& e) {
      refuse(reason(e));
    }
  };
  const Vec3 position(s.px[k], s.py[k], s.pz[k]), velocity(s.vx[k], s.vy[k], s.vz[k]);
  const Vec3 spin(s.wx[k], s.wy[k], s.wz[k]);
  const Vec3 force(s.force_x[k], s.force_y[k], s.force_z[k]), torque(s.torque_x[k], s.torque_y[k], s.torque_z[k]);
  const float radius = s.radius[k], inv_mass = s.inv_mass[k], inv_inertia = s.inv_inertia[k];
  checked([&] {
    checks::require_finite(position, "position");
    checks::require_sphere_radius(radius);
    checks::require_sphere_speed(velocity);
    checks::require_sphere_spin(spin);
    checks::require_spin_allowed(settings.rotation, spin);
    checks::require_material(s.restitution[k], s.friction[k], "sphere");
    checks::require_finite(force, "force");
    checks::require_finite(torque, "torque");
  });
  if (inv_mass > 0.0f) {
    // add_sphere stores 1 / mass and 1 / (0.4 mass r^2) in float: allow their rounding.
    const double mass = 1.0 / double(inv_mass);
    if (!(mass >= kMinSphereMass * (1.0 - 1e-6) && mass <= kMaxSphereMass * (1.0 + 1e-6)))
      refuse("inverse mass " + checks::number(inv_mass) + " is a mass of " + checks::number(mass) +
             " kg, out of [kMinSphereMass, kMaxSphereMass]");
    const double expected = 1.0 / (0.4 * mass * double(radius) * radius);
    if (!(std::fabs(double(inv_inertia) - expected) <= 1e-5 * expected))
      refuse("inverse inertia " + checks::number(inv_inertia) +
             " is not a solid sphere's 1 / (0.4 m r^2) = " + checks::number(expected));
    checked([&] {
      const double longest = checks::longest_step(settings);
      checks::require_step_change(force, inv_mass, longest, checks::kSpeedLimit, "force");
      checks::require_step_change(torque, inv_inertia, longest, checks::kSpinLimit, "torque");
    });
  } else if (!(inv_mass == 0.0f && inv_inertia == 0.0f)) {
    refuse("inverse mass " + checks::number(inv_mass) + " and inverse inertia " + checks::number(inv_inertia) +
           ": an immovable sphere has 0 for both");
  }
  if (!(std::fabs(s.gravity_scale[k]) <= kMaxGravityScale)) refuse("gravity_scale is out of range");
  checked([&] { checks::require_gravity_scale_step(settings, s.gravity_scale[k]); });
  if (!(std::isfinite(s.sleep_timer[k]) && s.sleep_timer[k] >= 0.0f)) refuse("sleep_timer is not finite and >= 0");
  if ((s.flags[k] & ~kKnownSphereFlags) != 0) refuse("flags " + std::to_string(s.flags[k]) + " has unknown bits");
  if ((s.flags[k] & kSphereFlagKinematic) && s.inv_mass[k] != 0.0f) refuse("is kinematic with an inverse mass > 0");
}

/// Everything a snapshot holds, parsed and checked, ready to be moved into a World.
struct Parsed {
  WorldSettings settings;
  std::uint64_t steps_taken = 0, unchecked_from = 0;
  bool forces_pending = false;
  CollisionFilter ground_filter{};
  float terrain_restitution = 0.5f, terrain_friction = 0.5f;
  std::vector<Plane> planes;
  SphereSoA spheres;
  ContactImpulseCache cache;
  ContactEventTracker events;
};

void read_world(snapshot::Reader r, Parsed& p, const Terrain* terrain, const Layout& layout) {
  bool warm_start = true;
  snapshot::for_each_setting(p.settings, [&](auto& field, const SettingSpec& spec) {
    if (layout.warm_start_byte && static_cast<const void*>(&field) == &p.settings.warm_start_factor)
      warm_start = r.flag("warm_start");
    if (!layout.rolling_resistance && static_cast<const void*>(&field) == &p.settings.rolling_resistance) return;
    read_setting(r, field, spec);
  });
  // An older snapshot's warm starting off is the factor 0 that means it now.
  if (!warm_start) p.settings.warm_start_factor = 0.0f;
  p.steps_taken = r.value<std::uint64_t>("steps taken");
  p.unchecked_from = r.value<std::uint64_t>("unchecked_from");
  p.forces_pending = r.flag("forces pending");
  p.ground_filter.category = r.value<std::uint32_t>("ground filter category");
  p.ground_filter.mask = r.value<std::uint32_t>("ground filter mask");
  const bool had_terrain = r.flag("terrain attached");
  const auto saved_hash = r.value<std::uint64_t>("terrain hash");
  p.terrain_restitution = r.value<float>("terrain restitution");
  p.terrain_friction = r.value<float>("terrain friction");
  r.finish();
  if (had_terrain != (terrain != nullptr))
    r.refuse(had_terrain ? "it was saved with a terrain (content hash " + hex(saved_hash) +
                               ") and this World has none: set_terrain the same terrain first"
                         : "it was saved without a terrain and this World has one: restore into a World without one");
  if (!had_terrain && saved_hash != 0) r.refuse("a terrain hash without a terrain");
  if (terrain) {
    const std::uint64_t hash = snapshot::terrain_hash(*terrain, layout.basis);
    if (hash != saved_hash)
      r.refuse("wrong terrain: it was saved with terrain content hash " + hex(saved_hash) +
               ", this World's terrain has " + hex(hash) + " (attach the terrain it was saved with)");
  }
  checks::require_material(p.terrain_restitution, p.terrain_friction, "snapshot: terrain");
}

void read_planes(snapshot::Reader r, Parsed& p) {
  constexpr std::size_t kPlaneBytes = 6 * sizeof(float);
  p.planes.resize(r.count("plane count", kPlaneBytes));
  for (Plane& plane : p.planes) {
    for (float* v : {&plane.nx, &plane.ny, &plane.nz, &plane.offset, &plane.restitution, &plane.friction})
      *v = r.value<float>("a plane");
    if (!(std::isfinite(plane.nx) && std::isfinite(plane.ny) && std::isfinite(plane.nz) && std::isfinite(plane.offset)))
      r.refuse("a plane's normal or offset is not finite");
    checks::require_material(plane.restitution, plane.friction, "snapshot: plane");
  }
  r.finish();
}

void read_spheres(snapshot::Reader r, Parsed& p) {
  const std::size_t n = r.count("sphere count", 2 * sizeof(std::uint32_t));
  std::vector<SphereId> handles(n);
  const std::size_t indices = r.count("handle index count", sizeof(std::uint32_t));
  const std::size_t free_count = r.count("free index count", sizeof(std::uint32_t));
  for (SphereId& id : handles) {
    id.index = r.value<std::uint32_t>("a handle");
    id.generation = r.value<std::uint32_t>("a handle");
  }
  std::vector<std::uint32_t> generations(indices), free_indices(free_count);
  for (std::uint32_t& g : generations) g = r.value<std::uint32_t>("a generation");
  for (std::uint32_t& f : free_indices) f = r.value<std::uint32_t>("a free index");
  try {
    p.spheres.restore_handles(handles, generations, free_indices);
  } catch (const InvalidArgument& e) {
    r.refuse(reason(e));
  }
  const auto arrays = r.value<std::uint32_t>("sphere array count");
  if (arrays != SphereSoA::kArrayCount)
    r.refuse(std::to_string(arrays) + " sphere arrays, this hail has " + std::to_string(SphereSoA::kArrayCount));
  p.spheres.for_each_array([&](const char* name, auto& array) {
    const std::size_t length = r.value<std::uint8_t>("a sphere array's name length");
    const std::span<const std::byte> found = r.take(length, "a sphere array's name");
    if (length != std::strlen(name) || std::memcmp(found.data(), name, length) != 0)
      r.refuse(std::string("expected sphere array '") + name + "', found another");
    const auto element = r.value<std::uint8_t>("a sphere array's element size");
    if (element != sizeof array[0])
      r.refuse(std::string("sphere array '") + name + "' has elements of " + std::to_string(element) + " bytes, not " +
               std::to_string(sizeof array[0]));
    const std::span<const std::byte> values = r.take(n * sizeof array[0], name);
    if (n) std::memcpy(array.data(), values.data(), values.size());
  });
  r.finish();
  for (std::size_t k = 0; k < n; ++k) check_sphere(r, p.spheres, k, p.settings);
  if (p.unchecked_from > n) r.refuse("unchecked_from " + std::to_string(p.unchecked_from) + " is past the spheres");
}

void read_cache(snapshot::Reader r, Parsed& p, std::size_t spheres, const Layout& layout) {
  std::vector<ContactImpulseCache::Entry> entries(r.count("warm-start entry count", 20));
  for (ContactImpulseCache::Entry& e : entries) {
    e.partner = r.value<std::uint32_t>("a warm-start entry");
    for (float* v : {&e.normal_impulse, &e.tx, &e.ty, &e.tz}) *v = r.value<float>("a warm-start entry");
  }
  std::vector<ContactImpulseCache::Range> ranges(r.count("warm-start range count", 20));
  if (ranges.size() > spheres)
    r.refuse(std::to_string(ranges.size()) + " warm-start ranges for " + std::to_string(spheres) + " spheres");
  for (ContactImpulseCache::Range& g : ranges) {
    for (std::uint32_t* v : {&g.id, &g.static_begin, &g.static_end, &g.pair_begin, &g.pair_end})
      *v = r.value<std::uint32_t>("a warm-start range");
    if (!(g.static_begin <= g.static_end && g.static_end <= entries.size() && g.pair_begin <= g.pair_end &&
          g.pair_end <= entries.size()))
      r.refuse("a warm-start range lies outside its " + std::to_string(entries.size()) + " entries");
  }
  std::vector<float> rolling;
  if (layout.rolling_impulses && p.settings.rolling_resistance > 0.0f) {
    rolling.resize(r.count("rolling impulse count", sizeof(float)));
    if (!rolling.empty() && rolling.size() != 3 * entries.size())
      r.refuse(std::to_string(rolling.size()) + " rolling impulse floats for " + std::to_string(entries.size()) +
               " warm-start entries (3 each, or none)");
    for (float& v : rolling) {
      v = r.value<float>("a rolling impulse");
      if (!std::isfinite(v)) r.refuse("a rolling impulse is not finite");
    }
  }
  r.finish();
  p.cache.assign(std::move(entries), std::move(ranges), std::move(rolling));
}

void read_events(snapshot::Reader r, Parsed& p) {
  EventSettings settings;
  settings.touch = r.flag("touch events on");
  settings.hits = r.flag("hit events on");
  settings.hit_speed = r.value<float>("hit speed");
  if (!(std::isfinite(settings.hit_speed) && settings.hit_speed >= 0.0f)) r.refuse("hit speed is not finite and >= 0");
  std::vector<TouchKey> keys[2];
  for (std::vector<TouchKey>& list : keys) {
    list.resize(r.count("touching key count", 16));
    for (TouchKey& k : list) {
      k.key = r.value<std::uint64_t>("a touching key");
      k.generations = r.value<std::uint64_t>("a touching key");
    }
  }
  r.finish();
  if (!settings.touch && !(keys[0].empty() && keys[1].empty())) r.refuse("touching keys with touch events off");
  p.events.configure(settings);
  if (!p.events.restore_touching(keys[0], keys[1])) r.refuse("touching keys not in strictly increasing order");
}

/// Version 9's MESH section, present only for a world with meshes: this World must have the
/// same meshes, in the same order (they are not in the snapshot; their hashes are).
void read_meshes(snapshot::Reader& payload, const MeshSet* meshes) {
  const std::size_t have = meshes ? meshes->size() : 0;
  if (payload.left() == 0) {
    if (have > 0)
      payload.refuse("it was saved without meshes and this World has " + std::to_string(have) +
                     ": restore it into a World without meshes");
    return;
  }
  snapshot::Reader r = payload.section(snapshot::kMeshesTag);
  const std::size_t saved = r.count("mesh count", sizeof(std::uint64_t));
  if (saved != have)
    r.refuse("it was saved with " + std::to_string(saved) + " meshes and this World has " + std::to_string(have) +
             ": add_mesh the same meshes, in the same order, first");
  for (std::size_t m = 0; m < saved; ++m) {
    const auto hash = r.value<std::uint64_t>("a mesh hash");
    if (hash != snapshot::mesh_hash((*meshes)[m]))
      r.refuse("wrong mesh " + std::to_string(m) + ": it was saved with mesh content hash " + hex(hash) +
               ", this World's mesh has " + hex(snapshot::mesh_hash((*meshes)[m])) +
               " (add the mesh it was saved with, placed and with the material it had)");
  }
  r.finish();
}

}  // namespace

void World::restore(std::span<const std::byte> bytes) {
  snapshot::Reader header(bytes, "header");
  const std::span<const std::byte> magic = header.take(sizeof kSnapshotMagic, "the magic");
  if (std::memcmp(magic.data(), kSnapshotMagic, sizeof kSnapshotMagic) != 0)
    header.refuse("not a hail snapshot (its first bytes are not \"HAILSNAP\")");
  const auto version = header.value<std::uint32_t>("the format version");
  if (version > kSnapshotVersion)
    header.refuse("format version " + std::to_string(version) + " is newer than this hail reads (" +
                  std::to_string(kSnapshotVersion) + "): restore it with the hail that saved it, or a newer one");
  if (version < kLegacyChecksumVersion)
    header.refuse("format version " + std::to_string(version) + " is unknown (this hail reads " +
                  std::to_string(kLegacyChecksumVersion) + " to " + std::to_string(kSnapshotVersion) + ")");
  const Layout layout{.basis = version == kLegacyChecksumVersion ? kLegacyFnvOffsetBasis : kFnvOffsetBasis,
                      .warm_start_byte = version <= kLastWarmStartByteVersion,
                      .rolling_resistance = version > kLastWithoutRollingVersion,
                      .rolling_impulses = version > kLastWithoutRollingImpulsesVersion};
  if (header.value<std::uint32_t>("the reserved word") != 0) header.refuse("the reserved word is not 0");
  const auto length = header.value<std::uint64_t>("the payload length");
  const auto checksum = header.value<std::uint64_t>("the checksum");
  if (length != header.left())
    header.refuse(length > header.left() ? "truncated: the payload should be " + std::to_string(length) + " bytes, " +
                                               std::to_string(header.left()) + " present"
                                         : std::to_string(header.left() - length) + " bytes after the payload");
  const std::span<const std::byte> payload = bytes.subspan(snapshot::kHeaderBytes);
  if (snapshot::fnv1a(payload, layout.basis) != checksum)
    header.refuse("checksum mismatch (the bytes are corrupt): the header says " + hex(checksum) + ", the payload has " +
                  hex(snapshot::fnv1a(payload, layout.basis)));

  snapshot::Reader r(payload, "payload");
  Parsed p;
  read_world(r.section(snapshot::kWorldTag), p, terrain_.get(), layout);
  try {
    validate(p.settings);
  } catch (const InvalidArgument& e) {
    r.refuse("its settings: " + reason(e));
  }
  read_planes(r.section(snapshot::kPlanesTag), p);
  read_spheres(r.section(snapshot::kSpheresTag), p);
  read_cache(r.section(snapshot::kCacheTag), p, p.spheres.size(), layout);
  read_events(r.section(snapshot::kEventsTag), p);
  read_meshes(r, has_meshes() ? meshes_.get() : nullptr);
  r.finish();

  // The only step of the commit that may allocate, taken first: it changes no sphere.
  spheres_.reserve_like(p.spheres);

  // Commit: nothing below throws.
  const int threads = settings_.threads;
  settings_ = p.settings;
  settings_.threads = threads;  // this World keeps its own threads (or arena)
  spheres_.assign(p.spheres);   // in the buffers it had: spans from spheres() and handles() stay valid
  planes_.swap(p.planes);
  terrain_restitution_ = p.terrain_restitution, terrain_friction_ = p.terrain_friction;
  steps_taken_ = p.steps_taken;
  unchecked_from_ = static_cast<std::size_t>(p.unchecked_from);
  forces_pending_ = p.forces_pending;
  ground_filter_ = p.ground_filter;
  uses_stale_ = true;                  // which filters and gravity scales the step must honour: recounted next step
  gravity_scaled_ = filtered_ = true;  // until then, the general loops (exact either way)
  services_->sphere_queries.invalidate();
  std::swap(scratch_->contact_cache, p.cache);
  std::swap(services_->events, p.events);
  scratch_->contacts.clear();
  scratch_->impacts.clear();
  services_->sleep.clear_events();
  stats_ = {};
  times_ = {};
}

void World::restore_file(const std::string& path) {
  // A FIFO, a device or a folder is refused before it is opened (kernel/files/), and the file
  // is read to the size it had when opened.
  const std::vector<std::byte> bytes = files::read_regular_file(path, "World::restore_file: ", "a snapshot file");
  try {
    restore(bytes);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(std::string(e.what()) + " (file '" + path + "')");
  }
}

}  // namespace hail
