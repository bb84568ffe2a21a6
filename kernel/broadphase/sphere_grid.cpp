#include "kernel/broadphase/sphere_grid.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "kernel/broadphase/sphere_pair_bounds.h"
#include "kernel/dispatch/kernel_table.h"
#include "soa/grow.h"

namespace hail {
namespace {

constexpr std::uint32_t kNoBucket = std::numeric_limits<std::uint32_t>::max();
// Padding after the sorted arrays: the widest batch of any SIMD path.
constexpr std::size_t kLanes = kSimdPadding;

// Sorts a row's partners ascending and drops repeats (two of a sphere's 9 runs may share
// buckets). Rows are a few partners long: insertion sort beats std::sort there.
std::size_t sort_unique(std::uint32_t* row, std::size_t count) {
  std::size_t kept = 0;
  for (std::size_t a = 0; a < count; ++a) {
    const std::uint32_t j = row[a];
    std::size_t at = kept;
    while (at > 0 && row[at - 1] > j) --at;
    if (at > 0 && row[at - 1] == j) continue;
    for (std::size_t b = kept; b > at; --b) row[b] = row[b - 1];
    row[at] = j;
    ++kept;
  }
  return kept;
}

}  // namespace

void SphereGrid::build(const SphereSoA& s, float margin, PairMargins pair_margins) {
  const std::size_t n = s.size();
  with_travel_ = pair_margins.travel != nullptr;
  travel_factor_ = pair_margins.factor;
  resize_geometric(bucket_of_, n);
  if (with_travel_) {
    resize_geometric(sphere_travel_, n);
    std::copy(pair_margins.travel, pair_margins.travel + n, sphere_travel_.begin());
  }

  // Spheres that pair with nothing (can_pair) stay out; the rest set the cell and the box.
  const float* __restrict px = s.px.data();
  const float* __restrict py = s.py.data();
  const float* __restrict pz = s.pz.data();
  const float* __restrict radius = s.radius.data();
  std::uint32_t* __restrict bucket_of = bucket_of_.data();
  float max_radius = 0.0f;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  float lowest[3] = {kInf, kInf, kInf}, highest[3] = {-kInf, -kInf, -kInf};
  std::size_t sorted = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float r = std::fabs(radius[i]);
    if (!can_pair(px[i], py[i], pz[i], r)) {
      bucket_of[i] = kNoBucket;
      continue;
    }
    bucket_of[i] = 0;
    ++sorted;
    max_radius = std::max(max_radius, r);
    lowest[0] = std::min(lowest[0], px[i]);
    lowest[1] = std::min(lowest[1], py[i]);
    lowest[2] = std::min(lowest[2], pz[i]);
    highest[0] = std::max(highest[0], px[i]);
    highest[1] = std::max(highest[1], py[i]);
    highest[2] = std::max(highest[2], pz[i]);
  }
  if (sorted == 0) lowest[0] = lowest[1] = lowest[2] = highest[0] = highest[1] = highest[2] = 0.0f;
  // The cell size only trades runs against candidates (the windows are exact, top of
  // sphere_grid.h). Two reaches: a window (two reaches wide) then spans 2 cells per axis, so
  // 4 runs of 2 cells; at one reach it spans 3, 9 runs of 3 cells with fewer candidates each.
  // Fewer, longer runs win on every SIMD path (detect-pairs by cell size: docs/benchmarks.md,
  // "Figures behind the code's choices").
  // An infinite cell puts every sphere in cell 0; a zero or NaN one gets any positive size.
  float cell = 2.0f * (2.0f * max_radius + std::fabs(margin));
  if (!(cell >= std::numeric_limits<float>::min())) cell = std::numeric_limits<float>::min();
  inv_cell_ = 1.0f / cell;
  max_radius_ = max_radius;
  for (int a = 0; a < 3; ++a) {
    lowest_[a] = lowest[a];
    top_cell_[a] = grid_cell(highest[a], lowest[a], inv_cell_);
  }
  // Odd strides wider than the occupied box (grid_key).
  stride_z_ = (static_cast<std::uint32_t>(top_cell_[0]) + 2) | 1u;
  stride_y_ = stride_z_ * ((static_cast<std::uint32_t>(top_cell_[2]) + 2) | 1u);
  const std::size_t buckets = std::bit_ceil(std::max<std::size_t>(2 * sorted, 64));
  mask_ = static_cast<std::uint32_t>(buckets - 1);
  assign_geometric(bucket_start_, buckets + 2, std::uint32_t{0});

  std::uint32_t* __restrict start = bucket_start_.data();
  for (std::size_t i = 0; i < n; ++i) {
    if (bucket_of[i] == kNoBucket) continue;
    const std::int32_t cx = grid_cell(px[i], lowest[0], inv_cell_), cy = grid_cell(py[i], lowest[1], inv_cell_),
                       cz = grid_cell(pz[i], lowest[2], inv_cell_);
    const std::uint32_t b = grid_key(cx, cy, cz, stride_y_, stride_z_) & mask_;
    bucket_of[i] = b;
    ++start[b + 2];
  }
  for (std::size_t b = 0; b < buckets; ++b) start[b + 2] += start[b + 1];

