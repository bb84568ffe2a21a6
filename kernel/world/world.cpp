#include "hail/world.h"
#include "hail/settings_table.h"
#include "kernel/world/step_scratch.h"
#include "kernel/world/world_checks.h"
#include "kernel/world/world_services.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "kernel/broadphase/sphere_filters.h"
#include "kernel/dispatch/simd_dispatch.h"
#include "kernel/mesh/mesh_set.h"
#include "kernel/terrain/terrain_parts.h"
#include "kernel/world/fnv1a.h"

namespace hail {
using namespace checks;  // kernel/world/world_checks.h

namespace {

/// One setting against its range in the table (include/hail/settings_table.h).
template <class T>
void require_in_table_range(const T& value, const SettingSpec& spec) {
  if constexpr (std::is_same_v<T, bool>) {
    return;
  } else if constexpr (std::is_same_v<T, Vec3>) {
    require_finite(value, (std::string("WorldSettings::") + spec.name).c_str());
  } else if constexpr (std::is_enum_v<T>) {
    const auto index = static_cast<std::size_t>(value);
    require(index < setting_value_count(spec), [&] {
      return std::string("WorldSettings::") + spec.name + " must be one of " + spec.values + " (values 0.." +
             std::to_string(setting_value_count(spec) - 1) + "), got " + std::to_string(index);
    });
  } else {
    const double v = static_cast<double>(value);
    const bool finite_or_allowed = std::isfinite(v) || (spec.infinity && v > 0.0);
    const bool above = spec.min_open ? v > spec.min : v >= spec.min;
    const bool below =
        (spec.infinity && v > 0.0 && !std::isfinite(v)) || (spec.max_open ? v < spec.max : v <= spec.max);
    require(finite_or_allowed && above && below, [&] {
      return std::string("WorldSettings::") + spec.name + " must be " +
             (std::is_floating_point_v<T> ? "finite and " : "") + "in " + setting_range_text(spec) +
             (spec.infinity ? " or infinity" : "") + " (include/hail/settings_table.h), got " + number(v);
    });
  }
}

}  // namespace

void World::validate(const WorldSettings& s) {
  for_each_setting(s, [](const auto& value, const SettingSpec& spec) { require_in_table_range(value, spec); });
  // What a range cannot say:
  require(s.solver_tile_spheres == 0 || s.solver_tile_spheres >= kMinSolverTileSpheres, [&] {
    return "WorldSettings::solver_tile_spheres must be 0 (no tiles) or >= " + std::to_string(kMinSolverTileSpheres) +
           ", got " + std::to_string(s.solver_tile_spheres);
  });
  require(s.rolling_resistance == 0.0f || s.solver == Solver::Passes, [&] {
    return "WorldSettings::rolling_resistance = " + number(s.rolling_resistance) +
           " acts in the passes solver only; with solver soft_step it must be 0";
  });
  // One step from rest under gravity alone stays within the speed limit (the longest step is
  // what check_step lets through); a stronger gravity turned spheres NaN a few steps later.
  const double g = s.gravity.cast<double>().norm();
  require(g == 0.0 || g * longest_step(s) <= kMaxSphereSpeed, [&] {
    return "WorldSettings::gravity of |g| = " + number(s.gravity.cast<double>().norm()) +
           " m/s^2 over the longest step (max_substeps * max_substep = " + number(longest_step(s)) +
           " s) would exceed kMaxSphereSpeed = " + number(kMaxSphereSpeed) + " m/s: |g| may be at most " +
           number(kMaxSphereSpeed / longest_step(s)) + " m/s^2 (lower max_substeps or max_substep for more)";
  });
  // Chooses the SIMD path now if nothing has yet, so that a bad HAIL_SIMD is reported here, at
  // the API boundary, and not from inside a step's parallel loop.
  (void)active_simd_path();
}

std::int64_t substeps_needed(const WorldSettings& settings, float dt) {
  require(std::isfinite(dt) && dt > 0.0f, [&] { return "World::step dt must be finite and > 0, got " + number(dt); });
  // 0 is a pause (nothing moves); a positive step shorter than kMinStep divides by its length
  // (1/h, and the soft step by its substeps' squares) past float range: every sphere turned NaN.
  const double scaled = double(dt) * double(settings.time_scale);
  require(settings.time_scale == 0.0f || scaled >= double(kMinStep), [&] {
    return "World::step dt = " + number(dt) + " s at time_scale " + number(settings.time_scale) + " advances " +
           number(scaled) + " s, less than kMinStep = " + number(kMinStep) +
           " s (include/hail/world.h): too short to move anything; take longer steps or raise time_scale";
  });
  // float * float is exact in double, and the quotient cannot overflow a double.
  const double count = std::ceil(double(dt) * double(settings.time_scale) / double(settings.max_substep));
  if (count <= 0.0) return settings.time_scale > 0.0f ? 1 : 0;
  constexpr double kBeyondInt64 = 9.2e18;  // below 2^63, so the cast below is defined
  return count >= kBeyondInt64 ? std::numeric_limits<std::int64_t>::max() : static_cast<std::int64_t>(count);
}

std::int64_t check_step(const WorldSettings& settings, float dt) {
  const std::int64_t needed = substeps_needed(settings, dt);
  require(needed <= settings.max_substeps, [&] {
    return "World::step dt = " + number(dt) + " s at time_scale " + number(settings.time_scale) + " needs " +
           std::to_string(needed) +
           " substeps of at most WorldSettings::max_substep = " + number(settings.max_substep) +
           " s, more than WorldSettings::max_substeps = " + std::to_string(settings.max_substeps) +
           ": take shorter steps (several calls), lower time_scale, or raise max_substep or max_substeps";
  });
  return needed;
}

World::World(const WorldSettings& settings)
    : settings_(settings), scratch_(std::make_unique<StepScratch>()), services_(std::make_unique<WorldServices>()) {
  validate(settings);
  constexpr int all_hardware_threads = tbb::task_arena::automatic;  // a copy: avoids odr-using the member
  own_arena_ = std::make_unique<tbb::task_arena>(settings.threads == 0 ? all_hardware_threads : settings.threads);
  arena_ = own_arena_.get();
}

World::World(const WorldSettings& settings, tbb::task_arena& host_arena)
    : settings_(settings),
      arena_(&host_arena),
      scratch_(std::make_unique<StepScratch>()),
      services_(std::make_unique<WorldServices>()) {
  validate(settings);
}

World::~World() = default;

std::span<const Contact> World::last_contacts() const { return scratch_->contacts; }
std::span<const Impact> World::last_impacts() const { return scratch_->impacts; }

int World::thread_count() const { return arena_->max_concurrency(); }

SphereId World::add_sphere(const SphereDesc& d) {
  require_finite(d.position, "sphere position");
  require_finite(d.velocity, "sphere velocity");
  require_finite(d.angular_velocity, "sphere angular_velocity");
  require_sphere_radius(d.radius);
  require(!(d.is_static && d.is_kinematic),
          [] { return std::string("a sphere cannot be both is_static and is_kinematic"); });
  if (!d.is_static) {
    if (!d.is_kinematic) require_sphere_mass(d.mass);
    require_sphere_speed(d.velocity);
    require_sphere_spin(d.angular_velocity);
  }
  require_material(d.restitution, d.friction, "sphere");
  require_spin_allowed(settings_.rotation || d.is_static, d.angular_velocity);
  const bool dynamic = !d.is_static && !d.is_kinematic;
  const float inv_mass = dynamic ? 1.0f / d.mass : 0.0f;
  const float inv_inertia = dynamic ? inverse_inertia(d.mass, d.radius) : 0.0f;
  require_resolvable(d.position, d.radius);
  unchecked_from_ = std::min(unchecked_from_, spheres_.size());
  const Vec3 v = d.is_static ? Vec3::Zero() : d.velocity;
  const Vec3 w = d.is_static ? Vec3::Zero() : d.angular_velocity;
  const std::uint32_t flags = d.is_kinematic ? kSphereFlagKinematic : kSphereFlagNone;
  SphereRecord record{d.position.x(), d.position.y(), d.position.z(), v.x(),      v.y(),
                      v.z(),          w.x(),          w.y(),          w.z(),      d.radius,
                      inv_mass,       inv_inertia,    d.restitution,  d.friction, flags};
  record.filter = d.filter;
  if (d.filter != CollisionFilter{} || d.is_kinematic) filtered_ = true;
  services_->sphere_queries.invalidate();
  const SphereId id = spheres_.add(record);
  if (d.is_static) wake(static_cast<std::size_t>(spheres_.slot_of(id)));  // it pushes nothing: wake what it meets
  return id;
}

bool World::remove_sphere(SphereId id) {
  services_->sphere_queries.invalidate();
  // Its id index may be reused by the next sphere added: warm-start data must not carry over.
  scratch_->contact_cache.clear();
  // The last sphere moves into the hole: if it was still unchecked, so is the hole's slot now.
  const std::int64_t slot = spheres_.slot_of(id);
  if (slot >= 0 && spheres_.size() - 1 >= unchecked_from_)
    unchecked_from_ = std::min(unchecked_from_, static_cast<std::size_t>(slot));
  uses_stale_ = uses_stale_ || gravity_scaled_ || filtered_;  // it may have been the last one
  if (slot >= 0) wake(static_cast<std::size_t>(slot));        // its island, and what rested on it
  return spheres_.remove(id);
}

std::size_t World::add_plane(const PlaneDesc& d) {
  require_finite(d.normal, "plane normal");
  require(std::isfinite(d.offset), "plane offset must be finite, got " + number(d.offset));
  // An ordinary normal is divided by its norm, as always. The norm of (1e20, 0, 0) squares past
  // float range (it stored a zero normal) and that of (1e-20, 0, 0) underflows: those are
  // scaled by their largest component first, so the norm is of a vector in [1, sqrt 3].
  float length = d.normal.norm();
  Vec3 n = d.normal / length;
  if (!(std::isfinite(length) && length > 1e-18f)) {
    const float largest = d.normal.cwiseAbs().maxCoeff();
    const Vec3 scaled = largest > 0.0f ? Vec3(d.normal / largest) : Vec3::Zero();
    const float scaled_length = scaled.norm();
    length = largest * scaled_length;  // infinite past float range: the offset below is then ~0
    n = scaled / scaled_length;
  }
  require(length > 1e-6f, [&] { return "plane normal must not be (nearly) zero, got length " + number(length); });
  require_material(d.restitution, d.friction, "plane");
  const float offset = d.offset / length;
  require(std::isfinite(offset),
          [&] { return "plane offset / |normal| must be finite, got " + number(d.offset) + " / " + number(length); });
  planes_.push_back({n.x(), n.y(), n.z(), offset, d.restitution, d.friction});
  wake_all();
  return planes_.size() - 1;
}

namespace {
/// set_terrain's rule (kTerrainCellResolution): floats at the terrain's farthest coordinate
/// resolve its cells.
void require_terrain_resolvable(const Terrain& terrain) {
  const Heightmap& h = terrain.heightmap();
  const HeightmapExtent e = h.extent();
  const float farthest = std::max({std::fabs(e.min_x), std::fabs(e.max_x), std::fabs(e.min_z), std::fabs(e.max_z),
                                   std::fabs(h.min_height()), std::fabs(h.max_height())});
  const float cell = std::min(h.params().cell_x, h.params().cell_z);
  require(float_spacing(farthest) <= cell / kTerrainCellResolution, [&] {
    return "terrain reaches " + number(farthest) + " m from the origin, where floats are " +
           number(float_spacing(farthest)) + " m apart, more than its cell size " + number(cell) +
           " m / kTerrainCellResolution = " + number(cell / kTerrainCellResolution) +
           " m (include/hail/world.h); move it nearer the origin or use larger cells";
  });
}
}  // namespace

void World::set_terrain(std::shared_ptr<const Terrain> terrain, float restitution, float friction) {
  require_material(restitution, friction, "terrain");
  if (terrain) require_terrain_resolvable(*terrain);
  terrain_ = std::move(terrain);
  wake_all();
  unchecked_from_ = 0;              // every sphere may be inside the new terrain
  scratch_->contact_cache.clear();  // triangle features name another terrain's triangles now
  terrain_restitution_ = restitution;
  terrain_friction_ = friction;
}

std::size_t World::add_mesh(const TriangleMesh& mesh, const MeshTransform& transform, float restitution,
                            float friction) {
  require_material(restitution, friction, "mesh");
  if (!meshes_) meshes_ = std::make_unique<MeshSet>();
  const std::size_t index = meshes_->add(mesh, transform, restitution, friction);
  wake_all();
  return index;
}

bool World::has_meshes() const { return meshes_ && !meshes_->empty(); }
std::size_t World::mesh_count() const { return meshes_ ? meshes_->size() : 0; }
std::size_t World::mesh_memory_bytes() const { return meshes_ ? meshes_->memory_bytes() : 0; }
float World::mesh_penetration(const Vec3& centre, float radius) const {
  return has_meshes() ? meshes_->penetration(centre.x(), centre.y(), centre.z(), radius) : 0.0f;
}

void World::shift_origin(const Vec3& offset) {
  require_finite(offset, "World::shift_origin: offset");
  // Everything is checked (and the moved terrain built) before anything changes, so that a
  // refusal leaves the world as it was.
  for (std::size_t k = 0; k < planes_.size(); ++k) {
    const Plane& p = planes_[k];
    const float moved = p.offset - (p.nx * offset.x() + p.ny * offset.y() + p.nz * offset.z());
    require(std::isfinite(moved), [&] {
      return "World::shift_origin: plane " + std::to_string(k) + "'s offset would be " + number(moved) +
             " (not finite)";
    });
  }
  // add_sphere's placement rule (kSphereRadiusResolution) where each sphere lands: a shift of
  // 1e30 collapsed every sphere onto one float. A sphere already past the rule (it flew out)
  // does not block a shift that brings it no farther out.
  const SphereSoA& s = spheres_;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3 from(s.px[i], s.py[i], s.pz[i]);
    const Vec3 to(s.px[i] - offset.x(), s.py[i] - offset.y(), s.pz[i] - offset.z());
    const float farthest = to.cwiseAbs().maxCoeff();
    const bool placeable =
        std::isfinite(farthest) &&
        (float_spacing(farthest) <= s.radius[i] / kSphereRadiusResolution || farthest <= from.cwiseAbs().maxCoeff());
    require(placeable, [&] {
      return "World::shift_origin: sphere " + std::to_string(s.id_at(i).index) + " (radius " + number(s.radius[i]) +
             ") would move from (" + number(from.x()) + ", " + number(from.y()) + ", " + number(from.z()) + ") to (" +
             number(to.x()) + ", " + number(to.y()) + ", " + number(to.z()) + "), " + number(farthest) +
             " m out, where floats are " + number(float_spacing(farthest)) + " m apart, more than its radius / " +
             "kSphereRadiusResolution (include/hail/world.h): add_sphere would refuse it there";
    });
  }
  std::shared_ptr<const Terrain> moved_terrain;
  if (terrain_) {
    try {
      moved_terrain = std::make_shared<const Terrain>(terrain_->moved(-offset));
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(std::string("hail: World::shift_origin: the terrain cannot move there: ") + e.what());
    }
    require_terrain_resolvable(*moved_terrain);
  }
  std::unique_ptr<MeshSet> moved_meshes;
  if (has_meshes()) moved_meshes = std::make_unique<MeshSet>(meshes_->moved(-offset));

