#pragma once
// Sort-and-sweep pair search: the spheres are sorted by their centre along the axis of
// greatest spread, and each sphere tests, with the brute-force SIMD predicate, the contiguous
// run of sorted spheres whose centres lie within reach along that axis (on both sides, since
// its partners j > i may sort before or after it). It returns exactly the pairs of the
// brute-force search, in the same order (rows i ascending, j ascending within a row), so the
// choice of pair search never changes a simulation.
//
// Mixed radii: one sorted run for all spheres would have to be searched as wide as the largest
// radius for every sphere, so a few giants would widen every window. Spheres are therefore
// sorted within radius classes (radii within a factor 4 share a class), and each class is
// searched with its own largest radius: one binary search pair per non-empty class and row.
// With one giant among many small spheres the classes are several times faster, and on an
// ordinary mixed pile they cost nothing (docs/benchmarks.md, "Figures behind the code's choices").

#include <cstdint>
#include <vector>

#include "hail/sphere_soa.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "soa/heap_bytes.h"

namespace hail {

/// A built SortedAxisPairs as plain arrays: what the SIMD search (kernel/simd/sorted_axis_pairs.cpp,
/// one copy per SIMD path) reads. Each array is followed by kSimdPadding inert slots.
struct SortedAxisPairsView {
  int axis;
  const float *x, *y, *z, *radius;   ///< sorted slots
  const std::uint32_t* index;        ///< sphere index of each sorted slot
  const std::uint32_t* class_begin;  ///< class c: sorted slots [class_begin[c], class_begin[c + 1])
  const float* class_max_radius;     ///< largest |radius| in each class
  std::size_t classes;
};

class SortedAxisPairs {
 public:
  /// Sorts the spheres along the axis of greatest centre variance (lowest axis on ties).
  /// Serial, O(n log n); allocates only on growth. The sort depends on centres and radii only,
  /// so find_pairs may be given any margin; `margin` is taken for the common interface.
  void build(const SphereSoA& spheres, float margin);
  /// Appends the pairs (i, j), i in [first, last), i < j, within `margin`, of the spheres as
  /// they were at the last build. `row` is caller-owned scratch so that disjoint row blocks can
  /// run in parallel. Runs the active SIMD path's kernel (kernel/dispatch/simd_dispatch.h).
  void find_pairs(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                  std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const;
  /// The sweep axis chosen by the last build (0 = x, 1 = y, 2 = z).
  [[nodiscard]] int axis() const { return axis_; }
  /// Number of non-empty radius classes after the last build.
  [[nodiscard]] std::size_t class_count() const { return class_begin_.empty() ? 0 : class_begin_.size() - 1; }
  /// The sorted arrays, for the SIMD kernels.
  [[nodiscard]] SortedAxisPairsView view() const;

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(x_, y_, z_, radius_, index_, class_begin_, class_max_radius_, keys_, class_of_);
  }

 private:
  /// Most radius classes: radii beyond 4^(kMaxRadiusClasses - 1) times the smallest share the last.
  static constexpr int kMaxRadiusClasses = 4;

  int axis_ = 0;
  // Spheres in sorted order (class, then centre on axis_, then index), SoA, each array
  // followed by kSimdPadding (the widest batch) inert slots, so that a window's last batch may
  // read past it on any SIMD path.
  std::vector<float> x_, y_, z_, radius_;
  std::vector<std::uint32_t> index_;        // sphere index of each sorted slot
  std::vector<std::uint32_t> class_begin_;  // class c holds sorted slots [class_begin_[c], class_begin_[c + 1])
  std::vector<float> class_max_radius_;     // largest |radius| in each class
  // Build scratch, kept so that a rebuild of the same size does not allocate.
  struct SortKey {
    float centre;  // on axis_
    std::uint32_t index;
  };
  std::vector<SortKey> keys_;
  std::vector<std::uint8_t> class_of_;  // per sphere; kExcluded for spheres that can pair with nothing
};

}  // namespace hail
