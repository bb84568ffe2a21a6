#pragma once
// StepModes: what one (sub)step does and how, decided once per substep from the settings and
// the world's state (World::substep) and read by every phase that branches on it: the step's
// pipeline (kernel/world/step_pipeline.cpp), the integrator (IntegrationParams::modes) and the
// sweep (SweepScene::modes). One place decides each mode, so two phases never disagree about one.

#include "hail/collision_filter.h"
#include "hail/world_settings.h"

namespace hail {

struct StepModes {
  Integrator integrator = Integrator::UniformAcceleration;
  Solver solver = Solver::Passes;
  /// WorldSettings::rotation: spheres spin. Off, friction acts on linear velocities alone and
  /// no angular velocity is read or written.
  bool rotation = true;
  /// WorldSettings::warm_start_factor > 0: contacts start from last step's impulses, which are
  /// looked up and remembered. Off (factor 0), the cache is not touched at all.
  bool warm_start = true;
  /// WorldSettings::continuous_collision: fast spheres are swept impact by impact.
  bool sweeping = true;
  /// WorldSettings::sleep: sleepers are left out (kernel/world/sleep_islands.h).
  bool sleeping = false;
  /// Some sphere sleeps as the substep starts (none falls asleep before its islands phase, at
  /// its end): the filters that leave sleepers' contacts out, and the warm-start cache's carry
  /// of their impulses, run only then. Where none sleeps they would drop nothing.
  bool sleepers = false;
  /// Sphere collisions on and at least two spheres: the pair search runs.
  bool detect_pairs = true;
  /// A terrain or planes: sphere-static detection runs.
  bool detect_static = false;
  /// A terrain: the terrain guard runs after depenetration.
  bool terrain_guard = false;
  /// Pairs are filtered by their own margin (pair_margin_travel > 0, with sphere collisions).
  bool pair_margins = false;
  /// Some sphere has a force or torque to apply (World::apply_force / apply_torque): the
  /// uniform-acceleration integrator's free flight includes F inv_mass (else the force arrays
  /// are zero).
  bool forces = false;
  /// Some sphere's gravity scale is not 1. When false the loops skip the multiply by it (the
  /// same result: the scale is 1): World keeps the flag, so scenes without scales pay nothing.
  bool gravity_scaled = true;
  /// Some collision filter is not the default: filtered pairs are dropped, and spheres whose
  /// filter rejects `ground` pass through the terrain and planes.
  bool filtering = false;
  CollisionFilter ground{};  ///< the terrain's and planes' filter (World::set_ground_filter)

  /// Integrator::UniformAcceleration: each sphere's start velocity is kept (predict).
  [[nodiscard]] bool uniform_acceleration() const { return integrator == Integrator::UniformAcceleration; }
  /// Solver::SoftStep.
  [[nodiscard]] bool soft_step() const { return solver == Solver::SoftStep; }
};

}  // namespace hail
