// World's calls that change a sphere after it was added (include/hail/world.h, "Driving spheres
// from a game"): each checks its value by add_sphere's rule for the same quantity
// (kernel/world/world_checks.h) before it changes anything.

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "hail/world.h"
#include "kernel/broadphase/sphere_filters.h"
#include "kernel/world/step_scratch.h"
#include "kernel/world/world_checks.h"
#include "kernel/world/world_services.h"

namespace hail {
using namespace checks;

namespace {

Vec3 velocity_at(const SphereSoA& s, std::size_t i) { return {s.vx[i], s.vy[i], s.vz[i]}; }
Vec3 spin_at(const SphereSoA& s, std::size_t i) { return {s.wx[i], s.wy[i], s.wz[i]}; }

/// A batch's handles and values must pair up.
void require_same_size(std::size_t handles, std::size_t values, const char* call) {
  require(handles == values, [&] {
    return std::string(call) + ": " + std::to_string(handles) + " handles but " + std::to_string(values) + " values";
  });
}

/// Runs `check` for entry k of a batch of `count`; in a batch of more than one, what it
/// refuses is named with the call and the entry's index.
template <class Check>
void check_entry(const char* call, std::size_t k, std::size_t count, Check&& check) {
  if (count == 1) return check();
  try {
    check();
  } catch (const InvalidArgument& e) {
    constexpr std::string_view prefix = "hail: ";
    std::string_view what = e.what();
    if (what.starts_with(prefix)) what.remove_prefix(prefix.size());
    throw InvalidArgument("hail: " + std::string(call) + " entry " + std::to_string(k) + ": " + std::string(what));
  }
}

}  // namespace

std::size_t World::require_movable(SphereId id, const char* what) const {
  const std::size_t i = require_slot(id);
  require(spheres_.inv_mass[i] > 0.0f || hail::is_kinematic(spheres_, i), [&] {
    return std::string(what) + ": sphere " + std::to_string(id.index) +
           " is static (no mass, never moves); it stays static";
  });
  return i;
}

std::size_t World::require_dynamic(SphereId id, const char* what) const {
  const std::size_t i = require_movable(id, what);
  require(!hail::is_kinematic(spheres_, i), [&] {
    return std::string(what) + ": sphere " + std::to_string(id.index) +
           " is kinematic (no mass; set_dynamic gives it one)";
  });
  return i;
}

bool World::is_kinematic(SphereId id) const { return hail::is_kinematic(spheres_, require_slot(id)); }

void World::set_kinematic(SphereId id) {
  const std::size_t i = require_slot(id);
  wake(i);  // its island, while it is still in one (or what rested on it)
  SphereSoA& s = spheres_;
  s.flags[i] |= kSphereFlagKinematic;
  s.inv_mass[i] = 0.0f;
  s.inv_inertia[i] = 0.0f;
  for (auto* a : {&s.force_x, &s.force_y, &s.force_z, &s.torque_x, &s.torque_y, &s.torque_z}) (*a)[i] = 0.0f;
  filtered_ = true;  // it passes through the ground (sphere_filters.h)
}

void World::set_dynamic(SphereId id, float mass) {
  const std::size_t i = require_slot(id);
  require_sphere_mass(mass);
  wake(i);
  SphereSoA& s = spheres_;
  const float inv_inertia = inverse_inertia(mass, s.radius[i]);
  if (hail::is_kinematic(s, i)) uses_stale_ = true;  // it may have been the last kinematic sphere
  s.flags[i] &= ~static_cast<std::uint32_t>(kSphereFlagKinematic);
  s.inv_mass[i] = 1.0f / mass;
  s.inv_inertia[i] = inv_inertia;
}

void World::move_kinematic(SphereId id, const Vec3& target, float dt) {
  const std::size_t i = require_slot(id);
  require(hail::is_kinematic(spheres_, i), [&] {
    return "World::move_kinematic: sphere " + std::to_string(id.index) + " is not kinematic (set_kinematic first)";
  });
  require(std::isfinite(dt) && dt > 0.0f,
          [&] { return "World::move_kinematic: dt must be finite and > 0, got " + number(dt); });
  require_finite(target, "kinematic target");
  require_resolvable(target, spheres_.radius[i]);
  const Vec3 here(spheres_.px[i], spheres_.py[i], spheres_.pz[i]);
  const Vec3 velocity = (target - here) / dt;
  require_finite(velocity, "kinematic velocity (target - position) / dt");
  require_sphere_speed(velocity);
  spheres_.vx[i] = velocity.x(), spheres_.vy[i] = velocity.y(), spheres_.vz[i] = velocity.z();
}

std::uint64_t World::user_data(SphereId id) const { return spheres_.user_data[require_slot(id)]; }
void World::set_user_data(SphereId id, std::uint64_t value) { spheres_.user_data[require_slot(id)] = value; }

CollisionFilter World::collision_filter(SphereId id) const {
  const std::size_t i = require_slot(id);
  return {spheres_.collision_category[i], spheres_.collision_mask[i]};
}

void World::set_collision_filter(SphereId id, CollisionFilter filter) {
  const std::size_t i = require_slot(id);
  spheres_.collision_category[i] = filter.category;
  spheres_.collision_mask[i] = filter.mask;
  wake(i);
  services_->sphere_queries.invalidate();
  if (filter != CollisionFilter{})
    filtered_ = true;
  else
    uses_stale_ = uses_stale_ || filtered_;
}

void World::set_ground_filter(CollisionFilter filter) {
  ground_filter_ = filter;
  wake_all();
  if (filter != CollisionFilter{})
    filtered_ = true;
  else
    uses_stale_ = uses_stale_ || filtered_;
}

void World::refresh_uses() {
  if (!uses_stale_) return;
  uses_stale_ = false;
  const SphereSoA& s = spheres_;
  bool scaled = false, filtered = ground_filter_ != CollisionFilter{};
  for (std::size_t i = 0; i < s.size(); ++i) {
    scaled = scaled || s.gravity_scale[i] != 1.0f;
    filtered = filtered || s.collision_category[i] != kDefaultCategory || s.collision_mask[i] != kAllCategories ||
               (s.flags[i] & kSphereFlagKinematic) != 0;
  }
  gravity_scaled_ = scaled;
  filtered_ = filtered;
}

void World::set_position(SphereId id, const Vec3& position) { set_positions({&id, 1}, {&position, 1}); }

void World::set_positions(std::span<const SphereId> handles, std::span<const Vec3> positions) {
  require_same_size(handles.size(), positions.size(), "World::set_positions");
  for (std::size_t k = 0; k < handles.size(); ++k) {
    check_entry("World::set_positions", k, handles.size(), [&] {
      const std::size_t i = require_slot(handles[k]);
      require_finite(positions[k], "sphere position");
      require_resolvable(positions[k], spheres_.radius[i]);
    });
  }
  ContactImpulseCache& cache = scratch_->contact_cache;
  for (std::size_t k = 0; k < handles.size(); ++k) {
    const std::size_t i = static_cast<std::size_t>(spheres_.slot_of(handles[k]));
    wake(i);  // where it was: an immovable one leaves what rested on it
    spheres_.px[i] = positions[k].x(), spheres_.py[i] = positions[k].y(), spheres_.pz[i] = positions[k].z();
    cache.forget(i);  // what it touched is not where it is now
  }
  if (!handles.empty()) cache.drop_forgotten(spheres_);
  services_->sphere_queries.invalidate();
}

void World::set_velocity(SphereId id, const Vec3& velocity) { set_velocities({&id, 1}, {&velocity, 1}); }

void World::set_velocities(std::span<const SphereId> handles, std::span<const Vec3> velocities) {
  require_same_size(handles.size(), velocities.size(), "World::set_velocities");
  for (std::size_t k = 0; k < handles.size(); ++k) {
    check_entry("World::set_velocities", k, handles.size(), [&] {
      require_movable(handles[k], "World::set_velocity");
      require_finite(velocities[k], "sphere velocity");
      require_sphere_speed(velocities[k]);
    });
  }
  for (std::size_t k = 0; k < handles.size(); ++k) {
    const std::size_t i = static_cast<std::size_t>(spheres_.slot_of(handles[k]));
    spheres_.vx[i] = velocities[k].x(), spheres_.vy[i] = velocities[k].y(), spheres_.vz[i] = velocities[k].z();
    wake(i);
  }
}

void World::set_angular_velocity(SphereId id, const Vec3& w) {
  const std::size_t i = require_movable(id, "World::set_angular_velocity");
  require_finite(w, "sphere angular_velocity");
  require_sphere_spin(w);
  require_spin_allowed(settings_.rotation, w);
  spheres_.wx[i] = w.x(), spheres_.wy[i] = w.y(), spheres_.wz[i] = w.z();
  wake(i);
}

void World::apply_impulse(SphereId id, const Vec3& impulse) { apply_impulses({&id, 1}, {&impulse, 1}); }

void World::apply_impulses(std::span<const SphereId> handles, std::span<const Vec3> impulses) {
  require_same_size(handles.size(), impulses.size(), "World::apply_impulses");
  for (std::size_t k = 0; k < handles.size(); ++k) {
    check_entry("World::apply_impulses", k, handles.size(), [&] {
      (void)require_slot(handles[k]);
      require_finite(impulses[k], "impulse");
    });
  }
  // Applied in order, each velocity kept first: a handle may come twice, so the speed limit is
  // checked on what the entries leave, and a refusal puts every velocity back as it was.
  SphereSoA& s = spheres_;
  std::vector<std::array<float, 3>>& undo = services_->impulse_undo;
  undo.resize(handles.size());
  for (std::size_t k = 0; k < handles.size(); ++k) {
    const std::size_t i = static_cast<std::size_t>(s.slot_of(handles[k]));
    undo[k] = {s.vx[i], s.vy[i], s.vz[i]};
    const Vec3 v = velocity_at(s, i) + impulses[k] * s.inv_mass[i];  // static: inv_mass 0, unchanged
    try {
      check_entry("World::apply_impulses", k, handles.size(), [&] { require_sphere_speed(v); });
    } catch (const InvalidArgument&) {
      for (std::size_t j = k; j-- > 0;) {
        const std::size_t at = static_cast<std::size_t>(s.slot_of(handles[j]));
        s.vx[at] = undo[j][0], s.vy[at] = undo[j][1], s.vz[at] = undo[j][2];
      }
      throw;
    }
    s.vx[i] = v.x(), s.vy[i] = v.y(), s.vz[i] = v.z();
    wake(i);
  }
}

void World::apply_impulse_at(SphereId id, const Vec3& impulse, const Vec3& world_point) {
  const std::size_t i = require_slot(id);
  require_finite(impulse, "impulse");
  require_finite(world_point, "impulse point");
  SphereSoA& s = spheres_;
  const Vec3 v = velocity_at(s, i) + impulse * s.inv_mass[i];
  require_sphere_speed(v);
  const bool spin = settings_.rotation && s.inv_mass[i] > 0.0f;
  Vec3 w = spin_at(s, i);
  if (spin) {
    const Vec3 r = world_point - Vec3(s.px[i], s.py[i], s.pz[i]);
    const Vec3 moment(r.y() * impulse.z() - r.z() * impulse.y(), r.z() * impulse.x() - r.x() * impulse.z(),
                      r.x() * impulse.y() - r.y() * impulse.x());  // r x impulse
    w += moment * s.inv_inertia[i];
    require_finite(w, "sphere angular_velocity after the impulse");
    require_sphere_spin(w);
  }
  s.vx[i] = v.x(), s.vy[i] = v.y(), s.vz[i] = v.z();
  s.wx[i] = w.x(), s.wy[i] = w.y(), s.wz[i] = w.z();
  wake(i);
}

void World::apply_force(SphereId id, const Vec3& force) {
  const std::size_t i = require_slot(id);
  require_finite(force, "force");
  SphereSoA& s = spheres_;
  const Vec3 sum = Vec3(s.force_x[i], s.force_y[i], s.force_z[i]) + force;
  require_finite(sum, "accumulated force");
  require_step_change(sum, s.inv_mass[i], longest_step(settings_), kSpeedLimit, "accumulated force");
  if (!(s.inv_mass[i] > 0.0f)) return;  // static: a push on the immovable
  wake(i);
  s.force_x[i] = sum.x(), s.force_y[i] = sum.y(), s.force_z[i] = sum.z();
  forces_pending_ = true;
}

void World::apply_torque(SphereId id, const Vec3& torque) {
  const std::size_t i = require_slot(id);
  require_finite(torque, "torque");
  require(settings_.rotation || torque == Vec3::Zero(), [&] {
    return "torque must be zero when WorldSettings::rotation is false (spheres never spin), got (" +
           number(torque.x()) + ", " + number(torque.y()) + ", " + number(torque.z()) + ")";
  });
  SphereSoA& s = spheres_;
  const Vec3 sum = Vec3(s.torque_x[i], s.torque_y[i], s.torque_z[i]) + torque;
  require_finite(sum, "accumulated torque");
  require_step_change(sum, s.inv_inertia[i], longest_step(settings_), kSpinLimit, "accumulated torque");
  if (!(s.inv_mass[i] > 0.0f)) return;  // static: ignored
  wake(i);
  s.torque_x[i] = sum.x(), s.torque_y[i] = sum.y(), s.torque_z[i] = sum.z();
  forces_pending_ = true;
}

void World::clear_forces() {
  if (!forces_pending_) return;
  SphereSoA& s = spheres_;
  for (auto* a : {&s.force_x, &s.force_y, &s.force_z, &s.torque_x, &s.torque_y, &s.torque_z})
    std::fill(a->data(), a->data() + s.size(), 0.0f);
  forces_pending_ = false;
}

void World::set_restitution(SphereId id, float restitution) {
  const std::size_t i = require_slot(id);
  require_material(restitution, spheres_.friction[i], "sphere");
  spheres_.restitution[i] = restitution;
  wake(i);
}

void World::set_friction(SphereId id, float friction) {
  const std::size_t i = require_slot(id);
  require_material(spheres_.restitution[i], friction, "sphere");
  spheres_.friction[i] = friction;
  wake(i);
}

void World::set_mass(SphereId id, float mass) {
  const std::size_t i = require_dynamic(id, "World::set_mass");
  require_sphere_mass(mass);
  const float inv_inertia = inverse_inertia(mass, spheres_.radius[i]);
  spheres_.inv_mass[i] = 1.0f / mass;
  spheres_.inv_inertia[i] = inv_inertia;
  wake(i);
}

void World::set_radius(SphereId id, float radius) {
  const std::size_t i = require_slot(id);
  require_sphere_radius(radius);
  const bool movable = spheres_.inv_mass[i] > 0.0f;
  const float inv_inertia = movable ? inverse_inertia(1.0f / spheres_.inv_mass[i], radius) : 0.0f;
  require_resolvable({spheres_.px[i], spheres_.py[i], spheres_.pz[i]}, radius);
  wake(i);  // at its old size: an immovable one that shrinks leaves what rested on it
  spheres_.radius[i] = radius;
  spheres_.inv_inertia[i] = inv_inertia;
  services_->sphere_queries.invalidate();
}

void World::set_gravity_scale(SphereId id, float scale) {
  const std::size_t i = require_slot(id);
  require(std::isfinite(scale) && std::fabs(scale) <= kMaxGravityScale, [&] {
    return "sphere gravity scale must be finite with |scale| <= kMaxGravityScale = " + number(kMaxGravityScale) +
           " (include/hail/world.h), got " + number(scale);
  });
  require_gravity_scale_step(settings_, scale);
  spheres_.gravity_scale[i] = scale;
  wake(i);
  if (scale != 1.0f)
    gravity_scaled_ = true;
  else
    uses_stale_ = uses_stale_ || gravity_scaled_;
}

}  // namespace hail
