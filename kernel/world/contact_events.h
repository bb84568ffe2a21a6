#pragma once
// Touch and hit events (include/hail/events.h): everything World keeps for them, in one place.
//
// A step, with events on, runs:
//   begin_step            this step's keys and hits emptied
//   per substep:
//     remember_solve_start  (hits only) positions and velocities just before the contact solve,
//                           for the approach speed of each contact that bounces
//     collect_substep       the substep's touching contacts and impacts, turned into keys of
//                           handles (slots move with the Morton re-sort, which runs at the start
//                           of a substep); hits above the speed, with their handles
//   finish_step           keys sorted; begin = current - previous, end = previous - current,
//                         found by one merge of the two sorted arrays; current becomes previous
// Every array is built serially from the contact and impact lists, which are the same for any
// thread count, and sorted by a total order, so the events are too, bitwise.
//
// Touching, in a step: in some substep, a contact that ended the solve with an impulse (normal,
// friction or bounce) or began it overlapping (gap <= 0), or an impact of World::last_impacts.
// Not "gap <= 0 after the step": in a settled pile touches flicker with each step's rounding
// (384 spheres settled, 200 steps: 6,676 begins by that rule, 35 by this one), and a pair that
// meets and parts within one step never overlaps at a step's end. Not impulse alone either: two
// spheres lying side by side press on nothing. A sphere resting under gravity carries about
// m g dt every step, so it stays touching (tests/test_events.cpp: 200 steps, and the pile).
//
// Persistent state (what a snapshot must save and restore): the settings and the previous
// step's touching keys (touching_pairs, touching_ground; restore_touching). Everything else
// is rebuilt by each step.

#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "hail/events.h"
#include "hail/plane.h"
#include "hail/sphere_soa.h"
#include "kernel/mesh/mesh_set.h"
#include "soa/heap_bytes.h"

namespace hail {

/// A touching pair or ground contact by handle. Sorted by (key, generations); equal entries are
/// the same touch. Sphere pairs: key = lower index << 32 | higher index, generations the two
/// handles' generations in the same order. Ground: key = index << 32 | surface (0 the terrain,
/// 1 + k plane k), generations the handle's generation.
struct TouchKey {
  std::uint64_t key = 0;
  std::uint64_t generations = 0;
  friend bool operator==(const TouchKey&, const TouchKey&) = default;
  friend auto operator<=>(const TouchKey&, const TouchKey&) = default;
};

/// What collect_substep reads of the World besides the sphere state and the lists.
struct EventSurfaces {
  std::span<const Plane> planes;
  float terrain_restitution = 0.0f;
  const MeshSet* meshes = nullptr;     ///< null: no meshes
  float restitution_threshold = 0.0f;  ///< the substep's (World::substep), to undo an impact's impulse
};

class ContactEventTracker {
 public:
  /// Takes new settings (checked by World::set_events). Turning touch off forgets the touching
  /// keys (turned on again, every touch begins anew); turning either off empties its events.
  void configure(const EventSettings& settings);
  [[nodiscard]] const EventSettings& settings() const { return settings_; }
  /// Touch or hits on: World::step calls the methods below only then.
  [[nodiscard]] bool on() const { return settings_.touch || settings_.hits; }
  [[nodiscard]] bool wants_hits() const { return settings_.hits; }

  void begin_step();
  /// Keeps slots' positions and velocities as the contact solve starts (hits only). With
  /// `gravity_dt` (g dt, given under Integrator::UniformAcceleration) the velocities are kept
  /// without this step's gravity, so that a hit reports the approach speed its restitution
  /// took (solve_collision's gravity_closing), not that speed plus g dt.
  void remember_solve_start(const SphereSoA& s, const float* gravity_dt = nullptr);
  /// After a substep: `contacts` and `impacts` are its lists (slots of `s` as it is now).
  void collect_substep(const SphereSoA& s, std::span<const Contact> contacts, std::span<const Impact> impacts,
                       const EventSurfaces& surfaces);
  /// Sleeping on, before finish_step: the touches of sleepers go on (their contacts are left
  /// out of the step, kernel/world/sleep_islands.h), so a pile that falls asleep ends none.
  void keep_sleepers_touching(const SphereSoA& s);
  void finish_step();
  /// A step that moves nothing (time_scale 0, or no sphere): every touch is kept, except those of
  /// removed spheres, which end; no hits.
  void finish_idle_step(const SphereSoA& s);

  [[nodiscard]] std::span<const TouchEvent> touch_begin() const { return begin_events_; }
  [[nodiscard]] std::span<const TouchEvent> touch_end() const { return end_events_; }
  [[nodiscard]] std::span<const HitEvent> hits() const { return hit_events_; }

  /// The persistent part: the touching keys after the last step, sorted, no duplicates.
  [[nodiscard]] std::span<const TouchKey> touching_pairs() const { return previous_pairs_; }
  [[nodiscard]] std::span<const TouchKey> touching_ground() const { return previous_ground_; }
  /// Puts back what touching_pairs / touching_ground returned (a snapshot); the events are
  /// emptied. Returns false, changing nothing, unless each is strictly increasing.
  bool restore_touching(std::span<const TouchKey> pairs, std::span<const TouchKey> ground);

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(previous_pairs_, previous_ground_, current_pairs_, current_ground_, begin_events_, end_events_, hit_records_, hit_events_, start_px_, start_py_, start_pz_, start_vx_, start_vy_, start_vz_);
  }

 private:
  /// A hit with what sorts it: kind (0 pair, 1 ground), key, then the order it was found in.
  struct HitRecord {
    std::uint32_t kind = 0;
    std::uint32_t sequence = 0;
    std::uint64_t key = 0;
    HitEvent event;
  };
  void add_touch(const SphereSoA& s, std::uint32_t a, std::uint32_t b, std::uint32_t feature);
  void add_hit(const SphereSoA& s, std::uint32_t a, std::uint32_t b, std::uint32_t feature, float speed,
               const Vec3& point, const Vec3& normal);
  void contact_hits(const SphereSoA& s, std::span<const Contact> contacts);
  void impact_hits(const SphereSoA& s, std::span<const Impact> impacts, const EventSurfaces& surfaces);
  /// Sorts, drops duplicates, appends begin and end events, and makes current the previous.
  void merge_touches(std::vector<TouchKey>& current, std::vector<TouchKey>& previous, bool pairs);

  /// The ground a static contact's feature names, as a TouchKey's low half: the terrain, plane
  /// k or mesh m (by the substep's meshes_).
  [[nodiscard]] std::uint32_t surface_code(std::uint32_t feature) const;

  EventSettings settings_;
  const MeshSet* meshes_ = nullptr;  ///< the substep's (collect_substep), for surface_code
  // Persistent: the keys touching after the last step, sorted.
  std::vector<TouchKey> previous_pairs_, previous_ground_;
  // This step's, then scratch.
  std::vector<TouchKey> current_pairs_, current_ground_;
  std::vector<TouchEvent> begin_events_, end_events_;
  std::vector<HitRecord> hit_records_;
  std::vector<HitEvent> hit_events_;
  std::vector<float> start_px_, start_py_, start_pz_, start_vx_, start_vy_, start_vz_;  ///< per slot, at solve start
};

}  // namespace hail
