#pragma once
// Integration of sphere state over one (time-scaled) step.
//
// Velocities get gravity first (predict), the solver then corrects them, and positions move
// last with the corrected velocity. Against static planes the position update is exact in
// time: a sphere that reaches a plane during the step is advanced to the moment of impact,
// bounced there (restitution and friction), and moved on for the rest of the step, so bounce
// heights carry no error from where inside a step the impact fell.

#include <cstdint>
#include <span>
#include <vector>

#include "hail/collision_filter.h"
#include "hail/sphere_soa.h"
#include "hail/world_settings.h"
#include "kernel/terrain/plane_contacts.h"

namespace hail {

struct IntegrationParams {
  Integrator integrator = Integrator::SemiImplicitEuler;
  float gravity[3] = {0.0f, -9.81f, 0.0f};
  float dt = 0.0f;                     ///< time-scaled step
  float restitution_threshold = 0.0f;  ///< closing speeds at or below this do not bounce
  bool rotation = true;  ///< plane impacts' friction turns spheres (WorldSettings::rotation); off: linear only
  /// Some sphere's gravity scale is not 1. When false the loops skip the multiply by it (the
  /// same result: the scale is 1): World keeps the flag, so scenes without scales pay nothing.
  bool gravity_scaled = true;
  /// Some collision filter is not the default: spheres whose filter rejects `ground` (the
  /// planes' filter, World::set_ground_filter) pass through the planes.
  bool ground_filtered = false;
  CollisionFilter ground{};
};

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

/// Moves spheres in [first, last) over dt with their solved velocities, resolving impacts with
/// the planes at their exact time (at most four per sphere per step). Spheres with skip[i] != 0
/// were moved already (continuous collision); an empty `skip` skips none. With `impacts` given,
/// each plane impact that applied an impulse is appended to it (in slot order).
void integrate_positions(SphereSoA& spheres, std::size_t first, std::size_t last, std::span<const Plane> planes,
                         const IntegrationParams& params, std::span<const std::uint8_t> skip = {},
                         std::vector<Impact>* impacts = nullptr);

}  // namespace hail