  // Counting sort of the indices, each bucket in index order. The counts went in two buckets
  // ahead, so start[b + 1] is bucket b's cursor, and it ends at bucket b's end = start of
  // b + 1. Then the sorted SoA is gathered in sorted order: one scattered write per sphere,
  // not six.
  resize_geometric(x_, sorted + kLanes);
  resize_geometric(y_, sorted + kLanes);
  resize_geometric(z_, sorted + kLanes);
  resize_geometric(radius_, sorted + kLanes);
  resize_geometric(index_, sorted + kLanes);
  if (with_travel_) resize_geometric(travel_, sorted + kLanes);
  std::uint32_t* __restrict index = index_.data();
  for (std::size_t i = 0; i < n; ++i)
    if (bucket_of[i] != kNoBucket) index[start[bucket_of[i] + 1]++] = static_cast<std::uint32_t>(i);
  float* __restrict x = x_.data();
  float* __restrict y = y_.data();
  float* __restrict z = z_.data();
  float* __restrict r = radius_.data();
  for (std::size_t k = 0; k < sorted; ++k) {
    const std::uint32_t i = index[k];
    x[k] = px[i];
    y[k] = py[i];
    z[k] = pz[i];
    r[k] = radius[i];
  }
  if (with_travel_)
    for (std::size_t k = 0; k < sorted; ++k) travel_[k] = sphere_travel_[index[k]];
  // Padding: far away, zero radius; never reported anyway (lanes past a run are masked).
  for (std::size_t k = sorted; k < sorted + kLanes; ++k) {
    x[k] = y[k] = z[k] = kPaddingPosition;
    r[k] = 0.0f;
    index[k] = 0;
    if (with_travel_) travel_[k] = 0.0f;
  }
}

SphereGridView SphereGrid::view() const {
  return {x_.data(),
          y_.data(),
          z_.data(),
          radius_.data(),
          with_travel_ ? travel_.data() : nullptr,
          index_.data(),
          bucket_start_.data(),
          with_travel_ ? sphere_travel_.data() : nullptr,
          mask_,
          stride_y_,
          stride_z_,
          travel_factor_,
          {lowest_[0], lowest_[1], lowest_[2]},
          inv_cell_,
          max_radius_,
          {top_cell_[0], top_cell_[1], top_cell_[2]}};
}

void SphereGrid::occupied_cells(std::vector<DebugBox>& out) const {
  out.clear();
  if (bucket_start_.empty()) return;
  const std::uint32_t sorted = bucket_start_[std::size_t(mask_) + 1];
  std::vector<std::array<std::int32_t, 3>> cells(sorted);
  for (std::uint32_t k = 0; k < sorted; ++k)
    cells[k] = {grid_cell(z_[k], lowest_[2], inv_cell_), grid_cell(y_[k], lowest_[1], inv_cell_),
                grid_cell(x_[k], lowest_[0], inv_cell_)};
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  const float cell = 1.0f / inv_cell_;
  const Vec3 lowest(lowest_[0], lowest_[1], lowest_[2]);
  out.reserve(cells.size());
  for (const auto& [cz, cy, cx] : cells) {
    const Vec3 min = lowest + cell * Vec3(float(cx), float(cy), float(cz));
    out.push_back({.min = min, .max = min + Vec3::Constant(cell)});
  }
}

void SphereGrid::find_pairs(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                            std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const {
  if (first >= last || bucket_start_.empty()) return;
  row.clear();
  simd_kernels().grid_find_pairs(view(), s, first, last, margin, out, row);
}

void SphereGrid::find_pairs_scalar(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                                   std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const {
  if (first >= last || bucket_start_.empty()) return;
  const SphereGridView v = view();
  for (std::size_t i = first; i < last; ++i) {
    const float xi = s.px[i], yi = s.py[i], zi = s.pz[i], ri = s.radius[i], ri_margin = ri + margin;
    if (!can_pair(xi, yi, zi, ri_margin)) continue;
    const float travel_i = v.travel ? v.sphere_travel[i] : 0.0f;
    row.clear();
    auto scan = [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t k = begin; k < end; ++k) {
        // Brute force's reach, or keep_pairs_within_their_margin's (kernel/world/step_pipeline.cpp).
        float reach = v.radius[k] + ri_margin;
        if (v.travel) {
          const float wanted = v.travel_factor * (travel_i + v.travel[k]);
          reach = v.radius[k] + (ri + std::min(margin, wanted));
        }
        if (v.index[k] > i && spheres_within(v.x[k] - xi, v.y[k] - yi, v.z[k] - zi, reach)) row.push_back(v.index[k]);
      }
    };
    const GridWindow g = grid_window(v, xi, yi, zi, ri, ri_margin);
    for_each_window_run(v, g, scan);
    row.resize(sort_unique(row.data(), row.size()));
    for (std::uint32_t j : row) out.push_back({static_cast<std::uint32_t>(i), j});
  }
  row.clear();
}

void append_sorted_unique_row(std::uint32_t i, std::vector<std::uint32_t>& row, std::vector<SpherePair>& out) {
  row.resize(sort_unique(row.data(), row.size()));
  reserve_geometric(out, out.size() + row.size());
  for (std::uint32_t j : row) out.push_back({i, j});
  row.clear();
}

}  // namespace hail