  wake_all();  // positions round: contacts that held may not
  for (Plane& p : planes_) p.offset -= p.nx * offset.x() + p.ny * offset.y() + p.nz * offset.z();
  SphereSoA& m = spheres_;
  for (std::size_t i = 0; i < m.size(); ++i) m.px[i] -= offset.x(), m.py[i] -= offset.y(), m.pz[i] -= offset.z();
  services_->sphere_queries.invalidate();
  for (Impact& i : scratch_->impacts) i.px -= offset.x(), i.py -= offset.y(), i.pz -= offset.z();
  if (moved_terrain) {
    // Warm starting keys terrain contacts by triangle index in BVH order (Contact::feature).
    // The moved terrain's BVH is built over moved boxes; rounding can make two centroids equal
    // that were not and so reorder triangles. Only then do the remembered impulses name other
    // triangles, and only then are they dropped (the next step starts its contacts from zero,
    // as after set_terrain).
    if (moved_terrain->bvh().primitive_order != terrain_->bvh().primitive_order) scratch_->contact_cache.clear();
    terrain_ = std::move(moved_terrain);
  }
  if (moved_meshes) {  // the same rule for the meshes' triangles (Contact::feature)
    if (!moved_meshes->same_order(*meshes_)) scratch_->contact_cache.clear();
    meshes_ = std::move(moved_meshes);
  }
}

