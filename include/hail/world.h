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

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <oneapi/tbb/task_arena.h>
#include <Eigen/Core>

#include "hail/collision_filter.h"
#include "hail/contact.h"
#include "hail/debug_draw.h"
#include "hail/errors.h"
#include "hail/events.h"
#include "hail/phase_trace.h"
#include "hail/plane.h"
#include "hail/queries.h"
#include "hail/snapshot.h"
#include "hail/sphere_soa.h"
#include "hail/step_stats.h"
#include "hail/terrain.h"
#include "hail/triangle_mesh.h"
#include "hail/vec3.h"
#include "hail/world_settings.h"

namespace hail {

class MeshSet;         // kernel/mesh/mesh_set.h
struct StepScratch;    // kernel/world/step_scratch.h
struct WorldServices;  // kernel/world/world_services.h

/// How many substeps World::step(dt) splits a step into under `settings`:
/// ceil(time_scale * dt / max_substep), at least 1; 0 when time_scale is 0 (nothing moves).
/// Computed in double, so it never overflows: a count beyond INT64_MAX is returned as
/// INT64_MAX. Throws InvalidArgument unless dt is finite and > 0 and dt * time_scale is 0 or at
/// least kMinStep. Needs no World: a scene
/// reader or a command line can call it to refuse a dt (with check_step) before it builds one.
[[nodiscard]] std::int64_t substeps_needed(const WorldSettings& settings, float dt);

/// Throws InvalidArgument exactly when World::step(dt) under `settings` would: dt not finite
/// or not > 0, dt * time_scale below kMinStep (but time_scale 0), or substeps_needed(settings, dt) > settings.max_substeps (the message gives dt,
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
/// |World::set_gravity_scale| at most this: a sphere's gravity stays within a million g's.
inline constexpr float kMaxGravityScale = 1e6f;

/// Resolution: a float cannot place a point more finely than the spacing of floats at its
/// coordinates (2^-23 of their magnitude), so far from the origin small things blur. add_sphere
/// requires the spacing at the sphere's largest |coordinate| to be at most radius /
/// kSphereRadiusResolution: contacts, the depenetration slop and the stress battery's bounds
/// are a few percent of a radius, and the overlaps grow with the spacing: at a spacing of r / 32
/// terrain-rain's terrain moved out broke the stress battery's 5% bound, at r / 64 it held
/// (hail-bench stress: docs/benchmarks.md, "Figures behind the code's choices"). A sphere of radius
/// 0.5 may so be placed up to 2^17 = 131,072 m out, one of radius 1e-6 within 0.25 m. The
/// check is made when a sphere is added; a step does not stop a sphere flying further.
inline constexpr float kSphereRadiusResolution = 64.0f;
/// set_terrain requires the spacing of floats at the terrain's largest |coordinate| (its
/// corners' x and z, its highest and lowest heights) to be at most the smaller cell size /
/// kTerrainCellResolution: a point's cell and place in it, (x - origin) / cell, then err by at
/// most 1/64 of a cell. At 3e7 m with 1 m cells (spacing 2 m) cells collapsed to zero width and
/// every value turned NaN once a sphere landed. 1 m cells may lie up to 2^18 = 262,144 m out.
inline constexpr float kTerrainCellResolution = 64.0f;

/// A new sphere. Mass must be > 0 unless `is_static` (then it never moves) or `is_kinematic`
/// (then the game moves it). Radius, mass, speed and spin within the limits above.
struct SphereDesc {
  Vec3 position{0.0f, 0.0f, 0.0f};          ///< m; resolvable for the radius (kSphereRadiusResolution)
  Vec3 velocity{0.0f, 0.0f, 0.0f};          ///< m/s
  Vec3 angular_velocity{0.0f, 0.0f, 0.0f};  ///< rad/s; must be zero when WorldSettings::rotation is off
  float radius = 0.5f;                      ///< m, in [kMinSphereRadius, kMaxSphereRadius]
  float mass = 1.0f;                        ///< kg, in [kMinSphereMass, kMaxSphereMass] (ignored when is_static)
  float restitution = 0.5f;                 ///< [0, 1]
  float friction = 0.5f;                    ///< Coulomb coefficient, >= 0
  bool is_static = false;                   ///< infinite mass: collides but never moves
  /// Infinite mass, moved by its velocity (set_velocity, move_kinematic) alone: it pushes
  /// dynamic spheres and is not pushed, feels no gravity or force, and passes through terrain
  /// and planes (a paddle, a moving platform, a wrecking ball). Not together with is_static.
  bool is_kinematic = false;
  /// Category and mask bits: it collides with what its mask accepts and what accepts it
  /// (collision_filter.h). The default collides with everything.
  CollisionFilter filter{};
};

/// A static plane: the solid half-space {x : normal . x < offset}. The normal is normalised.
struct PlaneDesc {
  Vec3 normal{0.0f, 1.0f, 0.0f};
  float offset = 0.0f;  ///< m
  float restitution = 0.5f;
  float friction = 0.5f;
};

/// Read-only views of the dense sphere state, in slot order (World::slot_of maps a handle to
/// its slot, World::id_at a slot to its handle). No copy: the spans point into the World's SoA
/// arrays, so reading them costs nothing and they see every later step. They stay valid until
/// a call adds or removes spheres (or reserve() grows the arrays); restore() keeps them valid
/// when the snapshot holds as many spheres as the World had (or fewer and the spans are cut to
/// them; more than the arrays have room for reallocates); a step keeps them valid but
/// may move spheres to other slots (the Morton re-sort, every reorder_interval steps), so look
/// a handle's slot up again after each step. Units: m, m/s, rad/s, m, 1/kg (0: static).
struct SphereState {
  std::span<const float> px, py, pz, vx, vy, vz, wx, wy, wz, radius, inv_mass;
};

/// Heap bytes a World holds, by part (World::memory_use): capacities, the room its buffers keep
/// so that a steady-state step allocates nothing. The terrain is apart (Terrain::memory_bytes).
struct MemoryUse {
  std::size_t spheres = 0;     ///< the sphere arrays (SphereSoA) and handle tables
  std::size_t pairs = 0;       ///< the pair search: per-block pair lists, grid, sorted axis, sphere BVH
  std::size_t contacts = 0;    ///< contact lists (per block, merged, in colour order) and impacts
  std::size_t solver = 0;      ///< colouring, solver bodies, SIMD contact batches, shock levels
  std::size_t warm_start = 0;  ///< last step's impulses, kept for warm starting
  std::size_t sweep = 0;       ///< continuous collision and the fast-sphere lists
  std::size_t per_sphere = 0;  ///< the step's other per-sphere arrays (guard, integrator, travel, re-sort)
  std::size_t services = 0;    ///< events, sleeping islands, the queries' BVH, apply_impulses' undo
  /// Calls f(name, bytes) for each part above, in this order (the names of hail-bench's JSON
  /// and of Python's World.memory_use()).
  template <class F>
  void for_each_part(F&& f) const {
    f("spheres", spheres), f("pairs", pairs), f("contacts", contacts), f("solver", solver);
    f("warm_start", warm_start), f("sweep", sweep), f("per_sphere", per_sphere), f("services", services);
  }
  [[nodiscard]] std::size_t total() const {
    std::size_t sum = 0;
    for_each_part([&](const char*, std::size_t bytes) { sum += bytes; });
    return sum;
  }
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
  void set_terrain(std::shared_ptr<const Terrain> terrain, float restitution = 0.5f, float friction = 0.5f);
  /// Moves the world's origin to `offset`: every sphere's position (static ones too) becomes
  /// position - offset, every plane, the terrain and the meshes move with them, and velocities, spins,
  /// handles and warm-start impulses are kept, so the motion goes on as before, only where
  /// floats are finer. PhysX's PxScene::shiftOrigin: a game whose action wanders far (floats at
  /// 1e5 m are 7.8 mm apart) moves it back near the origin now and then, e.g. when the player
  /// is past 1-2 km out (docs/embedding.md, "Keeping the action near the origin").
  /// Cost: O(spheres + planes), plus each mesh's collider rebuilt at its position - offset, plus
  /// a new Terrain built from terrain()->moved(-offset) (its
  /// BVH rebuilt: docs/benchmarks.md, `hail-bench bvh-build`), which this World then holds instead of the
  /// shared one. Warm-start impulses are kept unless the moved terrain's BVH orders its
  /// triangles differently (then they are dropped, as after set_terrain). last_contacts() is
  /// unchanged (it holds no positions); last_impacts() points move too.
  /// Exactness: a coordinate p becomes p - o exactly when o is a multiple of p's float spacing
  /// (any whole number of metres for |p| < 2^24 m) and |p - o| is below the power of two above
  /// |p|. So bringing the action back towards the origin by whole metres is exact; moving it
  /// out rounds each coordinate once, to half the spacing where it lands.
  /// Throws InvalidArgument (world unchanged) for a non-finite offset, a plane offset that would
  /// leave float range, a sphere that would land where add_sphere would refuse to place it
  /// (kSphereRadiusResolution; a sphere already past that rule may only be brought nearer), or a
  /// terrain that set_terrain would refuse where it lands (kTerrainCellResolution).
  void shift_origin(const Vec3& offset);
  /// Adds a static triangle mesh (include/hail/triangle_mesh.h) placed by `transform`, with its
  /// material; returns its index (0, 1, ... in the order added; TouchEvent::surface and
  /// HitEvent::surface name it with ContactWith::Mesh). The World keeps its own collider: the
  /// triangles in world coordinates, their internal edges and a flat BVH, built on the calling
  /// thread (O(n log n) in the triangles, about 150 bytes a triangle: mesh_memory_bytes). Spheres
  /// meet a mesh as they meet the terrain: speculative contacts with the terrain's reduction and
  /// internal-edge rule, bounces at their time, continuous collision of fast spheres, the guard,
  /// the ground filter, and the ray and sphere-cast queries (QueryHitKind::Mesh); mesh_triangles
  /// draws them (docs/meshes.md says what a closed mesh and a shell each do). Not yet: lift-out
  /// of a sphere added inside a solid. shift_origin moves meshes with everything else. A
  /// snapshot holds each mesh's content hash: restore wants the same meshes, added in the same
  /// order. Throws InvalidArgument (world unchanged) for a bad transform or material, a mesh with
  /// no triangle of non-zero area where it is placed, or more than 2^30 mesh triangles in all.
  /// Wakes every sleeper.
  std::size_t add_mesh(const TriangleMesh& mesh, const MeshTransform& transform = {}, float restitution = 0.5f,
                       float friction = 0.5f);
  /// Meshes added (add_mesh).
  [[nodiscard]] std::size_t mesh_count() const;
  /// Heap bytes the meshes' colliders hold (apart from memory_use, as the terrain's).
  [[nodiscard]] std::size_t mesh_memory_bytes() const;
  /// Deepest overlap (m, >= 0) of a sphere at `centre` with radius r with any mesh: for error
  /// reports (the way Terrain::penetration serves the terrain).
  [[nodiscard]] float mesh_penetration(const Vec3& centre, float radius) const;
  [[nodiscard]] const Terrain* terrain() const { return terrain_.get(); }
  [[nodiscard]] float terrain_restitution() const { return terrain_restitution_; }
  [[nodiscard]] float terrain_friction() const { return terrain_friction_; }
  /// The static world's collision filter: one for the terrain and every plane together
  /// (collision_filter.h, Box2D's rule with each sphere's). A sphere whose filter rejects it
  /// passes through the ground: no contacts, plane bounces, swept impacts, terrain guard or
  /// lift-out. The default collides with everything. Takes effect from the next step.
  void set_ground_filter(CollisionFilter filter);
  [[nodiscard]] CollisionFilter ground_filter() const { return ground_filter_; }
  /// Reserves room for n spheres so that adding them does not reallocate. Throws
  /// InvalidArgument for more than SphereSoA::kMaxSpheres, std::bad_alloc when memory runs
  /// out; the world keeps every sphere and stays usable either way.
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
  /// Handle of every dense slot, in slot order (slot k's is id_at(k)): one array for a game
  /// that walks spheres() and wants to know whose each entry is. No copy; valid (pointing at
  /// the current handles) across steps and restores as spheres() is (SphereState), but a step
  /// may re-sort the slots and so the handles in them.
  [[nodiscard]] std::span<const SphereId> handles() const { return spheres_.handles(); }
  /// The game's 64-bit value for a sphere (set_user_data; 0 until set). Throws for a stale handle.
  [[nodiscard]] std::uint64_t user_data(SphereId id) const;
  /// The sphere's category and mask bits. Throws for a stale handle.
  [[nodiscard]] CollisionFilter collision_filter(SphereId id) const;

