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
#include <vector>

#include "hail/aligned_array.h"

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
};

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
};

class SphereSoA {
 public:
  SphereSoA() { set_padding(0); }

  /// Appends a sphere and returns its handle. Allocates only when capacity is exceeded.
  SphereId add(const SphereRecord& record);
  /// Removes the sphere; the last dense sphere moves into its slot. Returns false if stale.
  bool remove(SphereId id);
  /// Dense slot of a live handle, or -1 when the handle is stale or was never issued.
  [[nodiscard]] std::int64_t slot_of(SphereId id) const noexcept;
  [[nodiscard]] SphereId id_at(std::size_t slot) const noexcept {
    return {slot_to_id_[slot], generation_[slot_to_id_[slot]]};
  }
  [[nodiscard]] bool contains(SphereId id) const noexcept { return slot_of(id) >= 0; }
  /// Reserves storage for n spheres so that adding up to n never allocates.
  void reserve(std::size_t n);
  /// Reorders dense slots: new slot k holds the sphere that was in slot order[k]. Handles stay valid.
  /// `angular` false leaves the angular velocity arrays as they are: for a caller that knows
  /// them all equal (a world without rotation keeps them all zero).
  void permute(std::span<const std::uint32_t> order, bool angular = true);
  /// permute() with its element loops run by `for_ranges(count, f)`, which must call f(first,
  /// last) for ranges that cover [0, count) exactly once each, in any order and on any thread
  /// (jobs/ runs them over blocks in parallel): each loop writes element k from element order[k]
  /// alone, so the result is permute()'s.
  template <class ForRanges>
  void permute(std::span<const std::uint32_t> order, bool angular, ForRanges&& for_ranges);

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

 private:
  void set_padding(std::size_t first);
  void resize_arrays(std::size_t n);
  void write_slot(std::size_t slot, const SphereRecord& r);
  SphereRecord read_slot(std::size_t slot) const;

  std::size_t size_ = 0;
  std::vector<std::uint32_t> slot_to_id_;  // dense slot -> id index
  std::vector<std::uint32_t> id_to_slot_;  // id index -> dense slot (0xFFFFFFFF when free)
  std::vector<std::uint32_t> generation_;  // id index -> current generation
  std::vector<std::uint32_t> free_ids_;
  AlignedArray<float> float_scratch_;       // permute(): one array's new order
  AlignedArray<std::uint32_t> id_scratch_;  // permute(): flags and ids in their new order
};

template <class ForRanges>
void SphereSoA::permute(std::span<const std::uint32_t> order, bool angular, ForRanges&& for_ranges) {
  // Array by array through one scratch array, so a re-sort every few steps allocates only the
  // first time (or when the world grows).
  float_scratch_.resize(size_);
  for (auto* a :
       {&px, &py, &pz, &vx, &vy, &vz, &wx, &wy, &wz, &radius, &inv_mass, &inv_inertia, &restitution, &friction}) {
    if (!angular && (a == &wx || a == &wy || a == &wz)) continue;
    for_ranges(size_, [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k) float_scratch_[k] = (*a)[order[k]];
    });
    for_ranges(size_, [&](std::size_t first, std::size_t last) {
      std::copy(float_scratch_.data() + first, float_scratch_.data() + last, a->data() + first);
    });
  }
  id_scratch_.resize(size_);
  for_ranges(size_, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) id_scratch_[k] = flags[order[k]];
  });
  for_ranges(size_, [&](std::size_t first, std::size_t last) {
    std::copy(id_scratch_.data() + first, id_scratch_.data() + last, flags.data() + first);
  });
  for_ranges(size_, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) id_scratch_[k] = slot_to_id_[order[k]];
  });
  // Ids are distinct, so each range writes its own entries of id_to_slot_.
  for_ranges(size_, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      slot_to_id_[k] = id_scratch_[k];
      id_to_slot_[id_scratch_[k]] = static_cast<std::uint32_t>(k);
    }
  });
}

}  // namespace hail
