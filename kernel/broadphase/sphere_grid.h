#pragma once
// Uniform-grid pair search for many spheres: spheres are counting-sorted into hashed cells
// twice the largest reach (largest diameter plus margin) wide, and each sphere tests the cells
// its reach window overlaps: usually 2 x 2 x 2. It returns exactly the pairs
// of the brute-force search, in the same order (rows i ascending, j ascending within a row), so
// the choice of pair search never changes a simulation.
//
// Layout, for speed: a cell (x, y, z) goes to bucket grid_key(x, y, z) & mask, so the cells of
// one row along x are consecutive buckets, one contiguous run of the sorted arrays: a sphere
// scans one run per (y, z) row of its window (usually 4), not one hashed bucket per cell. The
// build copies centres, radii (and travels) into that sorted order, so a run is read
// contiguously and tested a batch at a time by the SIMD kernel (kernel/simd/sphere_grid.cpp;
// find_pairs_scalar is its reference).
//
// Why the window never loses a pair to rounding: on each axis, every partner's centre lies in
// [fl(ci - W), fl(ci + W)] with W = fl(|q| + max|r|) (kernel/broadphase/sphere_pair_bounds.h; q = ri +
// margin, or ri + the pair's margin, which lies between ri and ri + margin), and grid_cell is
// monotone in the coordinate (fl(c - lowest) and fl(u * inv_cell) are monotone, and so are the
// truncation and the clamps). So a partner's cell lies between the cells of the window's ends,
// whatever the cell size: the cell size only trades runs against candidates.

#include <cmath>
#include <cstdint>
#include <vector>

#include "hail/debug_draw.h"
#include "hail/sphere_soa.h"
#include "kernel/broadphase/sphere_pair_bounds.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/dispatch/simd_namespace.h"
#include "soa/heap_bytes.h"

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

/// A built SphereGrid as plain arrays: what the search kernels read. The sorted arrays are
/// followed by kSimdPadding inert slots, so a run's last batch may read past it.
struct SphereGridView {
  const float *x, *y, *z, *radius;  ///< sorted slots
  const float* travel;              ///< sorted slots; null without pair margins
  const std::uint32_t* index;       ///< sphere index of each sorted slot
  const std::uint32_t*
      bucket_start;            ///< bucket b holds sorted slots [bucket_start[b], bucket_start[b + 1]), mask + 2 entries
  const float* sphere_travel;  ///< per sphere (dense slot); null without pair margins
  std::uint32_t mask;
  std::uint32_t stride_y, stride_z;  ///< grid_key's
  float travel_factor;               ///< PairMargins::factor (with travel)
  float lowest[3];                   ///< lowest centre on each axis (grid_cell's)
  float inv_cell;
  float max_radius;          ///< largest |radius| of the sorted spheres
  std::int32_t top_cell[3];  ///< highest cell coordinate of any sphere on each axis
};

