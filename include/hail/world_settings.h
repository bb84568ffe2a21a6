#pragma once
// WorldSettings: how a World steps, every knob with its unit and what too little or too much
// does; and the choices it names (pair search, integrator, depenetration). Checked by the World
// constructor (InvalidArgument naming the setting).

#include <algorithm>
#include <cstddef>

#include "hail/vec3.h"

namespace hail {

/// How positions follow velocities (WorldSettings::integrator).
enum class Integrator {
  /// v += a dt, then x += v dt with the solved velocity (symplectic). Bounce apexes 4% high at
  /// dt 1/60 (first order in free flight); the default up to 0.2.0 (docs/accuracy.md).
  SemiImplicitEuler,
  /// x += v dt - a dt^2 / 2 with the solved end velocity v and the step's mean acceleration a
  /// (uniform_step_acceleration): exact in free flight and for uniformly accelerated motion, no
  /// motion at rest (the original design; the default: bounce, slide to roll and slope roll
  /// within 0.5% at dt 1/60, docs/accuracy.md#the-uniform-integrator-at-rest).
  UniformAcceleration,
};

/// Which contact solver a step runs (WorldSettings::solver).
enum class Solver {
  /// Collision passes (restitution, impulses passed along chains), then warm start and resting
  /// passes of accumulated impulses (collision_iterations, resting_iterations): the default.
  Passes,
  /// Box2D v3's soft step (Catto, "Solver2D", 2024; SoftStepParams): the step's contacts are
  /// solved in `substeps` short substeps, each one soft (spring-damper) iteration with the
  /// separation updated from the spheres' displacements (no new collision detection) and the
  /// positions advanced, then rigid relax iterations; restitution is applied once at the end.
  /// collision_iterations and resting_iterations are not used.
  SoftStep,
};

/// The soft step's knobs (WorldSettings::soft_step; Solver::SoftStep). The defaults are from the
/// work-precision figures of docs/benchmarks.md, "Soft step" (terrain-rain 4k): Box2D v3's 4
/// substeps, one relax iteration, damping ratio 10 and pushes of at most 3 m/s, with the
/// stiffest contact the substep resolves (0.25 cycles per substep: a smaller mean deepest
/// overlap than Box2D's 30 Hz, 0.125 at 60 steps a second, at every substep count measured).
struct SoftStepParams {
  /// Substeps per (sub)step, >= 1: each one warm start, one soft iteration, a position update
  /// and relax_iterations rigid ones over every contact. More: stiffer, deeper stacks hold,
  /// and each substep costs about what three resting passes of Solver::Passes cost.
  int substeps = 4;
  /// Stiffness of the sphere-sphere contact spring, in cycles per substep (its frequency in Hz
  /// times the substep's length), in (0, 0.25]: at 0.25 (Box2D v3's cap, a quarter of the
  /// substep rate) the spring is as stiff as the substep resolves; smaller values let piles
  /// sink further before they push back. Ground contacts (a static side) use twice this, as
  /// Box2D's static softness does.
  float contact_cycles = 0.25f;
  /// Damping ratio of the contact spring, > 0 (Box2D v3: 10, far over-damped): small values
  /// make overlapping spheres spring apart, large ones make them push apart slowly.
  float damping_ratio = 10.0f;
  /// Rigid iterations (no position bias) after each substep's soft one, >= 0: they remove the
  /// push velocity the soft iteration added, so that spheres pushed out of overlap do not fly.
  int relax_iterations = 1;
  /// Largest speed (m/s, > 0) at which the soft iteration pushes overlapping spheres apart
  /// (Box2D v3's contactPushMaxVelocity, 3 m/s). An overlap deep enough to be pushed this fast
  /// (17 cm between spheres, 9 cm on the ground, at the defaults and dt 1/60) is not pushed:
  /// depenetration moves it apart without adding velocity, and it keeps no warm-start impulse.
  float max_push_speed = 3.0f;
  /// Most depenetration passes a step runs: past WorldSettings::depenetration_iterations, passes
  /// go on while the previous one pushed a contact out of an overlap beyond twice the slop whose
  /// smaller sphere is so small that the contact's spring sags beyond the slop under gravity
  /// alone (radius under |g| / omega^2 / slop_fraction: 6.9 mm at the defaults and dt 1/60). A
  /// soft contact carries a load at an overlap of about |g| / omega^2, a length (17 um on the
  /// ground, 69 um between spheres), which is a large share of a sub-millimetre sphere's
  /// radius, and one substep's gravity moves such a sphere further than its radius: four
  /// passes left a two-layer pile of 0.1 mm spheres 18% of their radius in the ground after its
  /// first step, 16 passes 1.1% (docs/benchmarks.md, "Soft step"). Larger spheres never get
  /// the extra passes; a value at or below depenetration_iterations turns them off.
  int depenetration_iterations_max = 16;
};

/// Position correction after the solve (WorldSettings::depenetration).
struct DepenetrationParams {
  float fraction = 0.8f;        ///< share of the excess overlap removed per pass
  float slop_fraction = 0.01f;  ///< overlap tolerated, as a fraction of the smaller radius
};

/// How sphere-sphere pairs are found. All give exactly the same pairs in the same order, so the
/// choice changes speed only, never the simulation (tests/test_broadphase.cpp).
enum class PairSearch {
  Automatic,      ///< by sphere count and radius spread, from measured crossovers (docs/benchmarks.md)
  BruteForce,     ///< SIMD all-pairs: O(n^2), fastest for small n
  Grid,           ///< hashed uniform grid sized by the largest reach (diameter + margin): O(n) for similar radii
  SweepAndPrune,  ///< sort along the axis of greatest spread, per radius class
  Bvh,            ///< per-step BVH over the spheres (the terrain's builder and flat walk)
};

/// Smallest WorldSettings::solver_tile_spheres other than 0: below it tiles hold too few
/// contacts to fill SIMD batches, and the colouring's per-tile tables grow with the tile count.
inline constexpr std::size_t kMinSolverTileSpheres = 64;

/// The shortest step World::step takes, in simulated seconds (dt * time_scale; time_scale 0,
/// a pause, is always accepted): a step divides by its length (and the soft step by its
/// substeps' squares, up to kMaxIterations of them), which left float range below about 2e-39 s
/// and turned every sphere NaN. 1e-9 s keeps those quotients 100 times inside float range for
/// the heaviest sphere; no sphere moves measurably in it. WorldSettings::max_substep is at least it.
inline constexpr float kMinStep = 1e-9f;

/// Most passes or substeps any iteration count of WorldSettings (and SoftStepParams) may ask
/// for: collision, resting and depenetration passes, soft-step substeps, relax iterations and
/// the soft step's depenetration maximum. Each costs a pass over every contact; the shipped
/// scenes use at most 16, and 2^31 passes over 8 spheres took minutes a step. The one range,
/// whether a setting comes from code, a scene file, a snapshot or the command line.
inline constexpr int kMaxIterations = 1000;
/// Most substeps WorldSettings::max_substeps may allow one step(dt): each costs a whole step's
/// work, so a larger cap only lets a step run for hours.
inline constexpr int kMaxSubstepsCap = 100'000;

/// How a World steps. Every field is checked by the World constructor (InvalidArgument).
struct WorldSettings {
  Vec3 gravity{0.0f, -9.81f, 0.0f};  ///< m/s^2
  /// Slow motion factor: each step advances time_scale * dt of simulated time. 0 freezes.
  float time_scale = 1.0f;
  /// Steps longer than this (s, after time_scale) are split into equal substeps no longer than
  /// it. A step of 1.7 s (time scale 100 at 1/60) sweeps every sphere resting on the ground
  /// thousands of times and multiplied its energy in the stress battery (docs/benchmarks.md,
  /// "Figures behind the code's choices"); 1/20 s keeps every step of the shipped scenes whole.
  float max_substep = 0.05f;
  /// Most substeps one step(dt) may be split into, >= 1. A step that needs more
  /// (substeps_needed below) is refused with InvalidArgument and the world is left unchanged:
  /// without the cap step(1e5) of one sphere ran two million substeps (seconds), and a count
  /// past INT_MAX wrapped to one substep of the whole dt. 256 is 12.8 s of simulated time per
  /// call at the default max_substep, far beyond any frame (time scale 100 at 1/60 s needs 34).
  int max_substeps = 256;
  Integrator integrator = Integrator::UniformAcceleration;
  /// Worker threads for step(); 0 = all hardware threads; 1 = strictly the calling thread.
  /// Ignored when the World is given the caller's task_arena.
  int threads = 0;
  /// The contact solver (Solver): Passes (today's, the default) or SoftStep (soft_step's knobs).
  Solver solver = Solver::Passes;
  SoftStepParams soft_step{};
  /// Passes that bounce closing contacts with restitution, propagating impulses through
  /// chains (a Newton's cradle of n spheres needs n). Stops early once nothing is closing.
  int collision_iterations = 16;
  /// Sequential-impulse passes for resting contacts (piles, rolling). Too few: piles sag.
  int resting_iterations = 8;
  /// Position-correction passes after integration.
  int depenetration_iterations = 4;
  /// The solver's tiles (kernel/solver/contact_colouring.h): runs of at most this many slots (in
  /// Morton order, so compact regions) whose contacts among themselves are solved together,
  /// one tile per thread at a time, before the contacts between tiles. A tile's bodies stay in
  /// its core's cache through all its colours, and a pass has one parallel stage for all tiles
  /// instead of one per colour. A world of fewer than 16 tiles of this many spheres gets
  /// smaller tiles (solver_tile_size in kernel/world/step_heuristics.h: 16 tiles of at least 256 spheres, or two halves of a small
  /// world), so that 16 threads share the tiles from 4,096 spheres up.
  /// 0: no tiles (every colour spans all spheres). The order in which contacts are solved
  /// depends on the tile size, so states differ bitwise between tile sizes (never between
  /// thread counts). The default and its measurements: docs/benchmarks.md, "Solver tiles".
  std::size_t solver_tile_spheres = 2048;
  DepenetrationParams depenetration{};
  /// Closing speeds (m/s) at or below max(this, 2 |g| dt) are treated as resting, not bounced:
  /// a sphere lying on the ground closes at |g| dt every step and must not hop.
  float restitution_threshold = 0.2f;
  /// Sphere-sphere collisions on/off (off: spheres only meet static geometry).
  bool sphere_collisions = true;
  PairSearch pair_search = PairSearch::Automatic;
  /// Sphere-sphere contacts are made speculatively for spheres whose gap is less than the
  /// distance they could close this step (2 * max speed * dt), capped at this many radii of the
  /// larger sphere. Larger: fewer missed fast contacts, more contact pairs.
  float speculative_radii = 1.0f;
  /// Sphere-sphere contacts a step may make, per sphere (>= 1): at most this many times the
  /// sphere count in all, shared out over runs of 64 slots (neighbours, in the Morton order).
  /// Pairs past a run's share are dropped, the first in slot order kept (the same for any
  /// thread count), and StepStats::sphere_contacts_capped says so. A guard, not a working
  /// limit: 10,000 spheres at one point made 50 million contacts and the step ran out of
  /// memory; spheres in a pile have about 6 each (terrain-rain: under 2), and a large sphere
  /// may have many small ones on it while its neighbours have few. A capped step frees the
  /// excess it found, so it allocates again (an overflow, not a steady state).
  std::size_t max_sphere_contacts_per_sphere = 64;
  /// Each pair's own speculative margin: this many times the distance the two spheres can close
  /// this step by their own speeds, (|va| + |vb|) dt, and never more than the step's margin
  /// above (which one fast sphere widens for everyone). Resting neighbours then get contacts
  /// only where they touch, not with the next shell of a pile: far fewer sphere contacts per step
  /// with the same worst penetration. 2 leaves room for speed gained from impacts during the step
  /// (1 let spheres sink deeper); 0 gives every pair the step's margin. Figures: docs/benchmarks.md,
  /// "Figures behind the code's choices".
  float pair_margin_travel = 2.0f;
  /// Every this many steps the spheres' dense slots are re-sorted by the Morton code of their
  /// centres (handles stay valid; slot order, and so World::spheres() order, changes), so
  /// neighbours sit together in memory and terrain queries run in coherent packets. 0 never
  /// re-sorts. The sort costs about one step's integrate phase; see docs/benchmarks.md for what it buys.
  int reorder_interval = 16;
  /// Warm starting: each contact starts with this fraction, in [0, 1], of the impulses it ended
  /// the last step with (kernel/solver/contact_cache.h), so that piles hold their weight from the
  /// first resting pass. Below 1 piles sag more into the ground (measured in docs/accuracy.md,
  /// the warm-start table). 0 turns warm starting off: no impulse is remembered or looked up, and
  /// every step starts from zero (deep piles sink into the ground).
  float warm_start_factor = 1.0f;
  /// Continuous collision (kernel/ccd/continuous_collision.h): spheres that travel more than
  /// fast_travel_fraction of their radius in a step are moved along their path impact by impact,
  /// so they neither tunnel nor bounce early. Off: they are left to the discrete step, whose
  /// terrain contacts then reach at most fast_travel_fraction radii (fast spheres tunnel; the
  /// benchmark shows what the sweep prevents). Spheres that are not fast step the same either way.
  bool continuous_collision = true;
  /// In (0, 1]. At 1 (one radius per step) the discrete step is still safe: a sphere's
  /// terrain contacts reach as far as it travels, and two spheres that are not fast close by at
  /// most ra + rb in a step, so they may overlap (the pair margin is capped at speculative_radii
  /// of the larger radius) but never pass through each other. terrain-rain's fastest fall,
  /// 21.5 m/s at dt = 1/60, is 0.72 radii: it stays discrete and pays nothing for the sweep.
  /// Smaller values sweep more spheres: fewer overlaps, exact impact times, more cost.
  float fast_travel_fraction = 1.0f;
  /// Impacts one swept sphere may have in one step; a sphere that reaches it stops where the
  /// last one left it for the rest of the step (StepStats::sweep.capped counts it). A guard
  /// against endless zero-time impacts, not a working limit: a very fast sphere into a pile needs
  /// hundreds of impacts in one step, and a low cap stops spheres early and leaves the pile
  /// overlapping (hail-bench stress: docs/benchmarks.md, "Figures behind the code's choices").
  int max_sweep_events = 256;
  /// Shock propagation (kernel/solver/shock_propagation.h): one more resting pass from the ground up
  /// with the lower body of each contact held still, run in steps where the heaviest movable
  /// sphere weighs more than this many times the lightest. Without it a 1 : 100 : 1e4 kg stack
  /// presses its 1 kg sphere through the ground. >= 1; infinity: never. The default leaves
  /// scenes of equal (or nearly equal) masses exactly as they were, and costs them nothing.
  float shock_mass_ratio = 10.0f;
  /// Spheres spin and roll: friction applies angular impulses (r x p through the inverse inertia
  /// 5 / (2 m r^2)), so a sliding sphere starts to roll and a rolling one keeps its spin. Off,
  /// spheres never spin: friction acts on the linear velocities alone (effective mass
  /// 1 / (1/m_a + 1/m_b), as along the normal), so a sliding sphere slows to a stop instead of
  /// rolling, and no angular velocity is read, changed or integrated: every angular velocity
  /// stays 0 (add_sphere refuses a non-zero one) and the step does no angular work
  /// (StepParts::rotation). A scene without friction runs the same passes either way and
  /// steps bitwise the same.
  bool rotation = true;
  /// Rolling resistance coefficient mu_r (dimensionless, finite, >= 0; default 0: none). Every
  /// contact that carries load N opposes the turning of its spheres against each other (their
  /// relative angular velocity: rolling, and twist about the normal) with an angular impulse
  /// of at most mu_r r N, r the contact's effective radius (the sphere's against static
  /// ground, r_a r_b / (r_a + r_b) between spheres): the constant-torque model of DEM codes
  /// (LIGGGHTS' rolling_friction cdt, Box2D v3's rollingResistance). A sphere rolling on flat
  /// ground slows at 5/7 mu_r g, and one on a slope of angle theta stays put where
  /// tan theta <= mu_r. Without it an ideal sphere rolls on for ever: in a bowl it swings like
  /// a pendulum, and a pile whose edge spheres roll along its grooves takes half a minute to
  /// come to rest (bowl-pile 4k: all asleep after 35 s; 12 s with 0.05, docs/accuracy.md).
  /// Its impulses are warm-started (snapshots keep them). The passes solver only
  /// (World::validate refuses it with the soft step); it acts where friction and rotation do.
  /// Costs nothing at 0.
  float rolling_resistance = 0.0f;
  /// Sleeping (kernel/world/sleep_islands.h): spheres joined by sphere-sphere contacts form an
  /// island (the terrain, planes and immovable spheres join none); an island all of whose
  /// spheres have stayed below sleep_linear_speed and sleep_angular_speed for sleep_time goes
  /// to sleep as a whole: velocities zeroed, and left out of integration, the solve and the
  /// pair and ground tests among sleepers (World::is_sleeping). A contact with a moving
  /// sphere (continuous collision's impacts too), any control call on one of its spheres
  /// (setters, impulses, forces), removing one of them and changing the ground (terrain,
  /// planes, ground filter, shift_origin) wake it. On by default, as in Box2D, Jolt, Bullet
  /// and PhysX: a scene pays nothing for what has come to rest. Until the first island sleeps
  /// a step is bitwise the same either way (the timers change no state); off, nothing sleeps
  /// and a step is bitwise what it was before sleeping existed.
  bool sleep = true;
  /// m/s, finite and >= 0: a sphere faster than this resets its sleep timer. Box2D v3 uses
  /// 0.05 m/s (b2BodyDef::sleepThreshold), Jolt 0.03 m/s (of a point's velocity,
  /// PhysicsSettings::mPointVelocitySleepThreshold). Too small, a pile never sleeps (its
  /// spheres keep a residual jitter); too large, a slow roll stops dead.
  float sleep_linear_speed = 0.05f;
  /// rad/s, finite and >= 0: a sphere spinning faster resets its sleep timer. 0.1 rad/s is
  /// 0.05 m/s at the surface of a sphere of radius 0.5 m (the linear speed above). What is
  /// compared is the spin that slides a contact: for a sphere whose contacts carry load
  /// (normal impulse > 0 that substep), the largest |w x n| over their normals n; for one with
  /// none, all of |w|. Spin about a loaded contact's normal (a twist in place) is left out:
  /// without rolling_resistance (default 0) nothing would ever stop it, and it moves
  /// nothing (a sphere pinched between two neighbours, spinning about the line through the two
  /// contacts, kept a whole 2,000-sphere pile awake). Spin across a normal (rolling, or
  /// slipping against friction) counts in full.
  float sleep_angular_speed = 0.1f;
  /// s, finite and >= 0: how long an island must stay below both speeds to sleep. Box2D v3
  /// (b2_timeToSleep) and Jolt (mTimeBeforeSleep) both use 0.5 s: long enough that a sphere at
  /// the top of a bounce, momentarily still, does not fall asleep in the air.
  float sleep_time = 0.5f;
};

}  // namespace hail
