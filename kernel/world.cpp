#include "kernel/world.h"

#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "kernel/simd_dispatch.h"

namespace hail {
namespace {

std::string describe(const char* what, float value) { return std::string(what) + " = " + std::to_string(value); }

/// Throws InvalidArgument("hail: " + message) unless ok. `message` is a string, or a function
/// that makes one: then it is made only on failure, so that a check that passes allocates
/// nothing (add_sphere within reserve() and the accessors must not; tests/allocation/).
template <class Message>
void require(bool ok, Message&& message) {
  if (ok) return;
  if constexpr (std::is_invocable_v<Message>) throw InvalidArgument("hail: " + std::string(message()));
  else throw InvalidArgument("hail: " + std::string(message));
}

void require_finite(const Vec3& v, const char* what) {
  require(std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()), [&] {
    return std::string(what) + " must be finite, got (" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " +
           std::to_string(v.z()) + ")";
  });
}

void require_material(float restitution, float friction, const char* owner) {
  require(std::isfinite(restitution) && restitution >= 0.0f && restitution <= 1.0f,
          [&] { return std::string(owner) + " restitution must be in [0, 1], got " + std::to_string(restitution); });
  require(std::isfinite(friction) && friction >= 0.0f,
          [&] { return std::string(owner) + " friction must be finite and >= 0, got " + std::to_string(friction); });
}

}  // namespace

void World::validate(const WorldSettings& s) {
  require_finite(s.gravity, "WorldSettings::gravity");
  require(std::isfinite(s.time_scale) && s.time_scale >= 0.0f,
          "WorldSettings::time_scale must be finite and >= 0, got " + std::to_string(s.time_scale));
  require(std::isfinite(s.max_substep) && s.max_substep > 0.0f,
          describe("WorldSettings::max_substep must be finite and > 0, got", s.max_substep));
  require(s.threads >= 0, "WorldSettings::threads must be >= 0 (0 = all hardware threads), got " + std::to_string(s.threads));
  require(s.collision_iterations >= 0, "WorldSettings::collision_iterations must be >= 0");
  require(s.resting_iterations >= 0, "WorldSettings::resting_iterations must be >= 0");
  require(s.depenetration_iterations >= 0, "WorldSettings::depenetration_iterations must be >= 0");
  require(s.solver_tile_spheres == 0 || s.solver_tile_spheres >= kMinSolverTileSpheres, [&] {
    return "WorldSettings::solver_tile_spheres must be 0 (no tiles) or >= " + std::to_string(kMinSolverTileSpheres) +
           ", got " + std::to_string(s.solver_tile_spheres);
  });
  require(std::isfinite(s.depenetration.fraction) && s.depenetration.fraction >= 0.0f && s.depenetration.fraction <= 1.0f,
          describe("WorldSettings::depenetration.fraction must be in [0, 1], got", s.depenetration.fraction));
  require(std::isfinite(s.depenetration.slop_fraction) && s.depenetration.slop_fraction >= 0.0f,
          describe("WorldSettings::depenetration.slop_fraction must be >= 0, got", s.depenetration.slop_fraction));
  require(std::isfinite(s.restitution_threshold) && s.restitution_threshold >= 0.0f,
          describe("WorldSettings::restitution_threshold must be >= 0, got", s.restitution_threshold));
  require(std::isfinite(s.warm_start_factor) && s.warm_start_factor >= 0.0f && s.warm_start_factor <= 1.0f,
          describe("WorldSettings::warm_start_factor must be in [0, 1], got", s.warm_start_factor));
  require(s.reorder_interval >= 0, "WorldSettings::reorder_interval must be >= 0 (0 = never), got " +
                                       std::to_string(s.reorder_interval));
  require(std::isfinite(s.fast_travel_fraction) && s.fast_travel_fraction > 0.0f && s.fast_travel_fraction <= 1.0f,
          describe("WorldSettings::fast_travel_fraction must be in (0, 1], got", s.fast_travel_fraction));
  require(HAIL_WITH_CONTINUOUS_COLLISION || !s.continuous_collision,
          "WorldSettings::continuous_collision is true, but this hail was built without it "
          "(HAIL_WITH_CONTINUOUS_COLLISION=OFF)");
  require(HAIL_WITH_ROTATION || !s.rotation,
          "WorldSettings::rotation is true, but this hail was built without it (HAIL_WITH_ROTATION=OFF)");
  require(s.shock_mass_ratio >= 1.0f,  // false for NaN
          describe("WorldSettings::shock_mass_ratio must be >= 1 (infinity: never), got", s.shock_mass_ratio));
  require(s.max_sweep_events >= 1, "WorldSettings::max_sweep_events must be >= 1, got " + std::to_string(s.max_sweep_events));
  require(std::isfinite(s.speculative_radii) && s.speculative_radii >= 0.0f,
          describe("WorldSettings::speculative_radii must be >= 0, got", s.speculative_radii));
  require(std::isfinite(s.pair_margin_travel) && s.pair_margin_travel >= 0.0f,
          describe("WorldSettings::pair_margin_travel must be >= 0, got", s.pair_margin_travel));
  // Chooses the SIMD path now if nothing has yet, so that a bad HAIL_SIMD is reported here, at
  // the API boundary, and not from inside a step's parallel loop.
  (void)active_simd_path();
}

