#pragma once
// Continuous collision: spheres that move far in one step compared with their radius ("fast")
// are moved along their straight path event by event, in time order, so that they neither pass
// through the terrain or each other nor bounce from where they were instead of where they hit.
//
// The discrete step (detect, solve) handles every sphere as before, except that a fast sphere
// gets no speculative contacts (only those it already touches): what it will meet during the
// step is found here instead, after the solve and before the integrator. For each fast sphere
// the earliest time of impact (kernel/geometry/swept_sphere.h) against
//   * terrain triangles: its path's box goes into the terrain's flat BVH (the stackless box
//     walk), then the swept-sphere test against each triangle found;
//   * planes;
//   * other spheres, each moving on its own straight path (fast-slow and fast-fast alike):
//     candidates by their path boxes, then the exact quadratic |dp + dv t| = ra + rb. With few
//     fast spheres each scans all n path boxes (SIMD, kernel/ccd/path_box_scan.h); with
//     kSweepBvhMinFast or more, a BVH over all path boxes is built once for the step (the
//     terrain's builder) and walked instead, plus a list of the spheres whose path changed.
// Events are then taken earliest first: both spheres are advanced to the time of impact, the
// impulse with restitution and friction is applied there (kernel/solver/contact_impulse.h's
// solve_impact, the rule the integrator uses for planes), and each sphere goes on with its new
// velocity for the rest of the step. A sphere hit this way follows its new path for the rest of
// the step and is swept against terrain and planes, so a slow sphere knocked into the ground is
// caught too; it is swept against other spheres only if the impact made it fast. A struck
// sphere that stays slow closes on a neighbour by less than the discrete step allows (see
// WorldSettings::fast_travel_fraction), and the next step's contacts resolve that. Sweeping it
// against spheres as well let impacts run through a resting pile sphere by sphere: terrain-rain
// at 1M spheres spent minutes in one step when its top layers (34 m/s, just fast) landed.
// Events whose spheres changed path since they were found are dropped and searched again.
//
// Nothing is lost silently: a sphere that reaches `max_events` impacts in one step stops where
// its last impact left it for the rest of that step (its velocity kept), and is counted in
// SweepStats::capped.
//
// Cost: nothing at all in a step with no fast sphere. Otherwise each search scans the path
// boxes of all n spheres (SIMD, 8 per instruction) and walks the terrain BVH along the path;
// events are processed serially, in a fixed order, so the result does not depend on the thread
// count.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "hail/collision_filter.h"
#include "hail/sphere_soa.h"
#include "hail/step_stats.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/ccd/changed_path_grid.h"
#include "kernel/geometry/fast_motion.h"
#include "kernel/mesh/mesh_set.h"
#include "kernel/solver/step_modes.h"
#include "kernel/terrain/plane_contacts.h"
#include "kernel/terrain/terrain_parts.h"
#include "soa/heap_bytes.h"

