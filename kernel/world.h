#pragma once
// kernel/ is hail's geometry and physics: primitives, contacts, the solver rules, the
// integrator and World, the object users create. How a step's work is spread over threads lives
// in jobs/; kernel/ only provides the range-based functions the phases call.
//
// World owns sphere state (SoA), static planes, settings and the per-step scratch buffers. It
// shares the terrain (a shared_ptr<const Terrain>, immutable) and uses, without owning, the
// caller's tbb::task_arena when given one.
//
// Threads: a World is not thread-safe: call its methods from one thread at a time (const
// methods may run at the same time as each other, never with a non-const one). step() itself
// runs in parallel inside a tbb::task_arena (the caller's, or one the World makes of `threads`
// slots); the calling thread joins in and returns when the step is done. hail never starts
// threads of its own. Separate Worlds share nothing mutable and may step at the same time.
//
// Allocation: add_sphere allocates only when the sphere arrays outgrow their capacity (reserve()
// prevents it). step() reuses its scratch buffers, so a steady-state step allocates nothing:
// they grow only when a step needs more contacts or pairs than every step before it, and then
// to at least twice their capacity (soa/grow.h), so a scene whose counts keep rising
// reallocates each buffer O(log n) times (tests/allocation/, hail-alloc-tests). The
// accessors return views or values and never allocate. The constructors, add_plane,
// set_terrain and enable_trace allocate, and while a trace records it grows every step.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <oneapi/tbb/task_arena.h>

// PhaseTrace is jobs/' recorder; World owns one so that a trace outlives the steps it records.
#include "jobs/phase_trace.h"
#include "jobs/stage_crew.h"
#include "kernel/aabb.h"
#include "kernel/contact.h"
#include "kernel/contact_cache.h"
#include "kernel/contact_colouring.h"
#include "kernel/sphere_extremes.h"
#include "kernel/contact_solve_simd.h"
#include "kernel/continuous_collision.h"
#include "kernel/depenetrate.h"
#include "kernel/errors.h"
#include "kernel/features.h"
#include "kernel/integrate.h"
#include "kernel/plane.h"
#include "kernel/shock_propagation.h"
#include "kernel/solver_body.h"
#include "kernel/sphere_bvh_pairs.h"
#include "kernel/sphere_grid.h"
#include "kernel/sphere_sweep.h"
#include "kernel/sphere_pairs.h"
#include "kernel/terrain.h"
#include "kernel/vec3.h"
#include "soa/sphere_soa.h"