  // ---- Driving spheres from a game (kernel/world/world_control.cpp) ----
  // Each call checks its handle (a stale one throws InvalidArgument) and its value by the rule
  // add_sphere uses for the same quantity (finite; radius, mass, speed and spin within the
  // limits above; positions resolvable for the radius; spin zero without rotation), and throws
  // InvalidArgument naming the value with the world unchanged. Velocity limits apply to the
  // velocity a call leaves: an impulse that would take a sphere past kMaxSphereSpeed is refused.
  // Static spheres stay static: set_velocity, set_angular_velocity and set_mass on one throw
  // (it has no mass and never moves), while impulses, forces and torques on one are checked
  // and then ignored (a push on the immovable: the game need not ask what it hit first).
  // Kinematic spheres take set_velocity and set_angular_velocity (that is how they move) and,
  // like static ones, refuse set_mass and ignore impulses, forces and torques.

  /// Teleports a sphere. Its warm-start impulses are dropped (ContactImpulseCache::forget), so
  /// the next step gives it nothing it had where it was; its velocity is kept. Costs
  /// O(spheres + last step's contacts): teleport many at once with set_positions. Not lifted
  /// out of the terrain (a centre put inside a hill stays there: place it above).
  void set_position(SphereId id, const Vec3& position);
  void set_velocity(SphereId id, const Vec3& velocity);
  /// Refused when WorldSettings::rotation is off and the value is not zero.
  void set_angular_velocity(SphereId id, const Vec3& angular_velocity);
  /// v += impulse / m (N s, at the centre).
  void apply_impulse(SphereId id, const Vec3& impulse);
  /// An impulse at a world point: v += impulse / m and, with rotation on, w += (r x impulse) / I,
  /// r = point - centre, I = 0.4 m r^2 (solid sphere). Without rotation only the linear part.
  void apply_impulse_at(SphereId id, const Vec3& impulse, const Vec3& world_point);
  /// Adds to the force (N) / torque (N m) that the next step applies: v += F dt / m (w += T dt / I)
  /// in each of its substeps, before gravity; the step then zeroes them (also a step that
  /// moves nothing: time_scale 0). Refused when the sum would not be finite; a non-zero torque
  /// is refused without rotation.
  void apply_force(SphereId id, const Vec3& force);
  void apply_torque(SphereId id, const Vec3& torque);
  void set_restitution(SphereId id, float restitution);
  void set_friction(SphereId id, float friction);
  /// Movable spheres only; the inertia follows (0.4 m r^2). Velocities are kept.
  void set_mass(SphereId id, float mass);
  /// The inertia follows for a movable sphere. Refused where floats at its position cannot
  /// resolve the new radius. The sphere grows in place: an overlap it makes is pushed apart
  /// by the next steps as any overlap is.
  void set_radius(SphereId id, float radius);
  /// The sphere's gravity becomes WorldSettings::gravity * scale (default 1; 0 floats, -1
  /// rises); |scale| <= kMaxGravityScale.
  void set_gravity_scale(SphereId id, float scale);
  void set_user_data(SphereId id, std::uint64_t value);
  /// Category and mask bits (collision_filter.h); any bits are accepted (a category of 0
  /// collides with nothing). Takes effect from the next step.
  void set_collision_filter(SphereId id, CollisionFilter filter);

