#pragma once
// The checks World makes at its API boundary, shared by add_sphere and the calls that change a
// sphere later (kernel/world/world_control.cpp), so that a value is refused by the same rule,
// with the same message, however it arrives. Each throws InvalidArgument("hail: ...") naming
// the value; a check that passes builds no string and allocates nothing.

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>

#include "hail/errors.h"
#include "hail/vec3.h"
#include "hail/world.h"
#include "hail/world_settings.h"

namespace hail::checks {

/// %g: limits such as 1e-12 read as 0.000000 in std::to_string.
inline std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

inline std::string describe(const char* what, float value) { return std::string(what) + " " + number(value); }

/// The longest step, in time-scaled seconds, a World under `settings` takes: check_step
/// refuses any longer. A force, torque or gravity is bounded over it, so that one step cannot
/// take a sphere past the speed limits (include/hail/world.h).
inline double longest_step(const WorldSettings& settings) {
  return double(settings.max_substeps) * double(settings.max_substep);
}

/// Throws InvalidArgument("hail: " + message) unless ok. `message` is a string, or a function
/// that makes one: then it is made only on failure, so that a check that passes allocates
/// nothing (add_sphere within reserve() and the accessors must not; tests/allocation/).
template <class Message>
void require(bool ok, Message&& message) {
  if (ok) return;
  if constexpr (std::is_invocable_v<Message>)
    throw InvalidArgument("hail: " + std::string(message()));
  else
    throw InvalidArgument("hail: " + std::string(message));
}

void require_finite(const Vec3& v, const char* what);
void require_material(float restitution, float friction, const char* owner);

/// Distance from a (>= 0) to the next float up: how finely a float places a point at a.
inline float float_spacing(float a) { return std::nextafter(a, std::numeric_limits<float>::infinity()) - a; }

// A movable sphere's quantities, by the limits of include/hail/world.h.
void require_sphere_radius(float radius);
void require_sphere_mass(float mass);
void require_sphere_speed(const Vec3& velocity);
void require_sphere_spin(const Vec3& angular_velocity);
/// A non-zero spin is refused when the world has no rotation (spheres never spin there).
void require_spin_allowed(bool rotation, const Vec3& angular_velocity);
/// 1 / (0.4 m r^2), the solid sphere's inverse inertia; refused when it leaves float range.
float inverse_inertia(float mass, float radius);
/// kSphereRadiusResolution: floats at the position resolve the radius.
void require_resolvable(const Vec3& position, float radius);

/// A limit a step must not take a sphere past, as its messages name it.
struct StepLimit {
  float value;
  const char* name;      ///< "kMaxSphereSpeed"
  const char* quantity;  ///< "speed"
  const char* unit;      ///< "m/s"
};
inline constexpr StepLimit kSpeedLimit{kMaxSphereSpeed, "kMaxSphereSpeed", "speed", "m/s"};
inline constexpr StepLimit kSpinLimit{kMaxSphereSpin, "kMaxSphereSpin", "spin", "rad/s"};

/// A force (torque) `load` on a sphere of inverse mass (inertia) `inverse` changes its speed
/// (spin) by |load| * inverse * seconds over a step of `seconds`: refused when that exceeds
/// the limit over the longest step, so one step cannot take a sphere at rest past the speed
/// limits (apply_force(3e38) gave 2.5e35 m/s after a step, then NaN). `what` names the load.
void require_step_change(const Vec3& load, float inverse, double seconds, const StepLimit& limit, const char* what);
/// The same for a sphere's gravity, |WorldSettings::gravity * scale|, over the longest step.
void require_gravity_scale_step(const WorldSettings& settings, float scale);

}  // namespace hail::checks