namespace hail {

/// How sphere-sphere pairs are found. All give exactly the same pairs in the same order, so the
/// choice changes speed only, never the simulation (tests/test_broadphase.cpp).
enum class PairSearch {
  Automatic,      ///< by sphere count and radius spread, from measured crossovers (docs/benchmarks.md)
  BruteForce,     ///< SIMD all-pairs: O(n^2), fastest for small n
  Grid,           ///< hashed uniform grid sized by the largest reach (diameter + margin): O(n) for similar radii
  SweepAndPrune,  ///< sort along the axis of greatest spread, per radius class
  Bvh,            ///< per-step BVH over the spheres (the terrain's builder and flat walk)
};

/// PairSearch::Automatic: below this many spheres of similar radii brute force wins (measured
/// crossover with the grid, `hail-bench pairs`: brute force ahead at 256, the grid from 1,000,
/// in random and in Morton order).
inline constexpr std::size_t kPairSearchMinSpheres = 1000;
/// Radii are "mixed" when largest / smallest is above kMixedRadiusSpread: the grid's cells must
/// fit the largest, so it needs more spheres to pay (measured on piles of 0.25..2.5 with 1% at
/// 5: brute force ahead at 1,000, the grid from 4,000 and ahead of the sphere BVH in either
/// slot order).
inline constexpr std::size_t kMixedPairSearchMinSpheres = 4000;
inline constexpr float kMixedRadiusSpread = 4.0f;
/// Beyond this spread (not measured: the bench's piles stop at 20) a few giants would make
/// every grid cell giant; the sphere BVH, whose boxes fit each sphere, takes over from
/// kGiantPairSearchMinSpheres (its crossover with brute force on the mixed piles).
inline constexpr float kGiantRadiusSpread = 20.0f;
inline constexpr std::size_t kGiantPairSearchMinSpheres = 16000;

/// Smallest WorldSettings::solver_tile_spheres other than 0: below it tiles hold too few
/// contacts to fill SIMD batches, and the colouring's per-tile tables grow with the tile count.
inline constexpr std::size_t kMinSolverTileSpheres = 64;

/// Spheres per solver tile for `spheres` spheres: WorldSettings::solver_tile_spheres, or half the
/// spheres (rounded up, at least kMinSolverTileSpheres) when that is smaller; 0 without tiles.
/// It depends on the sphere count alone, never on the thread count.
[[nodiscard]] constexpr std::size_t solver_tile_size(std::size_t setting, std::size_t spheres) {
  if (setting == 0) return 0;
  const std::size_t half = std::max<std::size_t>((spheres + 1) / 2, kMinSolverTileSpheres);
  return std::min(setting, half);
}

/// The search PairSearch::Automatic picks for n spheres with radii in [min_radius, max_radius].
/// The slot order (Morton or not) does not change the choice since the grid's rewrite.
[[nodiscard]] constexpr PairSearch automatic_pair_search(std::size_t n, float min_radius, float max_radius) {
  if (max_radius > kGiantRadiusSpread * min_radius)
    return n < kGiantPairSearchMinSpheres ? PairSearch::BruteForce : PairSearch::Bvh;
  const bool mixed = max_radius > kMixedRadiusSpread * min_radius;
  return n < (mixed ? kMixedPairSearchMinSpheres : kPairSearchMinSpheres) ? PairSearch::BruteForce : PairSearch::Grid;
}

/// How a World steps. Every field is checked by the World constructor (InvalidArgument).
struct WorldSettings {
  Vec3 gravity{0.0f, -9.81f, 0.0f};  ///< m/s^2
  /// Slow motion factor: each step advances time_scale * dt of simulated time. 0 freezes.
  float time_scale = 1.0f;
  /// Steps longer than this (s, after time_scale) are split into equal substeps no longer than
  /// it. A step of 1.7 s (time scale 100 at 1/60) sweeps every sphere resting on the ground
  /// thousands of times and gained energy 20-fold in the stress battery; 1/20 s keeps every step
  /// of the shipped scenes whole.
  float max_substep = 0.05f;
  /// Most substeps one step(dt) may be split into, >= 1. A step that needs more
  /// (substeps_needed below) is refused with InvalidArgument and the world is left unchanged:
  /// without the cap step(1e5) of one sphere ran two million substeps (seconds), and a count
  /// past INT_MAX wrapped to one substep of the whole dt. 256 is 12.8 s of simulated time per
  /// call at the default max_substep, far beyond any frame (time scale 100 at 1/60 s needs 34).
  int max_substeps = 256;
  Integrator integrator = Integrator::SemiImplicitEuler;
  /// Worker threads for step(); 0 = all hardware threads; 1 = strictly the calling thread.
  /// Ignored when the World is given the caller's task_arena.
  int threads = 0;
  /// Passes that bounce closing contacts with restitution, propagating impulses through
  /// chains (a Newton's cradle of n spheres needs n). Stops early once nothing is closing.
  int collision_iterations = 16;
  /// Sequential-impulse passes for resting contacts (piles, rolling). Too few: piles sag.
  int resting_iterations = 8;
  /// Position-correction passes after integration.
  int depenetration_iterations = 4;
  /// The solver's tiles (kernel/contact_colouring.h): runs of at most this many slots (in
  /// Morton order, so compact regions) whose contacts among themselves are solved together,
  /// one tile per thread at a time, before the contacts between tiles. A tile's bodies stay in
  /// its core's cache through all its colours, and a pass has one parallel stage for all tiles
  /// instead of one per colour. A world of fewer than twice this many spheres is cut into two
  /// tiles of half its spheres (solver_tile_size), so that two threads still share the tiles.
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
  /// only where they touch, not with the next shell of a pile: terrain-rain 4k, 12.5k -> 7.0k
  /// sphere contacts per step with the same worst penetration (docs/benchmarks.md). 2 leaves room for
  /// speed gained from impacts during the step (1 let spheres sink 0.0085 m instead of 0.005);
  /// 0 gives every pair the step's margin.
  float pair_margin_travel = 2.0f;
  /// Every this many steps the spheres' dense slots are re-sorted by the Morton code of their
  /// centres (handles stay valid; slot order, and so World::spheres() order, changes), so
  /// neighbours sit together in memory and terrain queries run in coherent packets. 0 never
  /// re-sorts. The sort costs about one step's integrate phase; see docs/benchmarks.md for what it buys.
  int reorder_interval = 16;
  /// Start each contact with the impulses it ended the last step with (kernel/contact_cache.h),
  /// so that piles hold their weight from the first resting pass. Off: every step starts from
  /// zero and deep piles sink into the ground.
  bool warm_start = true;
  /// Fraction of last step's impulses a contact starts with, in [0, 1]. Below 1 piles sag
  /// more into the ground (measured in docs/accuracy.md, the warm-start table).
  float warm_start_factor = 1.0f;
  /// Continuous collision (kernel/continuous_collision.h): spheres that travel more than
  /// fast_travel_fraction of their radius in a step are moved along their path impact by impact,
  /// so they neither tunnel nor bounce early. Off: they are left to the discrete step, whose
  /// terrain contacts then reach at most fast_travel_fraction radii (fast spheres tunnel; the
  /// benchmark shows what the sweep prevents). Spheres that are not fast step the same either way.
  /// Default: on when compiled in (HAIL_WITH_CONTINUOUS_COLLISION); true is refused otherwise.
  bool continuous_collision = HAIL_WITH_CONTINUOUS_COLLISION != 0;
  /// In (0, 1]. At 1 (one radius per step) the discrete step is still safe: a sphere's
  /// terrain contacts reach as far as it travels, and two spheres that are not fast close by at
  /// most ra + rb in a step, so they may overlap (the pair margin is capped at speculative_radii
  /// of the larger radius) but never pass through each other. terrain-rain's fastest fall,
  /// 21.5 m/s at dt = 1/60, is 0.72 radii: it stays discrete and pays nothing for the sweep.
  /// Smaller values sweep more spheres: fewer overlaps, exact impact times, more cost.
  float fast_travel_fraction = 1.0f;
  /// Impacts one swept sphere may have in one step; a sphere that reaches it stops where the
  /// last one left it for the rest of the step (StepStats::sweep.capped counts it). A guard
  /// against endless zero-time impacts, not a working limit: a 1e4 m/s sphere into a pile of 48
  /// took 750 impacts with no sphere above 64; at a cap of 16, 23 spheres stopped early and
  /// the pile ended 9% of a radius inside itself (hail-bench stress).
  int max_sweep_events = 256;
  /// Shock propagation (kernel/shock_propagation.h): one more resting pass from the ground up
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
  /// steps bitwise the same. Default: on when compiled in
  /// (HAIL_WITH_ROTATION); true is refused otherwise.
  bool rotation = HAIL_WITH_ROTATION != 0;
};

/// How many substeps World::step(dt) splits a step into under `settings`:
/// ceil(time_scale * dt / max_substep), at least 1; 0 when time_scale is 0 (nothing moves).
/// Computed in double, so it never overflows: a count beyond INT64_MAX is returned as
/// INT64_MAX. Throws InvalidArgument unless dt is finite and > 0. Needs no World: a scene
/// reader or a command line can call it to refuse a dt (with check_step) before it builds one.
[[nodiscard]] std::int64_t substeps_needed(const WorldSettings& settings, float dt);

/// Throws InvalidArgument exactly when World::step(dt) under `settings` would: dt not finite
/// or not > 0, or substeps_needed(settings, dt) > settings.max_substeps (the message gives dt,
/// time_scale, max_substep, the count needed and the ways out). Returns that count otherwise
/// (0 at time_scale 0). `settings` itself is assumed valid (the World constructor checks it).
std::int64_t check_step(const WorldSettings& settings, float dt);

/// What add_sphere accepts (InvalidArgument past them, naming the limit). They keep every
/// quantity a step derives from a sphere a normal float with room to spare: the inertia
/// 0.4 m r^2 lies in [4e-25, 4e23] kg m^2, so it and its inverse are normal floats (radius
/// 1e20 or mass 3e38 made it infinite and kinetic_energy() NaN), impulses m v stay below 1e18 N s
/// and their squares (friction cones) below 1e36, and squared speeds (the speculative margins)
/// below 1e12. The range covers dust to small moons: tests, scenes and the stress battery
/// use 0.01..10 m and 1e-3..1e4 kg.
inline constexpr float kMinSphereRadius = 1e-6f;  ///< m
inline constexpr float kMaxSphereRadius = 1e6f;   ///< m
inline constexpr float kMinSphereMass = 1e-12f;   ///< kg (movable spheres; a static one has none)
inline constexpr float kMaxSphereMass = 1e12f;    ///< kg
inline constexpr float kMaxSphereSpeed = 1e6f;    ///< m/s, |velocity|
inline constexpr float kMaxSphereSpin = 1e6f;     ///< rad/s, |angular_velocity|

/// Resolution: a float cannot place a point more finely than the spacing of floats at its
/// coordinates (2^-23 of their magnitude), so far from the origin small things blur. add_sphere
/// requires the spacing at the sphere's largest |coordinate| to be at most radius /
/// kSphereRadiusResolution: contacts, the depenetration slop and the stress battery's bounds
/// are a few percent of a radius, and the overlaps grow with the spacing (hail-bench stress,
/// terrain-rain's terrain moved out: deepest sphere overlap 0.8% of r at 1e4 m, 3.2% at 1e5 m
/// where the spacing is r / 64, 6.3% past the 5% bound at 2.5e5 m, r / 32). A sphere of radius
/// 0.5 may so be placed up to 2^17 = 131,072 m out, one of radius 1e-6 within 0.25 m. The
/// check is made when a sphere is added; a step does not stop a sphere flying further.
inline constexpr float kSphereRadiusResolution = 64.0f;
/// set_terrain requires the spacing of floats at the terrain's largest |coordinate| (its
/// corners' x and z, its highest and lowest heights) to be at most the smaller cell size /
/// kTerrainCellResolution: a point's cell and place in it, (x - origin) / cell, then err by at
/// most 1/64 of a cell. At 3e7 m with 1 m cells (spacing 2 m) cells collapsed to zero width and
/// every value turned NaN once a sphere landed. 1 m cells may lie up to 2^18 = 262,144 m out.
inline constexpr float kTerrainCellResolution = 64.0f;

/// A new sphere. Mass must be > 0 unless `is_static` (then it never moves). Radius, mass,
/// speed and spin within the limits above.
struct SphereDesc {
  Vec3 position{0.0f, 0.0f, 0.0f};          ///< m; resolvable for the radius (kSphereRadiusResolution)
  Vec3 velocity{0.0f, 0.0f, 0.0f};          ///< m/s
  Vec3 angular_velocity{0.0f, 0.0f, 0.0f};  ///< rad/s; must be zero when WorldSettings::rotation is off
  float radius = 0.5f;                      ///< m, in [kMinSphereRadius, kMaxSphereRadius]
  float mass = 1.0f;                        ///< kg, in [kMinSphereMass, kMaxSphereMass] (ignored when is_static)
  float restitution = 0.5f;                 ///< [0, 1]
  float friction = 0.5f;                    ///< Coulomb coefficient, >= 0
  bool is_static = false;                   ///< infinite mass: collides but never moves
};

/// A static plane: the solid half-space {x : normal . x < offset}. The normal is normalised.
struct PlaneDesc {
  Vec3 normal{0.0f, 1.0f, 0.0f};
  float offset = 0.0f;  ///< m
  float restitution = 0.5f;
  float friction = 0.5f;
};

/// Wall-clock milliseconds spent in each phase of the last step (cheap enough to stay on).
struct PhaseTimes {
  double reorder = 0, predict = 0, detect_terrain = 0, detect_pairs = 0, solve = 0, sweep = 0, integrate = 0,
         depenetrate = 0;
  [[nodiscard]] double total() const {
    return reorder + predict + detect_terrain + detect_pairs + solve + sweep + integrate + depenetrate;
  }
};

/// Which optional parts of a step ran. A step runs only what its scene needs: no planes and no
/// terrain, no static detection; sphere collisions off (or one sphere), no pair search; no
/// contacts, no solve and no depenetration; no contact with friction, no friction work; no
/// friction or rotation off, no angular work; no fast sphere, no sweep. Predict and integrate
/// always run.
struct StepParts {
  bool reorder = false;         ///< Morton re-sort (every reorder_interval steps)
  bool detect_static = false;   ///< sphere-plane and sphere-terrain contacts
  bool detect_pairs = false;    ///< sphere-sphere pair search
  bool solve = false;           ///< contact impulses
  bool friction = false;        ///< friction within the solve (some contact has friction > 0)
  bool rotation = false;        ///< angular work in the solve: WorldSettings::rotation on, and friction
  bool sweep = false;           ///< continuous collision of fast spheres
  bool shock = false;           ///< shock propagation (masses differ more than shock_mass_ratio)
  bool depenetrate = false;     ///< position correction
  bool terrain_guard = false;   ///< spheres that moved beyond their terrain contacts' reach checked (terrain only)
};

/// Counters of the last step.
struct StepStats {
  std::size_t static_contacts = 0;
  std::size_t sphere_contacts = 0;
  std::size_t colours = 0;        ///< colours on a pass's critical path: the largest solver tile's, then the shared ones
  std::size_t tile_contacts = 0;   ///< contacts solved within a solver tile (WorldSettings::solver_tile_spheres)
  std::size_t shared_contacts = 0; ///< contacts across tile edges (every contact without tiles)
  int collision_passes = 0;  ///< collision passes that applied an impulse
  PairSearch pair_search = PairSearch::BruteForce;  ///< the search that ran (never Automatic)
  std::size_t warm_started = 0;  ///< contacts that found their last-step impulses
  SweepStats sweep;              ///< continuous collision: fast spheres, impacts, capped spheres
  StepParts ran;                 ///< the optional parts that ran (of the last substep)
  /// Some sphere-sphere pairs were dropped: a run of slots found more than its share of
  /// WorldSettings::max_sphere_contacts_per_sphere (of the last substep).
  bool sphere_contacts_capped = false;
  std::size_t pushed_out = 0;    ///< spheres the terrain guard moved out of the terrain (Terrain::push_out)
  /// Spheres found with their centre below the terrain surface at the start of the step (those
  /// added, or all after set_terrain, since the last step) and lifted out onto it (World::step).
  std::size_t lifted_out = 0;
};

/// Read-only views of the dense sphere state, in slot order (World::slot_of maps a handle to
/// its slot, World::id_at a slot to its handle). No copy: the spans point into the World's SoA
/// arrays, so reading them costs nothing and they see every later step. They stay valid until
/// a call adds or removes spheres (or reserve() grows the arrays); a step keeps them valid but
/// may move spheres to other slots (the Morton re-sort, every reorder_interval steps), so look
/// a handle's slot up again after each step. Units: m, m/s, rad/s, m, 1/kg (0: static).
struct SphereState {
  std::span<const float> px, py, pz, vx, vy, vz, wx, wy, wz, radius, inv_mass;
};

class World {
 public:
  /// Creates its own task_arena of settings.threads slots. Throws InvalidArgument for a bad
  /// setting (the message names it).
  explicit World(const WorldSettings& settings = {});
  /// Runs every step inside the caller's arena (host_arena.execute): the host owns the threads
  /// and decides how many step() may use (its max_concurrency; settings.threads is ignored).
  /// The result is bitwise the same for any arena size. The arena must outlive the World; several
  /// Worlds may share one. Throws InvalidArgument for a bad setting.
  World(const WorldSettings& settings, tbb::task_arena& host_arena);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Adds a sphere; throws InvalidArgument (world unchanged) on a bad value.
  SphereId add_sphere(const SphereDesc& desc);
  /// Removes a sphere; false if the handle is stale. Other handles stay valid.
  bool remove_sphere(SphereId id);
  /// Adds a static plane; returns its index. Throws InvalidArgument on a bad value.
  std::size_t add_plane(const PlaneDesc& desc);
  /// Sets (or with nullptr removes) the static terrain and its material. The terrain is
  /// immutable and may be shared by several worlds. Throws InvalidArgument (world unchanged) on
  /// a bad material, or a terrain too far out for its cell size (kTerrainCellResolution).
  /// A movable sphere whose centre lies below the terrain surface (inside a hill: its contacts
  /// see no triangle, and it fell through forever) is lifted out at the start of the next step,
  /// as a plane pushes it out: its centre put a radius above the surface at its x, z, then
  /// moved out along the deepest overlap (Terrain::push_out). This is checked once for each
  /// sphere added since the last step, and for every sphere after set_terrain;
  /// StepStats::lifted_out counts them.
#if HAIL_WITH_TERRAIN
  void set_terrain(std::shared_ptr<const Terrain> terrain, float restitution = 0.5f, float friction = 0.5f);
#endif
  /// Moves the world's origin to `offset`: every sphere's position (static ones too) becomes
  /// position - offset, every plane and the terrain move with them, and velocities, spins,
  /// handles and warm-start impulses are kept, so the motion goes on as before, only where
  /// floats are finer. PhysX's PxScene::shiftOrigin: a game whose action wanders far (floats at
  /// 1e5 m are 7.8 mm apart) moves it back near the origin now and then, e.g. when the player
  /// is past 1-2 km out (docs/embedding.md, "Keeping the action near the origin").
  /// Cost: O(spheres + planes), plus a new Terrain built from terrain()->moved(-offset) (its
  /// BVH rebuilt: 0.04 s for 256 x 256 vertices), which this World then holds instead of the
  /// shared one. Warm-start impulses are kept unless the moved terrain's BVH orders its
  /// triangles differently (then they are dropped, as after set_terrain). last_contacts() is
  /// unchanged (it holds no positions); last_impacts() points move too.
  /// Exactness: a coordinate p becomes p - o exactly when o is a multiple of p's float spacing
  /// (any whole number of metres for |p| < 2^24 m) and |p - o| is below the power of two above
  /// |p|. So bringing the action back towards the origin by whole metres is exact; moving it
  /// out rounds each coordinate once, to half the spacing where it lands.
  /// Throws InvalidArgument (world unchanged) for a non-finite offset, a position or plane
  /// offset that would leave float range, or a terrain that set_terrain would refuse where it
  /// lands (kTerrainCellResolution).
  void shift_origin(const Vec3& offset);
  [[nodiscard]] const Terrain* terrain() const { return terrain_.get(); }
  [[nodiscard]] float terrain_restitution() const { return terrain_restitution_; }
  [[nodiscard]] float terrain_friction() const { return terrain_friction_; }
  /// Reserves room for n spheres so that adding them does not reallocate.
  void reserve(std::size_t spheres);