  /// Whether the sphere is kinematic (SphereDesc::is_kinematic). Throws for a stale handle.
  [[nodiscard]] bool is_kinematic(SphereId id) const;
  /// Makes a dynamic or static sphere kinematic: infinite mass from now on, its velocity kept
  /// (a static one's is zero), its pending force and torque dropped.
  void set_kinematic(SphereId id);
  /// Makes a kinematic or static sphere dynamic with this mass (inertia 0.4 m r^2), its
  /// velocities kept; on a dynamic sphere it is set_mass.
  void set_dynamic(SphereId id, float mass);
  /// Sets a kinematic sphere's velocity to (target - position) / dt, so that a step covering dt
  /// of simulated time (step(dt) at time_scale 1) ends it at `target`, pushing what is in the
  /// way (Jolt's MoveKinematic). The velocity stays after the step: call again each step, or
  /// set_velocity to zero to stop it. Refused (nothing changed) for a sphere that is not
  /// kinematic, dt not finite and > 0, a target not finite or not resolvable for the radius,
  /// or a velocity over kMaxSphereSpeed. A kinematic sphere that meets more than
  /// WorldSettings::max_sweep_events spheres in one swept step stops short (SweepStats::capped).
  void move_kinematic(SphereId id, const Vec3& target, float dt);