World::World(const WorldSettings& settings) : settings_(settings) {
  validate(settings);
  constexpr int all_hardware_threads = tbb::task_arena::automatic;  // a copy: avoids odr-using the member
  own_arena_ = std::make_unique<tbb::task_arena>(settings.threads == 0 ? all_hardware_threads : settings.threads);
  arena_ = own_arena_.get();
}

World::World(const WorldSettings& settings, tbb::task_arena& host_arena) : settings_(settings), arena_(&host_arena) {
  validate(settings);
}

World::~World() = default;

int World::thread_count() const { return arena_->max_concurrency(); }

SphereId World::add_sphere(const SphereDesc& d) {
  require_finite(d.position, "sphere position");
  require_finite(d.velocity, "sphere velocity");
  require_finite(d.angular_velocity, "sphere angular_velocity");
  require(std::isfinite(d.radius) && d.radius > 0.0f,
          [&] { return "sphere radius must be finite and > 0, got " + std::to_string(d.radius); });
  if (!d.is_static)
    require(std::isfinite(d.mass) && d.mass > 0.0f, [&] {
      return "sphere mass must be finite and > 0 (or the sphere marked is_static), got " + std::to_string(d.mass);
    });
  require_material(d.restitution, d.friction, "sphere");
  const bool spins = !(d.angular_velocity.x() == 0.0f && d.angular_velocity.y() == 0.0f && d.angular_velocity.z() == 0.0f);
  require(settings_.rotation || d.is_static || !spins, [&] {
    return "sphere angular_velocity must be zero when WorldSettings::rotation is false (spheres never spin), got (" +
           std::to_string(d.angular_velocity.x()) + ", " + std::to_string(d.angular_velocity.y()) + ", " +
           std::to_string(d.angular_velocity.z()) + ")";
  });
  const float inv_mass = d.is_static ? 0.0f : 1.0f / d.mass;
  const float inertia = 0.4f * d.mass * d.radius * d.radius;  // solid sphere, 2/5 m r^2
  const float inv_inertia = d.is_static ? 0.0f : 1.0f / inertia;
  require(std::isfinite(inv_mass) && std::isfinite(inv_inertia), [&] {
    return "sphere mass " + std::to_string(d.mass) + " and radius " + std::to_string(d.radius) +
           " give an inertia outside float range";
  });
  const Vec3 v = d.is_static ? Vec3::Zero() : d.velocity;
  const Vec3 w = d.is_static ? Vec3::Zero() : d.angular_velocity;
  return spheres_.add({d.position.x(), d.position.y(), d.position.z(), v.x(), v.y(), v.z(), w.x(), w.y(), w.z(),
                       d.radius, inv_mass, inv_inertia, d.restitution, d.friction, kSphereFlagNone});
}

bool World::remove_sphere(SphereId id) {
  // Its id index may be reused by the next sphere added: warm-start data must not carry over.
  contact_cache_.clear();
  return spheres_.remove(id);
}

std::size_t World::add_plane(const PlaneDesc& d) {
  require_finite(d.normal, "plane normal");
  require(std::isfinite(d.offset), "plane offset must be finite, got " + std::to_string(d.offset));
  const float length = d.normal.norm();
  require(length > 1e-6f, "plane normal must not be zero, got length " + std::to_string(length));
  require_material(d.restitution, d.friction, "plane");
  const Vec3 n = d.normal / length;
  planes_.push_back({n.x(), n.y(), n.z(), d.offset / length, d.restitution, d.friction});
  return planes_.size() - 1;
}

#if HAIL_WITH_TERRAIN
void World::set_terrain(std::shared_ptr<const Terrain> terrain, float restitution, float friction) {
  require_material(restitution, friction, "terrain");
  terrain_ = std::move(terrain);
  contact_cache_.clear();  // triangle features name another terrain's triangles now
  terrain_restitution_ = restitution;
  terrain_friction_ = friction;
}
#endif

void World::reserve(std::size_t n) { spheres_.reserve(n); }

SphereState World::spheres() const {
  const std::size_t n = spheres_.size();
  const SphereSoA& s = spheres_;
  return {{s.px.data(), n}, {s.py.data(), n}, {s.pz.data(), n}, {s.vx.data(), n}, {s.vy.data(), n},
          {s.vz.data(), n}, {s.wx.data(), n}, {s.wy.data(), n}, {s.wz.data(), n}, {s.radius.data(), n},
          {s.inv_mass.data(), n}};
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
  std::uint64_t h = 1469598103934665603ull;
  for (const AlignedArray<float>* a : {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz}) {
    for (std::size_t i = 0; i < s.size(); ++i) {
      std::uint32_t bits;
      std::memcpy(&bits, &(*a)[i], sizeof bits);
      for (int byte = 0; byte < 4; ++byte) {
        h ^= (bits >> (8 * byte)) & 0xFFu;
        h *= 1099511628211ull;
      }
    }
  }
  return h;
}

}  // namespace hail