  /// Advances the world by dt * time_scale seconds (split into substeps no longer than
  /// max_substep). dt must be finite and > 0, and the step must need no more than
  /// WorldSettings::max_substeps substeps (check_step; InvalidArgument, world unchanged).
  /// Blocks until done; runs in parallel inside the World's arena; allocates nothing in a
  /// steady state.
  void step(float dt);

  [[nodiscard]] std::size_t sphere_count() const { return spheres_.size(); }
  /// Spans over positions, velocities, radii and inverse masses; no copy (see SphereState).
  [[nodiscard]] SphereState spheres() const;
  /// All per-sphere arrays, including restitution, friction and flags, read-only.
  [[nodiscard]] const SphereSoA& soa() const { return spheres_; }
  /// Dense slot of a handle (index into spheres()), or -1 for a stale handle.
  [[nodiscard]] std::int64_t slot_of(SphereId id) const { return spheres_.slot_of(id); }
  /// Handle of the sphere in dense slot `slot` < sphere_count(), e.g. a Contact's a or b.
  [[nodiscard]] SphereId id_at(std::size_t slot) const { return spheres_.id_at(slot); }
  /// Throws InvalidArgument for a stale handle.
  [[nodiscard]] Vec3 position(SphereId id) const;
  [[nodiscard]] Vec3 velocity(SphereId id) const;
  [[nodiscard]] Vec3 angular_velocity(SphereId id) const;
  [[nodiscard]] std::span<const Plane> planes() const { return planes_; }
  [[nodiscard]] const WorldSettings& settings() const { return settings_; }
  [[nodiscard]] int thread_count() const;