  /// Batch forms: handles[k] gets values[k]. Every handle and value is checked first, then all
  /// are applied: a refusal (sizes differ, a stale handle, a bad value, naming its index)
  /// leaves the world unchanged. A handle listed twice: set_* keep the last value,
  /// apply_impulses adds both (and the limits are checked on the sum). set_positions drops
  /// the warm-start impulses of all the moved spheres in one pass.
  void set_positions(std::span<const SphereId> handles, std::span<const Vec3> positions);
  void set_velocities(std::span<const SphereId> handles, std::span<const Vec3> velocities);
  void apply_impulses(std::span<const SphereId> handles, std::span<const Vec3> impulses);

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
  [[nodiscard]] std::span<const Contact> last_contacts() const;
  /// The pair grid the last step searched (its last substep's), as the boxes of the cells
  /// that held a sphere (each once; include/hail/debug_draw.h), into `out`; empty unless that
  /// step ran the grid search (StepStats::pair_search). The cells are where the spheres were
  /// when the grid was built, before the step moved them: cubes two reaches (largest diameter
  /// plus the step's margin) wide, counted from the lowest centre on each axis
  /// (kernel/broadphase/sphere_grid.h). For drawing (hail-view --draw-grid): allocates.
  void pair_grid_cells(std::vector<DebugBox>& out) const;
  /// Every mesh's triangles in world coordinates (corners and unit normal from the winding),
  /// meshes in the order added, each in its BVH order: entry k is the triangle QueryHit::triangle
  /// k names. Into `out` (replacing what it held). For drawing (hail-view): allocates.
  void mesh_triangles(std::vector<TerrainTriangle>& out) const;
  // ---- Touch and hit events (include/hail/events.h; kernel/world/world_events.cpp) ----