std::size_t World::lift_out_of_terrain() {
  std::size_t lifted = 0;
  SphereSoA& s = spheres_;
  if (terrain_) {
    for (std::size_t i = unchecked_from_; i < s.size(); ++i) {
      if (!(s.inv_mass[i] > 0.0f)) continue;                           // a static sphere never moves
      if (filtered_ && !meets_ground(s, i, ground_filter_)) continue;  // it passes through the ground
      if (!terrain_->lift_above_surface(s.px[i], s.py[i], s.pz[i], s.radius[i])) continue;
      terrain_->push_out(s.px[i], s.py[i], s.pz[i], s.radius[i]);
      ++lifted;
    }
  }
  unchecked_from_ = spheres_.size();
  return lifted;
}

void World::reserve(std::size_t n) { spheres_.reserve(n); }

SphereState World::spheres() const {
  const std::size_t n = spheres_.size();
  const SphereSoA& s = spheres_;
  return {{s.px.data(), n}, {s.py.data(), n},     {s.pz.data(), n},      {s.vx.data(), n},
          {s.vy.data(), n}, {s.vz.data(), n},     {s.wx.data(), n},      {s.wy.data(), n},
          {s.wz.data(), n}, {s.radius.data(), n}, {s.inv_mass.data(), n}};
}

