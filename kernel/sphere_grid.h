#pragma once
// Uniform-grid pair search for many spheres: spheres are counting-sorted into hashed cells a
// little wider than the largest reach (largest diameter plus margin), and each sphere tests the
// 27 cells around its own. It returns exactly the pairs of the brute-force search, in the same
// order (rows i ascending, j ascending within a row), so the choice of pair search never
// changes a simulation.
//
// Layout, for speed: a cell (x, y, z) goes to bucket grid_key(x, y, z) & mask, so the three
// cells x - 1, x, x + 1 of one row are three consecutive buckets, one contiguous run of the
// sorted arrays: a sphere scans 9 runs, not 27 hashed buckets. The build copies centres, radii
// (and travels) into that sorted order, so a run is read contiguously and tested a batch at a
// time by the SIMD kernel (kernel/simd/sphere_grid.cpp; find_pairs_scalar is its reference).
//
// Why the cells never lose a pair to rounding: cell coordinates are
// floor(fl(fl(c - lowest) * fl(1 / cell))), monotone in c, clamped to [0, kMaxCell]. An accepted
// pair is at most |ri + margin| + |rj| <= (2 max|r| + |margin|)(1 + 2^-23) apart on each axis
// (kernel/sphere_pair_bounds.h), the cell is that bound times (1 + 2^-8), and below kMaxCell
// the three roundings move a coordinate by less than 2^-10.4 of a cell: two coordinates of an
// accepted pair differ by less than 1 - 2^-8 + 2^-9.4 < 1 cells, so their floors by at most 1.
// Clamping is monotone and does not widen gaps; a sphere clamped to kMaxCell and an unclamped
// partner stay neighbours by the same bound.

#include <cstdint>
#include <vector>

#include "kernel/simd_namespace.h"
#include "kernel/sphere_pairs.h"
#include "soa/sphere_soa.h"

namespace hail {

/// Per-pair speculative margins (WorldSettings::pair_margin_travel), applied inside the search:
/// pair (i, j) is reported only if spheres_within holds with
/// reach = rj + (ri + min(margin, factor * (travel[i] + travel[j]))), exactly the filter the
/// step pipeline applies to the other searches' pairs. That margin is never above `margin`, so
/// these pairs are a subset of the plain search's (float addition and squaring are monotone).
/// travel[] >= 0 and factor >= 0 (as the World guarantees); travel null: the plain search.
struct PairMargins {
  const float* travel = nullptr;  ///< per sphere (dense slot), read during build only
  float factor = 0.0f;
};

/// Cell of one sphere (build's coordinates) and its travel (PairMargins), per dense slot.
struct GridCell {
  std::int32_t x, y, z;
  float travel;
};

/// A built SphereGrid as plain arrays: what the search kernels read. The sorted arrays are
/// followed by kSimdPadding inert slots, so a run's last batch may read past it.
struct SphereGridView {
  const float *x, *y, *z, *radius;    ///< sorted slots
  const float* travel;                ///< sorted slots; null without pair margins
  const std::uint32_t* index;         ///< sphere index of each sorted slot
  const std::uint32_t* bucket_start;  ///< bucket b holds sorted slots [bucket_start[b], bucket_start[b + 1]), mask + 2 entries
  const GridCell* cell;               ///< per sphere (dense slot)
  std::uint32_t mask;
  std::uint32_t stride_y, stride_z;   ///< grid_key's
  float travel_factor;                ///< PairMargins::factor (with travel)
};

inline namespace HAIL_SIMD_NS {
/// The key of cell (x, y, z), modulo the bucket count: x + stride_z z + stride_y y. Spatially
/// coherent (a sphere's neighbour cells, and those of the next sphere in Morton order, lie
/// close in the sorted arrays), and with no collisions at all while the box of occupied cells
/// fits the table. The strides are odd, so no two cells of one column (or row) share a bucket
/// below the bucket count. Integers only; here (per path namespace) for the kernels and build.
[[nodiscard]] inline std::uint32_t grid_key(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t stride_y,
                                            std::uint32_t stride_z) {
  return static_cast<std::uint32_t>(x) + stride_z * static_cast<std::uint32_t>(z) + stride_y * static_cast<std::uint32_t>(y);
}
}  // namespace HAIL_SIMD_NS

class SphereGrid {
 public:
  /// Sorts the spheres into cells for this margin (and copies their travels when pair_margins
  /// has them). Serial, O(n); allocates only on growth.
  void build(const SphereSoA& spheres, float margin, PairMargins pair_margins = {});
  /// Appends the pairs (i, j), i in [first, last), i < j, within `margin` (the one given to
  /// build; and within their own margins if build had PairMargins). `row` is caller-owned
  /// scratch so that blocks can run in parallel. Runs the active SIMD path's kernel.
  void find_pairs(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                  std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const;
  /// The scalar reference of find_pairs: the same pairs from the same float operations.
  void find_pairs_scalar(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                         std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const;
  /// The sorted arrays, for the SIMD kernels.
  [[nodiscard]] SphereGridView view() const;

  /// Cells per axis above the lowest sphere before coordinates clamp (see the top of the file).
  static constexpr std::int32_t kMaxCell = 4096;

 private:
  std::uint32_t mask_ = 0;
  std::uint32_t stride_y_ = 0, stride_z_ = 0;
  bool with_travel_ = false;
  float travel_factor_ = 0.0f;
  std::vector<GridCell> cell_;               // per sphere
  std::vector<std::uint32_t> bucket_of_;     // per sphere, build scratch (kNoBucket: left out)
  std::vector<std::uint32_t> bucket_start_;  // mask + 3 entries (the last is build's scratch)
  // Spheres in bucket order (index ascending within a bucket), SoA, each array followed by
  // kSimdPadding inert slots.
  std::vector<float> x_, y_, z_, radius_, travel_;
  std::vector<std::uint32_t> index_;
};

}  // namespace hail