  /// Turns touch and hit events on or off (both off by default; off, a step does nothing for
  /// them). Throws InvalidArgument (nothing changed) unless hit_speed is finite and >= 0.
  /// Turning touch on starts from nothing touching (the next step begins every touch it finds);
  /// turning it off forgets the touches. After each step:
  /// - Touching, in a step: in some substep, a contact that ended the solve with an impulse
  ///   (normal, friction or bounce) or began it overlapping (gap <= 0), or an impact of
  ///   last_impacts(). A sphere resting under gravity carries an impulse every step, so it
  ///   begins once and never flickers (the gap after a step is not the rule: in a settled pile
  ///   it flickers with rounding, and misses a bounce within a step). A sphere that bounces
  ///   within one step touches in that step and ends in the next.
  /// - touch_begin_events: touching now and not after the previous step; touch_end_events: the
  ///   reverse. Substeps are one step: a touch that begins and ends within a step's substeps
  ///   begins in it and ends in the next. A removed sphere's touches end at the next step
  ///   (also a step with time_scale 0, which keeps every other touch).
  /// - hit_events: every impact of the step (all substeps) that closed faster than hit_speed
  ///   (strictly): each contact the collision passes bounced (Contact::bounce_impulse > 0),
  ///   with the approach speed of its spheres' velocities as the solve began (after gravity)
  ///   and the point a's radius plus the gap (half the gap between spheres) along the normal
  ///   from a's centre; and each of last_impacts() (continuous collision, spheres meeting a
  ///   plane mid-step), with the approach speed its impulse was made from (to float rounding)
  ///   and its point.
  /// Order: sphere pairs by (lower handle index, higher), then ground by (handle index, the
  /// terrain before plane 0, 1, ...); hits of one key in the order they happened. The same on
  /// any thread count, bitwise. Steady steps allocate nothing.
  void set_events(const EventSettings& settings);
  [[nodiscard]] const EventSettings& event_settings() const;
  /// The last step's events: no copy; valid until the next step or set_events. Empty when off.
  [[nodiscard]] std::span<const TouchEvent> touch_begin_events() const;
  [[nodiscard]] std::span<const TouchEvent> touch_end_events() const;
  [[nodiscard]] std::span<const HitEvent> hit_events() const;

