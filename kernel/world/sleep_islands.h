#pragma once
// Sleeping (WorldSettings::sleep): islands of spheres at rest are put to sleep as a whole and
// left out of the step until something wakes them. Box2D v3 and Jolt do the same by islands.
//
// The rules, one place each:
//   moves(i)     awake and movable (inv_mass > 0), or immovable with a velocity (a kinematic
//                sphere): what can push a sleeper. A static sphere at rest pushes nothing.
//   island       spheres joined by this substep's sphere-sphere contacts, both movable. The
//                terrain, planes and immovable spheres join no islands (a pile on the ground is
//                one island; two piles on a static sphere are two).
//   timer        per sphere (SphereSoA::sleep_timer): seconds it has stayed at or below both
//                WorldSettings::sleep_linear_speed and sleep_angular_speed; 0 once it is faster.
//   spin         what counts against sleep_angular_speed: for a sphere with contacts that carry
//                load (normal impulse > 0 this substep), the largest |w x n| over their normals
//                n, how fast the spin slides its surface past any of them (over its radius);
//                with none, all of |w|. Spin about a loaded normal (a twist in place) slides
//                nothing, and hail has no torsional or rolling resistance that would ever stop
//                it: a sphere pinched between two neighbours, spinning about the line through
//                the two contacts, kept a 2,000-sphere bowl pile awake for good (0.51 rad/s
//                about a horizontal axis, no linear velocity). A spin that slides a loaded
//                contact still counts: friction works on it. The largest of squares is exact
//                and order-free, so the result does not depend on the order of the contacts.
//   sleep        at the end of a substep, every island whose smallest timer is at least
//                sleep_time and which is supported (one of its spheres touches the terrain, a
//                plane or an immovable sphere): flag kSphereFlagSleeping set, velocities zeroed,
//                and its label (the smallest handle index in it, SphereSoA::sleep_island) kept
//                with each sphere. An island touching nothing static is in free flight: put to
//                sleep, a sphere drifting at 0.02 m/s in zero gravity stopped, and a head-on
//                collision with a 1,000 times heavier sphere lost all its momentum
//                (tests/test_known_answers.cpp, "C: head-on"). Box2D and Jolt sleep such bodies.
//   wake         a contact between a sleeper and a sphere that moves (found by detection, before
//                the solve; continuous collision's impacts after the sweep), a control call on a
//                sleeper, removing it: its whole island (every sleeper with its label). An
//                immovable sphere that is moved, resized, added or removed wakes the islands
//                of the sleepers within reach of it (a scan: such calls are rare).
//   drop         a contact with a sleeper on one side and nothing that moves on either is
//                left out of the step: sleepers cost no solve and no depenetration.
// Islands are found by a union-find whose roots are the smallest slot of each island, so the
// partition, its labels and every decision are the same whatever order the contacts come in
// and on any thread count. The pass is serial: O(spheres + contacts), one pass over the
// contacts, and only over a substep in which something moves (a world whose every movable
// sphere sleeps skips the substep).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "hail/world_settings.h"

namespace hail {

[[nodiscard]] inline bool sphere_sleeps(const SphereSoA& s, std::size_t i) {
  return (s.flags[i] & kSphereFlagSleeping) != 0;
}

/// Awake and movable, or immovable with a velocity: can push a sleeper (see the rules above).
[[nodiscard]] inline bool sphere_moves(const SphereSoA& s, std::size_t i) {
  if (sphere_sleeps(s, i)) return false;
  return s.inv_mass[i] > 0.0f || s.vx[i] != 0.0f || s.vy[i] != 0.0f || s.vz[i] != 0.0f;
}

/// A contact (or pair) the step leaves out: a sleeper on one side, nothing that moves on either.
[[nodiscard]] inline bool sleeping_contact(const SphereSoA& s, std::uint32_t a, std::uint32_t b) {
  if (b == kStaticBody) return sphere_sleeps(s, a);
  return (sphere_sleeps(s, a) || sphere_sleeps(s, b)) && !sphere_moves(s, a) && !sphere_moves(s, b);
}

class SleepIslands {
 public:
  /// Wakes the island of every sleeper that a contact of `contacts` joins to a sphere that
  /// moves. Returns whether any woke (the caller then predicts the woken spheres, woken_slots(),
  /// and detects again, so that their contacts are in this substep's solve).
  bool wake_touched(SphereSoA& s, std::span<const Contact> contacts);
  /// The slots the last wake_touched woke, in slot order.
  [[nodiscard]] std::span<const std::uint32_t> woken_slots() const { return woken_slots_; }
  /// The same for impacts of continuous collision (the sleeper hit has its impulse already).
  bool wake_hit(SphereSoA& s, std::span<const Impact> impacts);
  /// Wakes slot's island if it sleeps; if it is immovable, also the islands of the sleepers
  /// that touch it or nearly (within a tenth of their radii).
  void wake_around(SphereSoA& s, std::size_t slot);
  /// Wakes every sleeper (the ground changed).
  void wake_all(SphereSoA& s);
  /// End of a substep: timers advanced by dt, islands of `contacts` found, the islands at rest
  /// long enough put to sleep.
  void update(SphereSoA& s, std::span<const Contact> contacts, float dt, const WorldSettings& settings);
  /// How many spheres sleep.
  [[nodiscard]] static std::size_t count_sleeping(const SphereSoA& s);
  /// Whether some movable sphere is awake or some sphere moves: false, the substep can be skipped.
  [[nodiscard]] static bool anything_moves(const SphereSoA& s);

  /// Handles put to sleep / woken since the last publish(), sorted by index, each once (a
  /// sphere may be in both: it woke and slept again).
  void publish();
  [[nodiscard]] std::span<const SphereId> slept() const { return published_slept_; }
  [[nodiscard]] std::span<const SphereId> woken() const { return published_woken_; }
  /// Sleepers and islands counted by the last update (StepStats).
  [[nodiscard]] std::size_t islands() const { return islands_; }
  void clear_events();

 private:
  std::uint32_t find(std::uint32_t i);
  void unite(std::uint32_t a, std::uint32_t b);
  /// Wakes every sleeper whose label is in labels_ (sorted, unique); returns whether any woke.
  bool wake_labels(SphereSoA& s);
  void wake_slot(SphereSoA& s, std::size_t i);

  std::vector<std::uint32_t> parent_;
  std::vector<float> spin2_;                  // per slot: largest squared slide of its loaded contacts, or -1
  std::vector<std::uint8_t> touches_static_;  // per slot: a contact with something static
  std::vector<float> island_timer_;           // per root: smallest timer of the island
  std::vector<std::uint8_t> supported_;       // per root: the island touches something static
  std::vector<std::uint32_t> island_label_;   // per root: smallest handle index of the island
  std::vector<std::uint32_t> labels_;         // islands to wake
  std::vector<std::uint32_t> woken_slots_;    // slots woken by the last wake_touched
  std::vector<SphereId> slept_, woken_, published_slept_, published_woken_;
  std::size_t islands_ = 0;
};

}  // namespace hail
