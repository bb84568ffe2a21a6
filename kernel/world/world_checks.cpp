#include "kernel/world/world_checks.h"

#include "hail/world.h"

namespace hail::checks {

void require_finite(const Vec3& v, const char* what) {
  require(std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()), [&] {
    return std::string(what) + " must be finite, got (" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) +
           ")";
  });
}

void require_material(float restitution, float friction, const char* owner) {
  require(std::isfinite(restitution) && restitution >= 0.0f && restitution <= 1.0f,
          [&] { return std::string(owner) + " restitution must be in [0, 1], got " + number(restitution); });
  require(std::isfinite(friction) && friction >= 0.0f,
          [&] { return std::string(owner) + " friction must be finite and >= 0, got " + number(friction); });
}

void require_sphere_radius(float radius) {
  require(std::isfinite(radius) && radius > 0.0f,
          [&] { return "sphere radius must be finite and > 0, got " + number(radius); });
  require(radius >= kMinSphereRadius && radius <= kMaxSphereRadius, [&] {
    return "sphere radius must be in [kMinSphereRadius, kMaxSphereRadius] = [" + number(kMinSphereRadius) + ", " +
           number(kMaxSphereRadius) + "] m (include/hail/world.h), got " + number(radius);
  });
}

void require_sphere_mass(float mass) {
  require(std::isfinite(mass) && mass > 0.0f,
          [&] { return "sphere mass must be finite and > 0 (or the sphere marked is_static), got " + number(mass); });
  require(mass >= kMinSphereMass && mass <= kMaxSphereMass, [&] {
    return "sphere mass must be in [kMinSphereMass, kMaxSphereMass] = [" + number(kMinSphereMass) + ", " +
           number(kMaxSphereMass) + "] kg (include/hail/world.h), got " + number(mass);
  });
}

// Compared squared in double: the float norm of a finite vector can overflow. NaN fails too.
void require_sphere_speed(const Vec3& velocity) {
  require(velocity.cast<double>().squaredNorm() <= double(kMaxSphereSpeed) * kMaxSphereSpeed, [&] {
    return "sphere velocity must be at most kMaxSphereSpeed = " + number(kMaxSphereSpeed) +
           " m/s, got |v| = " + number(velocity.cast<double>().norm());
  });
}

void require_sphere_spin(const Vec3& angular_velocity) {
  require(angular_velocity.cast<double>().squaredNorm() <= double(kMaxSphereSpin) * kMaxSphereSpin, [&] {
    return "sphere angular_velocity must be at most kMaxSphereSpin = " + number(kMaxSphereSpin) +
           " rad/s, got |w| = " + number(angular_velocity.cast<double>().norm());
  });
}

void require_spin_allowed(bool rotation, const Vec3& w) {
  const bool spins = !(w.x() == 0.0f && w.y() == 0.0f && w.z() == 0.0f);
  require(rotation || !spins, [&] {
    return "sphere angular_velocity must be zero when WorldSettings::rotation is false (spheres never spin), got (" +
           number(w.x()) + ", " + number(w.y()) + ", " + number(w.z()) + ")";
  });
}

float inverse_inertia(float mass, float radius) {
  const float inertia = 0.4f * mass * radius * radius;  // solid sphere, 2/5 m r^2
  const float inv_inertia = 1.0f / inertia;
  require(std::isfinite(1.0f / mass) && std::isfinite(inv_inertia), [&] {
    return "sphere mass " + number(mass) + " and radius " + number(radius) + " give an inertia outside float range";
  });
  return inv_inertia;
}

void require_resolvable(const Vec3& position, float radius) {
  const float farthest = position.cwiseAbs().maxCoeff();
  require(float_spacing(farthest) <= radius / kSphereRadiusResolution, [&] {
    return "sphere position " + number(farthest) + " m from the origin cannot resolve radius " + number(radius) +
           " m: floats there are " + number(float_spacing(farthest)) + " m apart, more than radius / " +
           "kSphereRadiusResolution = " + number(radius / kSphereRadiusResolution) +
           " m (include/hail/world.h); move the scene nearer the origin or use larger spheres";
  });
}

void require_step_change(const Vec3& load, float inverse, double seconds, const StepLimit& limit, const char* what) {
  const double size = load.cast<double>().norm();
  const double change = size == 0.0 || inverse == 0.0f ? 0.0 : size * double(inverse) * seconds;  // 0 * inf is 0 here
  require(change <= double(limit.value), [&] {
    return std::string(what) + " of " + number(load.cast<double>().norm()) + " would change the sphere's " +
           limit.quantity + " by " + number(change) + " " + limit.unit +
           " over the longest step (max_substeps * max_substep = " + number(seconds) + " s), more than " + limit.name +
           " = " + number(limit.value) + " " + limit.unit +
           " (include/hail/world.h): apply a smaller one, or an impulse";
  });
}

void require_gravity_scale_step(const WorldSettings& settings, float scale) {
  const double gravity = settings.gravity.cast<double>().norm() * std::fabs(double(scale));
  require(gravity == 0.0 || gravity * longest_step(settings) <= double(kMaxSphereSpeed), [&] {
    return "sphere gravity scale " + number(scale) + " makes its gravity " + number(gravity) +
           " m/s^2, which over the longest step (max_substeps * max_substep = " + number(longest_step(settings)) +
           " s) would exceed kMaxSphereSpeed = " + number(kMaxSphereSpeed) + " m/s (include/hail/world.h)";
  });
}

}  // namespace hail::checks
