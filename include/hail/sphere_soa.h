#pragma once
// Sphere state as structure-of-arrays: one 64-byte aligned float array per component, length
// padded to a multiple of kSimdPadding so SIMD loops over [0, padded_size()) need no scalar
// tail. Padding lanes are inert by their data: zero radius, zero inverse mass, parked far away,
// so they never touch anything and no impulse moves them.
//
// Users hold SphereId handles; dense slots may move (removal swaps the last sphere into the
// hole, a later re-sort may permute them) but a handle keeps naming the same sphere.

#include <algorithm>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "hail/aligned_array.h"
#include "hail/collision_filter.h"

namespace hail {

/// Widest SIMD batch of floats any path uses (AVX-512: 16 lanes). Arrays are padded to it.
inline constexpr std::size_t kSimdPadding = 16;

/// Where padding lanes are parked: far from everything, yet its square stays finite in float.
inline constexpr float kPaddingPosition = 1.0e18f;

/// Stable handle to a sphere. `generation` makes a handle to a removed sphere detectably stale.
struct SphereId {
  std::uint32_t index = 0xFFFFFFFFu;
  std::uint32_t generation = 0;
  friend bool operator==(SphereId, SphereId) = default;
};

/// Per-sphere flag bits.
enum SphereFlags : std::uint32_t {
  kSphereFlagNone = 0,
  /// Moved by the velocity the game sets (World::set_velocity, move_kinematic), never by
  /// contacts, gravity or forces: inv_mass 0 like a static sphere, so every impulse rule gives
  /// it none, while its velocity enters the contacts it makes. Passes through terrain and planes.
  kSphereFlagKinematic = 1u << 0,
  /// Asleep (WorldSettings::sleep): at rest with its island, left out of the step until a
  /// contact, a control call or a change of the ground wakes it (World::is_sleeping).
  kSphereFlagSleeping = 1u << 1,
};
/// Every flag bit above: a snapshot with any other bit set is refused.
inline constexpr std::uint32_t kKnownSphereFlags = kSphereFlagKinematic | kSphereFlagSleeping;

/// Everything a new sphere is made of, already validated and converted to inverse quantities.
struct SphereRecord {
  float px, py, pz;
  float vx, vy, vz;
  float wx, wy, wz;
  float radius;
  float inv_mass;
  float inv_inertia;
  float restitution;
  float friction;
  std::uint32_t flags;
  float gravity_scale = 1.0f;            ///< the sphere's gravity is WorldSettings::gravity * this
  float force[3] = {0.0f, 0.0f, 0.0f};   ///< N, accumulated for the next step
  float torque[3] = {0.0f, 0.0f, 0.0f};  ///< N m, accumulated for the next step
  std::uint64_t user_data = 0;           ///< the game's, never read by hail
  CollisionFilter filter{};              ///< category and mask bits (collision_filter.h)
  float sleep_timer = 0.0f;              ///< s spent below the sleep speeds (SphereSoA::sleep_timer)
  std::uint32_t sleep_island = 0;        ///< while asleep: its island's label (SphereSoA::sleep_island)
};

class SphereSoA {
 public:
  SphereSoA() { set_padding(0); }

  /// Appends a sphere and returns its handle. Allocates only when capacity is exceeded.
  /// Throws InvalidArgument (nothing added) when kMaxSpheres handle indices are in use.
  SphereId add(const SphereRecord& record);
  /// Removes the sphere; the last dense sphere moves into its slot. Returns false if stale.
  bool remove(SphereId id);
  /// Dense slot of a live handle, or -1 when the handle is stale or was never issued.
  [[nodiscard]] std::int64_t slot_of(SphereId id) const noexcept;
  [[nodiscard]] SphereId id_at(std::size_t slot) const noexcept { return slot_ids_[slot]; }
  /// Handle of every dense slot, in slot order (id_at for all of them); valid until the next
  /// add, remove or permute.
  [[nodiscard]] std::span<const SphereId> handles() const noexcept { return {slot_ids_.data(), size_}; }
  /// Dense slot of the live sphere whose handle has this index (any generation: the one alive),
  /// or -1 when none has. For data that keeps only handle indices (the warm-start cache).
  [[nodiscard]] std::int64_t slot_of_index(std::uint32_t index) const noexcept;
  [[nodiscard]] bool contains(SphereId id) const noexcept { return slot_of(id) >= 0; }
  /// The most spheres a SphereSoA holds: a handle index is 32 bits, and one value is kept free.
  static constexpr std::size_t kMaxSpheres = 0xFFFFFFFEu;
  /// Reserves storage for n spheres so that adding up to n never allocates. Throws
  /// InvalidArgument for n > kMaxSpheres and std::bad_alloc when memory runs out; either way
  /// every array keeps its spheres (some may have grown), so the SoA stays usable.
  void reserve(std::size_t n);
  /// Reorders dense slots: new slot k holds the sphere that was in slot order[k]. Handles stay valid.
  /// `angular` false leaves the angular velocity arrays as they are: for a caller that knows
  /// them all equal (a world without rotation keeps them all zero); `accumulators` false does
  /// the same for the force and torque arrays (a world with no force pending keeps them zero).
  void permute(std::span<const std::uint32_t> order, bool angular = true, bool accumulators = true);
  /// permute() with its element loops run by `for_ranges(count, f)`, which must call f(first,
  /// last) for ranges that cover [0, count) exactly once each, in any order and on any thread
  /// (jobs/ runs them over blocks in parallel): each loop writes element k from element order[k]
  /// alone, so the result is permute()'s.
  template <class ForRanges>
  void permute(std::span<const std::uint32_t> order, bool angular, bool accumulators, ForRanges&& for_ranges);

  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  /// size() rounded up to kSimdPadding; the arrays are at least this long.
  [[nodiscard]] std::size_t padded_size() const noexcept { return padded_size_for(size_); }
  static constexpr std::size_t padded_size_for(std::size_t n) noexcept {
    return (n + kSimdPadding - 1) / kSimdPadding * kSimdPadding + (n == 0 ? kSimdPadding : 0);
  }