inline namespace HAIL_SIMD_NS {
/// Cell coordinate of c on an axis whose lowest centre is `lowest`: fl(fl(c - lowest) *
/// inv_cell) truncated, clamped to [0, kMaxCell] (NaN, from an infinite offset times a zero
/// inverse, goes to 0). Monotone in c; build and kernels must use exactly this.
[[nodiscard]] inline std::int32_t grid_cell(float c, float lowest, float inv_cell) {
  constexpr std::int32_t kMaxCell = 1 << 15;
  const float u = (c - lowest) * inv_cell;
  if (!(u > 0.0f)) return 0;
  return u < static_cast<float>(kMaxCell) ? static_cast<std::int32_t>(u) : kMaxCell;
}

/// The key of cell (x, y, z), modulo the bucket count: x + stride_z z + stride_y y. Spatially
/// coherent (a sphere's neighbour cells, and those of the next sphere in Morton order, lie
/// close in the sorted arrays), and with no collisions at all while the box of occupied cells
/// fits the table. The strides are odd, so no two cells of one column (or row) share a bucket
/// below the bucket count. Integers only; here (per path namespace) for the kernels and build.
[[nodiscard]] inline std::uint32_t grid_key(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t stride_y,
                                            std::uint32_t stride_z) {
  return static_cast<std::uint32_t>(x) + stride_z * static_cast<std::uint32_t>(z) +
         stride_y * static_cast<std::uint32_t>(y);
}

/// The cells, on each axis [lo, hi], that hold every partner of sphere i (the top of this
/// file): the cells of its window's ends, the top clamped to the highest occupied cell.
struct GridWindow {
  std::int32_t lo[3], hi[3];
};
[[nodiscard]] inline GridWindow grid_window(const SphereGridView& v, float xi, float yi, float zi, float ri,
                                            float ri_margin) {
  const float q = std::fabs(ri) > std::fabs(ri_margin) ? std::fabs(ri) : std::fabs(ri_margin);
  const float w = axis_reach_bound(q, v.max_radius);
  const float c[3] = {xi, yi, zi};
  GridWindow g;
  for (int a = 0; a < 3; ++a) {
    g.lo[a] = grid_cell(c[a] - w, v.lowest[a], v.inv_cell);
    const std::int32_t hi = grid_cell(c[a] + w, v.lowest[a], v.inv_cell);
    g.hi[a] = hi < v.top_cell[a] ? hi : v.top_cell[a];
  }
  return g;
}

/// Calls scan(first, last) for the sorted-slot ranges [first, last) that hold the window's
/// cells: per (y, z) row, cells lo .. hi along x are consecutive buckets, split where they wrap.
/// Shared by the scalar reference and every SIMD path, so both visit the same candidates.
template <class Scan>
inline void for_each_window_run(const SphereGridView& v, const GridWindow& g, Scan&& scan) {
  const std::uint32_t buckets = v.mask + 1, length = static_cast<std::uint32_t>(g.hi[0] - g.lo[0]) + 1;
  for (std::int32_t cz = g.lo[2]; cz <= g.hi[2]; ++cz)
    for (std::int32_t cy = g.lo[1]; cy <= g.hi[1]; ++cy) {
      const std::uint32_t b0 = grid_key(g.lo[0], cy, cz, v.stride_y, v.stride_z) & v.mask, b1 = b0 + length;
      if (length >= buckets) {
        scan(v.bucket_start[0], v.bucket_start[buckets]);
      } else if (b1 <= buckets) {
        scan(v.bucket_start[b0], v.bucket_start[b1]);
      } else {
        scan(v.bucket_start[b0], v.bucket_start[buckets]);
        scan(v.bucket_start[0], v.bucket_start[b1 - buckets]);
      }
    }
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
  /// The boxes of the cells that hold a sphere since the last build, each once, sorted by
  /// cell (z, y, x), into `out` (replacing what it held): for drawing the grid
  /// (World::pair_grid_cells). Cells clamped at the grid's edge (grid_cell) are drawn where
  /// the clamp puts them. Allocates; not for the step.
  void occupied_cells(std::vector<DebugBox>& out) const;

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(sphere_travel_, bucket_of_, bucket_start_, x_, y_, z_, radius_, travel_, index_);
  }

 private:
  std::uint32_t mask_ = 0;
  std::uint32_t stride_y_ = 0, stride_z_ = 0;
  float lowest_[3] = {0, 0, 0};
  float inv_cell_ = 1.0f, max_radius_ = 0.0f;
  std::int32_t top_cell_[3] = {0, 0, 0};
  bool with_travel_ = false;
  float travel_factor_ = 0.0f;
  std::vector<float> sphere_travel_;         // per sphere, with pair margins
  std::vector<std::uint32_t> bucket_of_;     // per sphere, build scratch (kNoBucket: left out)
  std::vector<std::uint32_t> bucket_start_;  // mask + 3 entries (the last is build's scratch)
  // Spheres in bucket order (index ascending within a bucket), SoA, each array followed by
  // kSimdPadding inert slots.
  std::vector<float> x_, y_, z_, radius_, travel_;
  std::vector<std::uint32_t> index_;
};

}  // namespace hail
