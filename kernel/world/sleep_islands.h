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
//                nothing, and without rolling_resistance (default 0) nothing would ever stop
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
// How update() finds the islands that sleep, paying for spheres at rest only:
//   candidate    an awake movable sphere that is slow and whose timer reaches sleep_time this
//                substep (if its spin lets it run). An island sleeps only if every sphere of it
//                is a candidate, so islands are joined among candidates only, and a contact
//                between a candidate and any other movable sphere marks the candidate's island
//                held awake. A joined group of candidates with no such contact is a whole
//                island: the decisions are exactly those of a union-find over every contact,
//                and a step in which few spheres rest pays for one read of the contacts and of
//                a byte per sphere (terrain-rain, 2 threads: 2.1 ms a step against 12.0 for
//                that union-find, serial, at 256k spheres; 6.3 against 38.5 at 1M;
//                docs/benchmarks.md, "The islands phase").
//   ready        StepStats::ready_to_sleep: awake spheres whose timers have reached sleep_time,
//                the spheres an island holds awake.
// The union-find's roots are the smallest slot of each island, so the partition, its labels
// and every decision are the same whatever order the contacts come in and on any thread
// count. It runs in parallel over fixed blocks of spheres and of contacts: a root is linked
// under a smaller one by compare-and-swap, and what each island gathers (its smallest label,
// whether it is supported or held awake) and what each sphere gathers from its contacts (the
// largest slide, touching something static) are minima, maxima and ORs, atomic updates whose
// results do not depend on the order the threads apply them in (no atomic decides an order).
// Only a substep in which something moves runs it (a world whose every movable sphere sleeps
// skips the substep), and waking scans the contacts only when some sphere sleeps.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "hail/world_settings.h"
#include "soa/heap_bytes.h"

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
  /// Whether some sphere sleeps.
  [[nodiscard]] static bool any_sleeping(const SphereSoA& s);
  /// Whether some movable sphere is awake or some sphere moves: false, the substep can be skipped.
  [[nodiscard]] static bool anything_moves(const SphereSoA& s);

  /// Handles put to sleep / woken since the last publish(), sorted by index, each once (a
  /// sphere may be in both: it woke and slept again).
  void publish();
  [[nodiscard]] std::span<const SphereId> slept() const { return published_slept_; }
  [[nodiscard]] std::span<const SphereId> woken() const { return published_woken_; }
  /// Awake spheres whose timers have reached sleep_time, counted by the last update (StepStats).
  [[nodiscard]] std::size_t ready_to_sleep() const { return ready_to_sleep_; }
  void clear_events();

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(parent_, spin2_, sphere_class_, contact_flags_, root_flags_, island_label_, block_counts_, labels_, woken_slots_, slept_, woken_, published_slept_, published_woken_);
  }

 private:
  std::uint32_t find(std::uint32_t i);
  void unite(std::uint32_t a, std::uint32_t b);
  /// Wakes every sleeper whose label is in labels_ (sorted, unique); returns whether any woke.
  bool wake_labels(SphereSoA& s);
  void wake_slot(SphereSoA& s, std::size_t i);

  /// What a block of spheres counted in update()'s passes.
  struct BlockCounts {
    std::size_t candidates = 0, needs_slides = 0, ready = 0, slept = 0;
  };
  // Per-slot arrays of update(), written by atomic updates while its passes run in parallel.
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> spin2_;          // per slot: largest squared slide of its loaded contacts (ordered bits)
  std::vector<std::uint8_t> sphere_class_;    // per slot: kMovable, kCandidate, kNeedsSlides
  std::vector<std::uint8_t> contact_flags_;   // per slot: kTouchesStatic, kLoaded, kHeldAwake, kSleptNow
  std::vector<std::uint8_t> root_flags_;      // per root: kSupported, kBlocked
  std::vector<std::uint32_t> island_label_;   // per root: smallest handle index of the island
  std::vector<BlockCounts> block_counts_;     // per block of spheres
  std::vector<std::uint32_t> labels_;         // islands to wake
  std::vector<std::uint32_t> woken_slots_;    // slots woken by the last wake_touched
  std::vector<SphereId> slept_, woken_, published_slept_, published_woken_;
  std::size_t ready_to_sleep_ = 0;
};

}  // namespace hail