  /// Translational + rotational kinetic energy of all movable spheres, J.
  [[nodiscard]] double kinetic_energy() const;
  /// Total linear momentum of all movable spheres, kg m/s.
  [[nodiscard]] Eigen::Vector3d linear_momentum() const;
  /// Number of non-finite position or velocity components.
  [[nodiscard]] std::size_t nan_count() const;
  /// FNV-1a over the bits of positions and velocities in slot order: equal hashes mean
  /// bitwise equal state.
  [[nodiscard]] std::uint64_t state_hash() const;

  [[nodiscard]] const PhaseTimes& last_phase_times() const { return times_; }
  /// Starts (or stops) recording a per-thread phase trace of every step from now on; clears
  /// what was recorded. Costs two clock reads per block of work while on.
  void enable_trace(bool on) { trace_.enable(on, thread_count()); }
  /// The trace recorded since enable_trace(true): one slice per phase per step per thread.
  [[nodiscard]] const PhaseTrace& trace() const { return trace_; }
  [[nodiscard]] const StepStats& last_step_stats() const { return stats_; }
  /// Contacts of the last step (of its last substep), grouped by solver colour: one array to
  /// scan after step() for sounds or gameplay, no per-contact callback. a and b are dense slots
  /// (id_at gives the handle) until the next step or add/remove; b is kStaticBody for terrain
  /// (feature: the triangle in Terrain::triangles()) or a plane (feature: kPlaneFeature | index).
  /// Contacts are speculative: gap (m) is measured before the step moves anything, and > 0
  /// means the sphere could reach the surface within the step, not that it did (one that
  /// bounced off it moves away along the normal afterwards: see examples/drop_spheres.cpp).
  /// After solving, a contact holds its impulses (N s): bounce_impulse, the sum of what the
  /// collision passes gave it (the bounce: about (1 + e) m v_closing on static ground, 0 for a
  /// contact that only rested), and normal_impulse, the resting impulse (about m g dt under a
  /// sphere lying still); tx, ty, tz the resting friction. A sound wants bounce_impulse. Impacts
  /// taken at their exact time outside the solve (planes met during the step, continuous
  /// collision) are not contacts: last_impacts() lists them. No copy, no allocation; valid
  /// until the next step.
  [[nodiscard]] std::span<const Contact> last_contacts() const { return contacts_; }
  /// Impacts of the last step (of its last substep) resolved at their exact time outside the
  /// contact solve, each with its normal impulse: first those of continuous collision (fast
  /// spheres against terrain, planes and spheres; StepStats::sweep), in the order they were
  /// taken (by time), then spheres that reached a plane during the step (the integrator splits
  /// the motion there), in slot order. A sphere falling onto a plane bounces here, not in a
  /// contact: planes make contacts only for spheres already touching them. a and b are dense
  /// slots as in last_contacts(). No copy; valid until the next step. The lists grow only
  /// when a step has more impacts than every step before it.
  [[nodiscard]] std::span<const Impact> last_impacts() const { return impacts_; }