std::size_t World::require_slot(SphereId id) const {
  const std::int64_t slot = spheres_.slot_of(id);
  require(slot >= 0, [&] {
    return "sphere handle " + std::to_string(id.index) + "/" + std::to_string(id.generation) +
           " is stale or was never issued";
  });
  return static_cast<std::size_t>(slot);
}

Vec3 World::position(SphereId id) const {
  const std::size_t i = require_slot(id);
  return {spheres_.px[i], spheres_.py[i], spheres_.pz[i]};
}
Vec3 World::velocity(SphereId id) const {
  const std::size_t i = require_slot(id);
  return {spheres_.vx[i], spheres_.vy[i], spheres_.vz[i]};
}
Vec3 World::angular_velocity(SphereId id) const {
  const std::size_t i = require_slot(id);
  return {spheres_.wx[i], spheres_.wy[i], spheres_.wz[i]};
}

double World::kinetic_energy() const {
  const SphereSoA& s = spheres_;
  double energy = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.inv_mass[i] <= 0.0f) continue;
    const double m = 1.0 / s.inv_mass[i], inertia = 1.0 / s.inv_inertia[i];
    const double v2 = double(s.vx[i]) * s.vx[i] + double(s.vy[i]) * s.vy[i] + double(s.vz[i]) * s.vz[i];
    const double w2 = double(s.wx[i]) * s.wx[i] + double(s.wy[i]) * s.wy[i] + double(s.wz[i]) * s.wz[i];
    energy += 0.5 * m * v2 + 0.5 * inertia * w2;
  }
  return energy;
}

Eigen::Vector3d World::linear_momentum() const {
  const SphereSoA& s = spheres_;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.inv_mass[i] <= 0.0f) continue;
    const double m = 1.0 / s.inv_mass[i];
    p += m * Eigen::Vector3d(s.vx[i], s.vy[i], s.vz[i]);
  }
  return p;
}

std::size_t World::nan_count() const {
  const SphereSoA& s = spheres_;
  std::size_t count = 0;
  for (const AlignedArray<float>* a : {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz, &s.wx, &s.wy, &s.wz})
    for (std::size_t i = 0; i < s.size(); ++i) count += std::isfinite((*a)[i]) ? 0 : 1;
  return count;
}

std::uint64_t World::state_hash() const {
  const SphereSoA& s = spheres_;
  // Each float's bytes low byte first: x86-64's memory order, which hail's SIMD paths assume.
  std::uint64_t h = kFnvOffsetBasis;
  for (const AlignedArray<float>* a : {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz})
    h = fnv1a(std::as_bytes(std::span<const float>(a->data(), s.size())), h);
  return h;
}

}  // namespace hail
