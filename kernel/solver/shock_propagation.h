#pragma once
// Shock propagation (Guendelman, Bridson & Fedkiw 2003, "Nonconvex rigid bodies with
// stacking"): one more resting pass after the others, taken from the ground up, in which the
// body of each contact that is nearer the ground counts as immovable.
//
// Why: sequential impulses pass weight down a stack at a rate set by the mass ratio. A 1 kg
// sphere under 100 kg under 1e4 kg takes each pass's push almost entirely on the light body, so
// after 8 passes the stack still falls at nearly g dt per step and the 1 kg sphere is pressed
// through the ground (hail-bench stress, stack-1-100-1e4). Taken level by level with the lower
// body fixed, the one pass stops the whole stack: the ground stops the bottom sphere, that one
// stops the next, and so on.
//
// The pass changes velocities only (no accumulated impulse is kept, so warm starting is
// unaffected) and only removes closing speed, so it cannot add energy.
//
// Two spheres on one level (a pebble and a boulder both resting on the ground) are ordered by
// which is below the other: a 1e4 kg sphere rolling onto a 0.01 kg one lying on the ground took
// each pass's push on the light sphere, pressed it into the ground, and rolled over it until
// the pebble sat inside the boulder (hail-bench stress, small-under-big-rain).

#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "hail/vec3.h"
#include "kernel/solver/solver_body.h"
#include "soa/heap_bytes.h"

namespace hail {

class ShockPropagation {
 public:
  /// Levels from the contacts: immovable bodies (static geometry, static spheres) are level 0,
  /// a sphere touching one is level 1, a sphere touching a level-1 sphere is level 2, ...;
  /// spheres not connected to the ground get no level and are left out. Then the contacts in
  /// order of their lower level. Serial, O(spheres + contacts); reuses its buffers.
  /// `up` is the unit vector against gravity (zero without gravity): it orders two spheres of one
  /// level (holder()).
  void plan(std::span<const Contact> contacts, std::span<const SolverBody> bodies, const Vec3& up);

  /// The pass over the planned contacts (bodies as for plan; the last is the static body):
  /// each contact's closing speed is brought to at most gap / dt by a normal impulse; where the
  /// two levels differ only the upper body moves. A normal impulse passes through both
  /// centres, so only linear velocities change (w is neither read nor written).
  void solve(std::span<const Contact> contacts, std::span<SolverBody> bodies, float inv_dt) const;

  /// Which body of contact c holds still in a shock pass: the one on the lower level; of two
  /// spheres of one level, the one below, where the contact's normal is within 78 degrees of up
  /// (a side-by-side pair: neither, both move by their masses). Static geometry always holds.
  enum class Holder : std::uint8_t { None, A, B };
  /// Of two spheres of one level, b sits on a where the contact normal (a to b) is within 78
  /// degrees of up: cos 0.2, not 60 degrees' 0.5: a pebble on a slope under a boulder's flank
  /// (normal 63 degrees off up) was otherwise pushed by their correction into the ground,
  /// lifted back by the guard, and stayed 0.4 of its radius inside the boulder step after step
  /// (hail-bench stress, small-under-big-rain).
  static constexpr float kBelowCosine = 0.2f;
  [[nodiscard]] Holder holder(const Contact& c) const;
  /// The height rule alone, for two spheres whose contact normal (a to b) is n: A where b sits
  /// on a, B where a sits on b, None side by side. Also the rule of the step's last parting of
  /// the pairs that met in the sweep, which have no contact and so no level.
  [[nodiscard]] static Holder holder_by_height(const Contact& c, const Vec3& up);

  /// Contacts the pass visits (those with a level), in order.
  [[nodiscard]] std::span<const std::uint32_t> order() const { return order_; }
  /// Level of sphere `slot` after plan(); kNoLevel when it does not rest on anything.
  [[nodiscard]] std::uint32_t level(std::uint32_t slot) const { return level_[slot]; }
  static constexpr std::uint32_t kNoLevel = 0xFFFFFFFFu;

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(level_, first_edge_, edges_, queue_, level_count_, order_);
  }

 private:
  std::vector<std::uint32_t> level_;        ///< per sphere
  std::vector<std::uint32_t> first_edge_;   ///< per sphere + 1: where its neighbours start in edges_
  std::vector<std::uint32_t> edges_;        ///< neighbour slots of sphere-sphere contacts
  std::vector<std::uint32_t> queue_;        ///< breadth-first order
  std::vector<std::uint32_t> level_count_;  ///< counting sort of contacts by level
  std::vector<std::uint32_t> order_;        ///< contact indices, lowest level first
  Vec3 up_ = Vec3::Zero();
};

}  // namespace hail