  // ---- Sleeping (WorldSettings::sleep; kernel/world/sleep_islands.h) ----

  /// Whether the sphere sleeps: at rest with its island, its velocities zero, left out of the
  /// step until a contact with a moving sphere, a control call (every setter, impulse and force
  /// but set_user_data), removing a sphere of its island or an immovable one it rests on, or a
  /// change of the ground (set_terrain, add_plane, set_ground_filter, shift_origin) wakes it.
  /// A game can stop drawing updates for it. Always false with sleeping off. Throws
  /// InvalidArgument for a stale handle.
  [[nodiscard]] bool is_sleeping(SphereId id) const;
  /// Spheres that fell asleep in the last step, and spheres woken since the step before it (by
  /// the last step, or by a call made before it), each sorted by handle index, each sphere once
  /// (a sphere may be in both: woken, then asleep again). No copy; valid until the next step.
  /// Empty with sleeping off. A sleeper's contacts are left out of last_contacts(), but its
  /// touches go on (no touch_end_events) until it wakes.
  [[nodiscard]] std::span<const SphereId> sleep_events() const;
  [[nodiscard]] std::span<const SphereId> wake_events() const;

  // ---- Snapshots (include/hail/snapshot.h; kernel/world/snapshot_writer.cpp, snapshot_reader.cpp) ----

