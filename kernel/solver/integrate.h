#pragma once
// Integration of sphere state over one (time-scaled) step.
//
// Velocities get gravity first (predict), the solver then corrects them, and positions move
// last with the corrected velocity. Against static planes the position update is exact in
// time: a sphere that reaches a plane during the step is advanced to the moment of impact,
// bounced there (restitution and friction), and moved on for the rest of the step, so bounce
// heights carry no error from where inside a step the impact fell.

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "hail/sphere_soa.h"
#include "hail/world_settings.h"
#include "kernel/solver/step_modes.h"
#include "kernel/terrain/plane_contacts.h"

namespace hail {

struct IntegrationParams {
  /// The substep's modes: the integrator, rotation (plane impacts' friction turns spheres; off:
  /// linear only), gravity scales, forces and the ground filter (spheres whose filter rejects
  /// modes.ground pass through the planes).
  StepModes modes{};
  float gravity[3] = {0.0f, -9.81f, 0.0f};
  float dt = 0.0f;                     ///< time-scaled step
  float restitution_threshold = 0.0f;  ///< closing speeds at or below this do not bounce
  /// Integrator::UniformAcceleration: each sphere's velocity at the start of the (sub)step,
  /// before forces and gravity (StepScratch::start_vx..vz); unused (null) otherwise.
  const float* start_vx = nullptr;
  const float* start_vy = nullptr;
  const float* start_vz = nullptr;
};

/// The acceleration the uniform-acceleration integrator moves sphere i with over the step,
/// given its solved end velocity `v_end`: the mean acceleration actually applied,
/// (v_end - v_start) / dt, brought into the ball whose diameter runs from 0 to the free-flight
/// acceleration f (gravity times the sphere's scale, plus F inv_mass): its share along f
/// clamped to [0, 1], and its part across f at most |f| sqrt(share (1 - share)) long. That
/// ball holds exactly the accelerations f gives a sphere on a frictionless support, wholly or
/// partly loaded (on a slope of normal n, f minus its part along n lies on the sphere; Thales):
/// in free flight f (the exact parabola), on a slope its tangential part (the exact slide or
/// roll), at rest on flat ground zero (it stays where it rests: reconstructing the start velocity
/// as v_end - f dt lifted it by |g| dt^2 / 2 every step). What lies outside is impulsive (a
/// push from a collision, a bounce) or friction, and moves the sphere with its end velocity, as
/// the solver assumed: were the part across f only bounded by |f|, two spheres pushed apart
/// sideways would each move up to |g| dt^2 / 2 less than their solved velocities, and
/// terrain-rain's mean deepest overlap would be 16-24% deeper (docs/accuracy.md).
/// Positions then move by v_end dt - a dt^2 / 2 (integrate_positions; soft_store_bodies takes
/// the same off).
inline void uniform_step_acceleration(const SphereSoA& s, std::size_t i, const IntegrationParams& p,
                                      const float v_end[3], float a[3]) {
  const float movable = s.inv_mass[i] > 0.0f ? (p.modes.gravity_scaled ? s.gravity_scale[i] : 1.0f) : 0.0f;
  float f[3] = {p.gravity[0] * movable, p.gravity[1] * movable, p.gravity[2] * movable};
  if (p.modes.forces)
    f[0] += s.force_x[i] * s.inv_mass[i], f[1] += s.force_y[i] * s.inv_mass[i], f[2] += s.force_z[i] * s.inv_mass[i];
  const float ff = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
  if (!(ff > 0.0f)) {
    a[0] = a[1] = a[2] = 0.0f;
    return;
  }
  const float inv_dt = 1.0f / p.dt;
  const float mean[3] = {(v_end[0] - p.start_vx[i]) * inv_dt, (v_end[1] - p.start_vy[i]) * inv_dt,
                         (v_end[2] - p.start_vz[i]) * inv_dt};
  const float share = (mean[0] * f[0] + mean[1] * f[1] + mean[2] * f[2]) / ff;
  const float along = share < 0.0f ? 0.0f : share > 1.0f ? 1.0f : share;
  float across[3] = {mean[0] - share * f[0], mean[1] - share * f[1], mean[2] - share * f[2]};
  const float across2 = across[0] * across[0] + across[1] * across[1] + across[2] * across[2];
  const float bound2 = ff * along * (1.0f - along);
  if (across2 > bound2) {
    const float shrink = std::sqrt(bound2 / across2);
    for (float& c : across) c *= shrink;
  }
  for (int d = 0; d < 3; ++d) a[d] = along * f[d] + across[d];
}

/// Earliest t in (0, limit] where d0 + vn t + an t^2 / 2 = 0, or a negative value if none: when
/// a sphere at gap d0 from a plane, moving at vn along its normal with acceleration an, meets
/// it. Computed in double: it must not lose the root to rounding.
double earliest_root(double d0, double vn, double an, double limit);

/// v += F inv_mass dt and, with `rotation`, w += T inv_inertia dt for spheres [first, last),
/// F and T their accumulated force and torque (World::apply_force / apply_torque); static
/// spheres (inv_mass 0) do not move. Leaves the accumulators as they are (a step applies
/// them in each of its substeps; World::step zeroes them after the last).
void apply_forces(SphereSoA& spheres, std::size_t first, std::size_t last, float dt, bool rotation);

/// v += (g dt) gravity_scale for movable spheres in [first, last); returns the largest speed after it among
/// the spheres that are not fast. With `fast` given, the movable spheres that travel more than
/// fast_fraction of their radius this step (is_fast, kernel/ccd/continuous_collision.h) are
/// appended to it in slot order.
float predict_velocities(SphereSoA& spheres, std::size_t first, std::size_t last, const IntegrationParams& params,
                         float fast_fraction = 0.0f, std::vector<std::uint32_t>* fast = nullptr);

/// integrate_positions without planes, one sphere at a time: the scalar reference of the SIMD
/// kernel that integrate_positions runs when there are none (SimdKernels::integrate_free).
/// skip[i] != 0: moved already (null: none).
void integrate_free_scalar(SphereSoA& spheres, std::size_t first, std::size_t last, const IntegrationParams& params,
                           const std::uint8_t* skip);

/// Moves spheres in [first, last) over dt with their solved velocities, resolving impacts with
/// the planes at their exact time (at most four per sphere per step). Spheres with skip[i] != 0
/// were moved already (continuous collision); an empty `skip` skips none. With `impacts` given,
/// each plane impact that applied an impulse is appended to it (in slot order).
void integrate_positions(SphereSoA& spheres, std::size_t first, std::size_t last, std::span<const Plane> planes,
                         const IntegrationParams& params, std::span<const std::uint8_t> skip = {},
                         std::vector<Impact>* impacts = nullptr);

}  // namespace hail