  AlignedArray<float> px, py, pz;   ///< position, m
  AlignedArray<float> vx, vy, vz;   ///< linear velocity, m/s
  AlignedArray<float> wx, wy, wz;   ///< angular velocity, rad/s
  AlignedArray<float> radius;       ///< m (0 in padding lanes)
  AlignedArray<float> inv_mass;     ///< 1/kg (0 = immovable; 0 in padding lanes)
  AlignedArray<float> inv_inertia;  ///< 1/(kg m^2), solid sphere: 1 / (2/5 m r^2)
  AlignedArray<float> restitution;  ///< [0, 1]
  AlignedArray<float> friction;     ///< Coulomb coefficient, >= 0
  AlignedArray<std::uint32_t> flags;
  AlignedArray<float> gravity_scale;  ///< the sphere's gravity is WorldSettings::gravity * this (default 1)
  /// Force (N) and torque (N m) accumulated by World::apply_force / apply_torque for the next
  /// step, which applies them in predict (over each of its substeps) and then zeroes them.
  AlignedArray<float> force_x, force_y, force_z, torque_x, torque_y, torque_z;
  AlignedArray<std::uint64_t> user_data;  ///< the game's (World::set_user_data), never read by hail
  /// Collision filter bits (collision_filter.h): what the sphere is, and what it collides with.
  /// Padding lanes have 0 in both, so they pass no filter.
  AlignedArray<std::uint32_t> collision_category, collision_mask;
  /// Sleeping (kernel/world/sleep_islands.h): seconds the sphere has stayed below both sleep
  /// speeds (WorldSettings::sleep_linear_speed, sleep_angular_speed), 0 once it moves faster;
  /// and while it sleeps (kSphereFlagSleeping), the label its island went to sleep under (the
  /// smallest handle index in it), which waking one of them wakes all of.
  AlignedArray<float> sleep_timer;
  AlignedArray<std::uint32_t> sleep_island;

  /// Calls f(name, array) for every per-sphere array above, in one fixed order: the one list
  /// that resize, reserve, permute and snapshots (kernel/world/snapshot_*.cpp) walk, so that an
  /// array added to SphereSoA is added here once and is then sized, re-sorted and saved with
  /// the rest (sphere_soa.cpp checks sizeof(SphereSoA) against this list's length).
  template <class F>
  void for_each_array(F&& f) {
    for_each_array_of(f, *this);
  }
  template <class F>
  void for_each_array(F&& f) const {
    for_each_array_of(f, *this);
  }
  /// How many arrays for_each_array visits.
  static constexpr std::size_t kArrayCount = 27;

  /// Heap bytes held (capacities): the per-sphere arrays, the handle tables and the re-sort's
  /// scratch.
  [[nodiscard]] std::size_t heap_bytes() const {
    std::size_t bytes = 0;
    for_each_array([&](const char*, const auto& array) {
      bytes += array.capacity() * sizeof(typename std::remove_cvref_t<decltype(array)>::value_type);
    });
    return bytes + slot_ids_.capacity() * sizeof(SphereId) + id_to_slot_.capacity() * 4 + generation_.capacity() * 4 +
           free_ids_.capacity() * 4 + float_scratch_.capacity() * 4 + id_scratch_.capacity() * 4 +
           user_scratch_.capacity() * 8 + handle_scratch_.capacity() * sizeof(SphereId);
  }