  /// Replaces `out`'s contents with a snapshot of everything that decides the world's future:
  /// the sphere arrays, handles and free list, the warm-start cache, the step count (the
  /// re-sort's phase), pending forces, the settings (all but threads), planes, the touch-event
  /// state and the terrain's content hash (docs/embedding.md, "Snapshots"). O(spheres +
  /// remembered contacts); allocates `out`'s room only when it grows.
  void save(std::vector<std::byte>& out) const;
  /// save() into a file: written beside it, flushed to the disk (fsync), then renamed over it,
  /// so that a failure (a full disk, a crash) leaves the old file whole. Throws FileError
  /// (naming the file and what failed) when it cannot be written.
  void save_file(const std::string& path) const;
  /// Makes this World the one saved: after it, N steps give bitwise the state the saved world
  /// had after N steps, on any thread count (this World keeps its own threads or arena) and any
  /// SIMD path. The same terrain must be attached (set_terrain; or none, if it had none).
  /// Throws InvalidArgument naming the problem, with the world unchanged, for a snapshot that
  /// is truncated, corrupt (checksum), of a newer format version, of another terrain, or
  /// inconsistent. The last step's contacts, impacts, events and stats are emptied. The
  /// sphere arrays are overwritten in place (grown first if the snapshot holds more spheres
  /// than they have room for), so spans from spheres() and handles() stay valid: a rollback
  /// reads the restored state through them.
  void restore(std::span<const std::byte> snapshot);
  /// restore() from a file; throws FileError (naming the file) when it cannot be read or is
  /// not a regular file (a FIFO, a device, a folder: refused before it is opened).
  void restore_file(const std::string& path);

  /// Impacts of the last step (of its last substep) resolved at their exact time outside the
  /// contact solve, each with its normal impulse: first those of continuous collision (fast
  /// spheres against terrain, planes and spheres; StepStats::sweep), in the order they were
  /// taken (by time), then spheres that reached a plane during the step (the integrator splits
  /// the motion there), in slot order. A sphere falling onto a plane bounces here, not in a
  /// contact: planes make contacts only for spheres already touching them. a and b are dense
  /// slots as in last_contacts(). No copy; valid until the next step. The lists grow only
  /// when a step has more impacts than every step before it.
  [[nodiscard]] std::span<const Impact> last_impacts() const;

  // ---- World queries (include/hail/queries.h; kernel/world/world_queries.cpp) ----
  // Rays, swept spheres and overlaps against the spheres (as they are now), the terrain and the
  // planes; each takes a QueryFilter. Spheres are found through a BVH over their boxes
  // (kernel/bvh/sphere_query_bvh.h), built at the first query after any change to the spheres
  // (step, add/remove, set_position(s), set_radius, set_collision_filter, shift_origin) and
  // reused until the next: O(n log n) on the calling thread, 1.3 s for a million spheres (2-core EPYC)
  // (hail-bench rays prints it); query_cache_builds() counts the builds. Queries are const and
  // change no physics state; the cache is built under a mutex, so const methods, queries
  // included, may still run at the same time as each other. Bad input (a non-finite origin or
  // centre, a zero or non-finite direction, a NaN or negative distance or radius, a box with
  // min > max) throws InvalidArgument naming the value. A ray or sphere starting inside a
  // sphere or a plane's solid hits it at distance 0 (normal against the direction, or the
  // plane's); the terrain is a surface: a ray meets either face, a swept sphere only the upper.

  /// Closest hit of the ray (hit_before breaks distance ties), or nullopt.
  [[nodiscard]] std::optional<QueryHit> raycast(const Ray& ray, const QueryFilter& filter = {}) const;
  /// Every hit along the ray, sorted by hit_before (each sphere, triangle and plane once).
  [[nodiscard]] std::vector<QueryHit> raycast_all(const Ray& ray, const QueryFilter& filter = {}) const;
  /// raycast for each ray: hits[k] for rays[k] (sizes must match). Blocks of rays run in parallel
  /// in the World's arena; results are bitwise raycast's on any thread count. Allocates only to build the BVH.
  void raycast_batch(std::span<const Ray> rays, std::span<std::optional<QueryHit>> hits,
                     const QueryFilter& filter = {}) const;
  /// First hit of a sphere of `radius` swept along the ray (point: where it touches, normal out
  /// of what it hit), or nullopt. Against the terrain: kernel/geometry/swept_sphere.h's test.
  [[nodiscard]] std::optional<QueryHit> sphere_cast(const Ray& ray, float radius, const QueryFilter& filter = {}) const;
  /// Every sphere that touches the ball (centre, radius) (|c - centre| <= r + radius), by handle index.
  [[nodiscard]] std::vector<SphereId> overlap_sphere(const Vec3& centre, float radius,
                                                     const QueryFilter& filter = {}) const;
  /// Every sphere that touches the closed box [min, max], by handle index.
  [[nodiscard]] std::vector<SphereId> overlap_box(const Vec3& min, const Vec3& max,
                                                  const QueryFilter& filter = {}) const;
  /// How many times the query BVH over the spheres has been built (diagnostics, tests).
  [[nodiscard]] std::uint64_t query_cache_builds() const;
  /// Heap bytes held, by part (MemoryUse). O(blocks); reads nothing a step writes concurrently,
  /// so call it between steps.
  [[nodiscard]] MemoryUse memory_use() const;

