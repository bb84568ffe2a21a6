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

namespace hail::checks {

/// %g: limits such as 1e-12 read as 0.000000 in std::to_string.
inline std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

inline std::string describe(const char* what, float value) { return std::string(what) + " = " + std::to_string(value); }

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

}  // namespace hail::checks