namespace hail {

/// From this many fast spheres in a step on, their sphere candidates come from a BVH built over
/// every sphere's path box instead of a scan of all path boxes per fast sphere: the scan wins
/// below it, the BVH above (crossover measured with `hail-bench run bullets --threads 1`:
/// docs/benchmarks.md, "Figures behind the code's choices").
inline constexpr std::size_t kSweepBvhMinFast = 512;

/// Where a sweep's sphere candidates come from; both give the same impacts (tested).
enum class SweepCandidates { Automatic, Scan, Bvh };

/// What swept spheres can hit besides each other.
struct SweepScene {
  const Terrain* terrain = nullptr;
  float terrain_restitution = 0.5f, terrain_friction = 0.5f;
  std::span<const Plane> planes;
  bool sphere_collisions = true;
  /// The substep's modes: rotation (impacts' friction turns spheres; off: linear only) and the
  /// filters (with modes.filtering, filtered sphere pairs are not tried, and a sphere whose
  /// filter rejects modes.ground passes through the terrain and planes).
  StepModes modes{};
  /// A sphere lighter than the one striking it by more than this, pressed by the strike into
  /// the ground or the heavier sphere it hit earlier in the step and still touches, is held by
  /// that backer for the impact (see ContinuousCollision::resolve).
  /// WorldSettings::shock_mass_ratio; infinity: never.
  float hold_mass_ratio = std::numeric_limits<float>::infinity();
  const MeshSet* meshes = nullptr;  ///< null: no meshes
};

class ContinuousCollision {
 public:
  /// Starts a step's sweep of the fast spheres (slots, ascending) over dt. Clears the last
  /// step's marks. Allocates only when the sphere count grows.
  /// `fast_fraction` is is_fast's threshold: a struck sphere that it makes fast is swept
  /// against spheres too. `slots_coherent`: the slots are in a spatially coherent (Morton)
  /// order, so the path-box BVH is built in slot order (BvhSplit::InputOrder, O(n)) instead of
  /// by median splits; its candidates, and so the result, are the same either way.
  void begin(const SphereSoA& spheres, std::span<const std::uint32_t> fast, float dt, float fast_fraction,
             SweepCandidates candidates = SweepCandidates::Automatic, bool slots_coherent = false);
  /// Finds the first event of fast spheres [first, last) (positions in the fast list). Only
  /// reads shared state: ranges may run in parallel.
  void find_first_events(const SphereSoA& spheres, const SweepScene& scene, std::size_t first, std::size_t last);
  /// Takes events earliest first until none is left in the step (serial).
  void resolve(SphereSoA& spheres, const SweepScene& scene, float restitution_threshold, int max_events);
  /// Writes every swept sphere's end-of-step position and velocity, and marks it in moved().
  void finish(SphereSoA& spheres);

  /// moved()[slot] != 0: finish() already moved this sphere over the step (the integrator skips
  /// it). Empty when the step had no fast sphere.
  [[nodiscard]] std::span<const std::uint8_t> moved() const {
    return any_ ? std::span<const std::uint8_t>(moved_) : std::span<const std::uint8_t>();
  }
  [[nodiscard]] const SweepStats& stats() const { return stats_; }
  /// This step's impacts that applied an impulse, in the order resolve() took them (by time).
  [[nodiscard]] std::span<const Impact> impacts() const { return impacts_; }
  [[nodiscard]] std::size_t fast_count() const { return fast_count_; }

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(motions_, motion_of_, moved_, first_events_, heap_, path_boxes_, path_bvh_.nodes, path_bvh_.primitive_order, impacts_) + changed_paths_.heap_bytes();
  }

 private:
  enum class Target : std::uint8_t { Terrain, Plane, Mesh, Sphere };
  struct Motion {
    double x[3];  ///< centre at time t0
    double v[3];  ///< velocity since t0
    double t0;
    std::uint32_t slot;
    std::uint32_t version;  ///< +1 at every impact: events found before it are stale
    int events;
    bool stopped;        ///< reached max_events: stays at x for the rest of the step
    bool meets_spheres;  ///< its search includes other spheres: fast at the start or after an impact
    /// What it last hit this step (the terrain or a plane: kStaticBody; else a sphere's slot),
    /// unless that impact was one in which it was held; kNoBacker before any impact.
    std::uint32_t backer;
    double back_x[3];  ///< centre at that impact
    double back_n[3];  ///< its normal, from this sphere into what it hit
  };
  static constexpr std::uint32_t kNoBacker = kStaticBody - 1;
  struct Event {
    double t;
    std::uint32_t motion;   ///< index in motions_
    std::uint32_t version;  ///< motions_[motion].version when found
    Target target;
    std::uint32_t other;          ///< triangle (BVH order), plane index or sphere slot
    std::uint32_t other_version;  ///< the other sphere's version when found
    double n[3];                  ///< for static targets: contact normal into the surface
  };
  static bool later(const Event& a, const Event& b);
  /// A light sphere struck into what it hit before in the step (its backer: the ground, or a
  /// sphere heavier than it by hold_mass_ratio), that it still touches, is held by it. Taken
  /// pair by pair, a pebble on the ground struck from above was driven into the ground, thrown
  /// back up into the striker, and so on, impact after impact (the striker hardly slowed),
  /// until max_events stopped it and the striker ended the step inside it (1.7 of its radius:
  /// hail-bench stress, small-under-big-rain); the same between two heavy spheres.
  struct Hold {
    double into[3];      ///< unit normal from the held sphere into its backer
    double backer_v[3];  ///< the backer's velocity (0 for the ground)
  };
  /// Whether motion m, struck by sphere `striker` with an impulse along `push` (unit, on m's
  /// sphere) at time t, is held by its backer; if so, `hold` says how.
  [[nodiscard]] bool held_by_backer(const SphereSoA& s, std::uint32_t m, std::uint32_t striker, const double push[3],
                                    double t, float ratio, Hold& hold) const;
  /// The strike on a held sphere: it meets it bound to its backer along their normal g (moving
  /// with the backer along g, by its own mass across it), without friction, and a sphere
  /// backer takes the impulse's part along g. What the impacts one by one converge to, in one.
  void strike_held(SphereSoA& s, const SweepScene& scene, const Contact& c, double t, std::uint32_t held,
                   std::uint32_t striker, const Hold& hold, float restitution_threshold, int max_events);
  /// Motion m's sphere hit `hit` (kStaticBody: the ground) with normal `into` (unit, towards
  /// what it hit): its backer for a later strike.
  void remember(std::uint32_t m, std::uint32_t hit, const double into[3]);
  /// Moves motion m along its path to time t.
  void advance(std::uint32_t m, double t);
  /// Lists an impact with impulse > 0 for World::last_impacts (a's centre at its time, the
  /// normal from a to b).
  void record_impact(const SphereSoA& s, const Contact& c, double t, const double a_centre[3], const double n[3],
                     float impulse);