  /// The handle tables, for snapshots: per handle index, its current generation (a removed
  /// sphere's index has moved on to the next), and the free indices in the order add() reuses
  /// them (from the back).
  [[nodiscard]] std::span<const std::uint32_t> generations() const noexcept { return generation_; }
  [[nodiscard]] std::span<const std::uint32_t> free_indices() const noexcept { return free_ids_; }
  /// Makes this (an empty SphereSoA) hold handles.size() spheres with these handles (slot k's is
  /// handles[k]), generations and free list, as generations() and free_indices() returned them;
  /// the arrays are sized, padding lanes written, slots [0, size) left for the caller to fill.
  /// Throws InvalidArgument naming the first inconsistency (a handle index out of range, used
  /// twice, also free, or with another generation; an index neither live nor free).
  /// Grows this SphereSoA's storage to hold `other`'s spheres and handle tables, changing no
  /// sphere (std::bad_alloc leaves it as it was, with more room perhaps).
  void reserve_like(const SphereSoA& other);
  /// Makes this a copy of `other` in its own buffers: after reserve_like(other) it allocates
  /// nothing and cannot throw, and the arrays stay where they were, so spans taken before
  /// (World::spheres(), handles()) stay valid. World::restore commits a snapshot by it.
  void assign(const SphereSoA& other) noexcept;

  void restore_handles(std::span<const SphereId> handles, std::span<const std::uint32_t> generations,
                       std::span<const std::uint32_t> free_indices);

 private:
  /// f(name, s.array...) for each array, over one SphereSoA or side by side over several.
  template <class F, class... Soa>
  static void for_each_array_of(F& f, Soa&... s) {
    f("px", s.px...), f("py", s.py...), f("pz", s.pz...), f("vx", s.vx...), f("vy", s.vy...), f("vz", s.vz...);
    f("wx", s.wx...), f("wy", s.wy...), f("wz", s.wz...);
    f("radius", s.radius...), f("inv_mass", s.inv_mass...), f("inv_inertia", s.inv_inertia...);
    f("restitution", s.restitution...), f("friction", s.friction...), f("flags", s.flags...);
    f("gravity_scale", s.gravity_scale...);
    f("force_x", s.force_x...), f("force_y", s.force_y...), f("force_z", s.force_z...);
    f("torque_x", s.torque_x...), f("torque_y", s.torque_y...), f("torque_z", s.torque_z...);
    f("user_data", s.user_data...);
    f("collision_category", s.collision_category...), f("collision_mask", s.collision_mask...);
    f("sleep_timer", s.sleep_timer...), f("sleep_island", s.sleep_island...);
  }

  void set_padding(std::size_t first);
  void resize_arrays(std::size_t n);
  void write_slot(std::size_t slot, const SphereRecord& r);
  SphereRecord read_slot(std::size_t slot) const;

  std::size_t size_ = 0;
  std::vector<SphereId> slot_ids_;         // dense slot -> handle
  std::vector<std::uint32_t> id_to_slot_;  // id index -> dense slot (0xFFFFFFFF when free)
  std::vector<std::uint32_t> generation_;  // id index -> current generation
  std::vector<std::uint32_t> free_ids_;
  AlignedArray<float> float_scratch_;         // permute(): one array's new order
  AlignedArray<std::uint32_t> id_scratch_;    // permute(): a uint32 array in its new order
  AlignedArray<std::uint64_t> user_scratch_;  // permute(): user data in its new order
  std::vector<SphereId> handle_scratch_;      // permute(): handles in their new order
};

template <class ForRanges>
void SphereSoA::permute(std::span<const std::uint32_t> order, bool angular, bool accumulators, ForRanges&& for_ranges) {
  // Array by array through one scratch array, so a re-sort every few steps allocates only the
  // first time (or when the world grows).
  auto permute_through = [&](auto& array, auto& scratch) {
    for_ranges(size_, [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k) scratch[k] = array[order[k]];
    });
    for_ranges(size_, [&](std::size_t first, std::size_t last) {
      std::copy(scratch.data() + first, scratch.data() + last, array.data() + first);
    });
  };
  float_scratch_.resize(size_);
  id_scratch_.resize(size_);
  user_scratch_.resize(size_);
  for_each_array([&](const char*, auto& a) {
    const void* p = &a;
    const bool spin = p == &wx || p == &wy || p == &wz;
    const bool accumulator =
        p == &force_x || p == &force_y || p == &force_z || p == &torque_x || p == &torque_y || p == &torque_z;
    if ((!angular && spin) || (!accumulators && accumulator)) return;
    using T = typename std::remove_reference_t<decltype(a)>::value_type;
    if constexpr (std::is_same_v<T, float>)
      permute_through(a, float_scratch_);
    else if constexpr (std::is_same_v<T, std::uint32_t>)
      permute_through(a, id_scratch_);
    else
      permute_through(a, user_scratch_);
  });
  handle_scratch_.resize(size_);
  permute_through(slot_ids_, handle_scratch_);
  // Handles are distinct, so each range writes its own entries of id_to_slot_.
  for_ranges(size_, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) id_to_slot_[slot_ids_[k].index] = static_cast<std::uint32_t>(k);
  });
}

}  // namespace hail