 private:
  friend struct StepPipeline;
  static void validate(const WorldSettings& settings);
  /// One pass of the step pipeline over `scaled` (time-scaled) seconds.
  void substep(float scaled);
  std::size_t require_slot(SphereId id) const;
  /// Lifts the movable spheres of slots [unchecked_from_, n) whose centre is below the terrain
  /// surface out of it (see set_terrain); returns how many moved.
  std::size_t lift_out_of_terrain();

  WorldSettings settings_;
  std::unique_ptr<tbb::task_arena> own_arena_;
  tbb::task_arena* arena_ = nullptr;
  SphereSoA spheres_;
  std::vector<Plane> planes_;
  std::shared_ptr<const Terrain> terrain_;
  float terrain_restitution_ = 0.5f, terrain_friction_ = 0.5f;
  /// Slots from here on have not been checked against the terrain since they were added (or
  /// the terrain set): lift_out_of_terrain checks them at the start of the next step.
  std::size_t unchecked_from_ = 0;

  // Per-step scratch, reused so that a steady-state step does not allocate.
  std::vector<std::vector<SpherePair>> pair_blocks_;
  std::vector<std::vector<std::uint32_t>> pair_row_scratch_;
  SphereGrid grid_;
  SphereSweep sweep_;
  SphereBvhPairs sphere_bvh_;
  std::vector<std::vector<Contact>> contact_blocks_;
  std::vector<Contact> contacts_;
  std::vector<std::vector<Impact>> impact_blocks_;  ///< integrate: plane impacts per sphere block
  std::vector<Impact> impacts_;                     ///< last_impacts(): sweep's, then impact_blocks_ in order
  std::vector<std::size_t> merge_offsets_;  ///< per detect block: where its contacts start in contacts_
  ContactColouring colouring_;
  std::vector<std::uint32_t> tile_changed_;  ///< solve phase: per solver tile, the latest stamp of its bodies (changed_in_pass)
  TiledColouring tiled_colouring_;          ///< solve phase: colours the solver tiles in parallel
  std::vector<Contact> coloured_contacts_;  ///< solve phase scratch: contacts_ before colour order
  std::vector<SolverBody> solver_bodies_;  ///< solve phase scratch: n bodies and a static one
  ContactBatches contact_batches_;  ///< solve phase scratch: contacts staged for SIMD
  ContactImpulseCache contact_cache_;  ///< last step's impulses, for warm starting
  std::vector<float> block_max_speed_;
  std::vector<SphereExtremes> block_extremes_;  ///< predict: radii and inverse masses per block
  std::vector<std::vector<std::uint32_t>> fast_blocks_;  ///< predict: fast spheres per block
  std::vector<std::uint32_t> fast_;                      ///< this step's fast spheres, slot order
  ContinuousCollision sweep_motion_;
  // Terrain guard (predict -> end of step): where each sphere started and how far (squared) its
  // terrain contacts reached.
  std::vector<float> start_x_, start_y_, start_z_, reach2_;
  std::vector<float> travel_;  // per sphere |v| dt this step (pair margins)
  std::vector<std::uint32_t> moved_at_;  // per sphere: last depenetration (pass, colour) that moved it
  ShockPropagation shock_;  ///< solve phase scratch: levels and contact order of the shock pass
  std::vector<std::uint64_t> reorder_keys_;   ///< Morton re-sort scratch
  std::vector<std::uint32_t> reorder_slots_;  ///< Morton re-sort: new slot k <- old slot
  std::vector<Aabb> reorder_bounds_;          ///< Morton re-sort: box of each block's centres
  std::uint64_t steps_taken_ = 0;
  PhaseTimes times_;
  PhaseTrace trace_;
  StageCrew crew_;  // the solver passes' threads (jobs/stage_crew.h)
  StepStats stats_;
};

}  // namespace hail