  [[nodiscard]] Event earliest_event(const SphereSoA& s, const SweepScene& scene, std::uint32_t m) const;
  void centre_at(const SphereSoA& s, std::uint32_t slot, double t, double out[3], double v[3]) const;
  [[nodiscard]] std::uint32_t version_of(std::uint32_t slot) const;
  /// When the sphere's current straight path began: its last impact this step, else 0.
  [[nodiscard]] double path_start(std::uint32_t slot) const;
  /// The motion of `slot`, started on its current path if it has none (meets_spheres false).
  std::uint32_t activate(const SphereSoA& s, std::uint32_t slot);
  void push(const Event& e);
  /// Writes a swept sphere's current path into the SoA as the line p + v t it now follows
  /// (p extrapolated back to t = 0), so that the SIMD path scan sees it like any other sphere.
  /// The SoA holds the real end-of-step state again after finish().
  static void sync_path(SphereSoA& s, const Motion& mo);
  /// Motion m goes on at velocity vnew after an impact: a new version (its pending events go
  /// stale), counted against max_events, synced into the SoA and listed as changed.
  void take_new_path(SphereSoA& s, std::uint32_t m, const float vnew[3], int max_events);
  /// Lists motion m's new path in changed_paths_ (use_bvh_).
  void list_changed_path(const SphereSoA& s, std::uint32_t m);

  double dt_ = 0;
  float fast_fraction_ = 1.0f;
  bool any_ = false;
  std::size_t fast_count_ = 0;
  std::vector<Motion> motions_;
  std::vector<std::int32_t> motion_of_;  ///< slot -> index in motions_, or -1
  std::vector<std::uint8_t> moved_;
  std::vector<Event> first_events_;  ///< find_first_events' results, one per fast sphere
  std::vector<Event> heap_;          ///< pending events, earliest on top
  bool use_bvh_ = false;             ///< this step's sphere candidates come from path_bvh_
  std::vector<Aabb> path_boxes_;     ///< every sphere's path box over the step (use_bvh_)
  FlatBvh path_bvh_;                 ///< over path_boxes_; stale for spheres whose path changed
  /// Paths changed since begin, by box (use_bvh_). Mutable: earliest_event queries it, and it
  /// is only written (and queried: the first events see it empty) in the serial resolve().
  mutable ChangedPathGrid changed_paths_;
  SweepStats stats_;
  std::vector<Impact> impacts_;  ///< this step's, for World::last_impacts
};

}  // namespace hail
