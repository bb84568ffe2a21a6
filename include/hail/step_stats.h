#pragma once
// What the last step did: counters (StepStats), the optional parts that ran (StepParts) and the
// wall-clock time of each phase (PhaseTimes). World::last_step_stats() and last_phase_times().

#include <cstddef>

#include "hail/world_settings.h"

namespace hail {

/// Continuous collision of the last step (StepStats::sweep).
struct SweepStats {
  std::size_t fast = 0;           ///< spheres swept because they were fast
  std::size_t swept = 0;          ///< spheres swept in all (fast ones and those they hit)
  std::size_t meets_spheres = 0;  ///< of those, swept against spheres too (fast at the start or after an impact)
  std::size_t events = 0;         ///< impacts resolved at their time
  std::size_t capped = 0;         ///< spheres that reached max_events and stopped for the rest of the step
  std::size_t held = 0;           ///< impacts in which the ground held a light sphere struck into it
};

/// Wall-clock milliseconds spent in each phase of the last step (cheap enough to stay on).
struct PhaseTimes {
  double reorder = 0, predict = 0, detect_terrain = 0, detect_pairs = 0, solve = 0, sweep = 0, integrate = 0,
         depenetrate = 0, islands = 0;
  [[nodiscard]] double total() const {
    return reorder + predict + detect_terrain + detect_pairs + solve + sweep + integrate + depenetrate + islands;
  }
};

/// Which optional parts of a step ran. A step runs only what its scene needs: no planes and no
/// terrain, no static detection; sphere collisions off (or one sphere), no pair search; no
/// contacts, no solve and no depenetration; no contact with friction, no friction work; no
/// friction or rotation off, no angular work; no fast sphere, no sweep. Predict and integrate
/// always run.
struct StepParts {
  bool reorder = false;        ///< Morton re-sort (every reorder_interval steps)
  bool detect_static = false;  ///< sphere-plane and sphere-terrain contacts
  bool detect_pairs = false;   ///< sphere-sphere pair search
  bool solve = false;          ///< contact impulses
  bool friction = false;       ///< friction within the solve (some contact has friction > 0)
  bool rotation = false;       ///< angular work in the solve: WorldSettings::rotation on, and friction
  bool sweep = false;          ///< continuous collision of fast spheres
  bool shock = false;          ///< shock propagation (masses differ more than shock_mass_ratio)
  bool depenetrate = false;    ///< position correction
  bool terrain_guard = false;  ///< spheres that moved beyond their terrain contacts' reach checked (terrain only)
};

/// Counters of the last step.
struct StepStats {
  std::size_t static_contacts = 0;
  std::size_t sphere_contacts = 0;
  std::size_t colours = 0;  ///< colours on a pass's critical path: the largest solver tile's, then the shared ones
  std::size_t tile_contacts = 0;    ///< contacts solved within a solver tile (WorldSettings::solver_tile_spheres)
  std::size_t shared_contacts = 0;  ///< contacts across tile edges (every contact without tiles)
  int collision_passes = 0;         ///< collision passes that applied an impulse
  /// Depenetration passes run (of the last substep): WorldSettings::depenetration_iterations,
  /// or more with the soft step (SoftStepParams::depenetration_iterations_max).
  int depenetration_passes = 0;
  PairSearch pair_search = PairSearch::BruteForce;  ///< the search that ran (never Automatic)
  std::size_t warm_started = 0;                     ///< contacts that found their last-step impulses
  SweepStats sweep;                                 ///< continuous collision: fast spheres, impacts, capped spheres
  StepParts ran;                                    ///< the optional parts that ran (of the last substep)
  /// Some sphere-sphere pairs were dropped: a run of slots found more than its share of
  /// WorldSettings::max_sphere_contacts_per_sphere (of the last substep).
  bool sphere_contacts_capped = false;
  /// Spheres the terrain guard moved out of the terrain (Terrain::push_out), or the plane guard
  /// set back onto a plane their centre had ended behind (after depenetration in a crowd).
  std::size_t pushed_out = 0;
  /// Spheres found with their centre below the terrain surface at the start of the step (those
  /// added, or all after set_terrain, since the last step) and lifted out onto it (World::step).
  std::size_t lifted_out = 0;
  /// Bounces off speculative terrain contacts moved to their time of impact (of the last
  /// substep; the passes solver: kernel/solver/bounce_timing.h, docs/accuracy.md).
  std::size_t timed_bounces = 0;
  /// How often the step's threads met, all substeps (jobs/sync_count.h): parallel loops of more
  /// than one block (each a fork and a join) and solver stages of more than one block (each a
  /// barrier). The same on every thread count above one (jobs/sync_count.h). Counted
  /// process-wide: while another world steps at the same time, its meetings are counted too.
  std::size_t parallel_loops = 0;
  std::size_t crew_stages = 0;
  /// Sleeping (WorldSettings::sleep; 0 when off): spheres asleep after the step, and awake
  /// spheres that have stayed slow for sleep_time at the end of its last substep: ready to sleep,
  /// and kept awake by a sphere of their island that is not (or by an island in free flight).
  std::size_t sleeping = 0;
  std::size_t ready_to_sleep = 0;
};

}  // namespace hail