  /// Checks `settings` as the constructor and restore do: InvalidArgument naming the first
  /// field out of its range (include/hail/settings_table.h) or a rule between fields. A settings
  /// UI or a command line can refuse a value this way before it builds a World.
  static void validate(const WorldSettings& settings);

 private:
  /// One pass of the step pipeline over `scaled` (time-scaled) seconds.
  void substep(float scaled);
  std::size_t require_slot(SphereId id) const;
  /// require_slot, also refusing a static sphere for `what` (it has no mass, never moves).
  std::size_t require_movable(SphereId id, const char* what) const;
  /// require_slot, also refusing a static sphere or a kinematic one (neither has a mass).
  std::size_t require_dynamic(SphereId id, const char* what) const;
  /// Sleeping on: wakes slot's island, and if it is immovable the islands resting on it
  /// (SleepIslands::wake_around); every control call on a sphere calls it.
  void wake(std::size_t slot);
  /// Sleeping on: wakes every sleeper (the ground changed).
  void wake_all();
  /// Zeroes the force and torque accumulators if any call filled them (after each step).
  void clear_forces();
  /// Recomputes gravity_scaled_ and filtered_ (one pass over the spheres) if a change may have
  /// cleared them since the last step (the step start calls it).
  void refresh_uses();
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
  std::unique_ptr<MeshSet> meshes_;  ///< null until the first add_mesh
  [[nodiscard]] bool has_meshes() const;
  /// Slots from here on have not been checked against the terrain since they were added (or
  /// the terrain set): lift_out_of_terrain checks them at the start of the next step.
  std::size_t unchecked_from_ = 0;

  /// The step's scratch (pair blocks, contact lists, colourings, solver bodies and batches, the
  /// warm-start cache, the sweep, reorder keys, the solver's threads: kernel/world/step_scratch.h),
  /// reused so that a steady-state step does not allocate; and the services the World keeps
  /// between steps (events, sleeping islands, the queries' cache, apply_impulses' undo:
  /// kernel/world/world_services.h). Behind pointers so that this header needs none of the
  /// kernel's internal headers.
  std::unique_ptr<StepScratch> scratch_;
  std::unique_ptr<WorldServices> services_;
  std::uint64_t steps_taken_ = 0;
  /// apply_force / apply_torque filled an accumulator since the last step: the step applies
  /// them and re-sorts them (when false they are all zero, and both are skipped).
  bool forces_pending_ = false;
  /// Some sphere's gravity scale is not 1: the step takes the scaled gravity loop. Some
  /// sphere's collision filter, or the ground's, is not the default, or some sphere is
  /// kinematic (it passes through the ground as a filtered sphere does): the step filters. When
  /// false the step runs exactly the code of a world without scales or filters (their cost is
  /// paid only by scenes that use them). Set at once by a change that makes them true; a change
  /// that may make them false marks them stale, and refresh_uses recounts at the next step.
  bool gravity_scaled_ = false, filtered_ = false;
  bool uses_stale_ = false;
  CollisionFilter ground_filter_{};
  PhaseTimes times_;
  PhaseTrace trace_;
  StepStats stats_;
};

}  // namespace hail
