#include "kernel/sphere_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "soa/grow.h"

namespace hail {
namespace {

std::int32_t cell_coordinate(float p, float inv_cell) {
  const float c = std::floor(p * inv_cell);
  // Non-finite or huge coordinates (a NaN sphere, parked padding) all land in one far cell:
  // they are still tested exactly, only less efficiently.
  if (!(c > -1.0e9f && c < 1.0e9f)) return 1 << 30;
  return static_cast<std::int32_t>(c);
}

}  // namespace

std::uint32_t SphereGrid::bucket_of(std::int32_t x, std::int32_t y, std::int32_t z) const {
  const std::uint32_t h = static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u ^
                          static_cast<std::uint32_t>(z) * 83492791u;
  return (h ^ (h >> 15)) & mask_;
}

void SphereGrid::build(const SphereSoA& s, float margin) {
  const std::size_t n = s.size();
  float max_radius = 0.0f;
  for (std::size_t i = 0; i < n; ++i) max_radius = std::max(max_radius, s.radius[i]);
  // Any pair within reach is at most one cell apart on every axis.
  const float cell = std::max(2.0f * max_radius + margin, 1e-6f);
  inv_cell_ = 1.0f / cell;
  const std::size_t buckets = std::bit_ceil(std::max<std::size_t>(2 * n, 64));
  mask_ = static_cast<std::uint32_t>(buckets - 1);
  resize_geometric(cell_, 3 * n);
  assign_geometric(bucket_start_, buckets + 1, std::uint32_t{0});
  resize_geometric(sorted_, n);
  for (std::size_t i = 0; i < n; ++i) {
    cell_[3 * i] = cell_coordinate(s.px[i], inv_cell_);
    cell_[3 * i + 1] = cell_coordinate(s.py[i], inv_cell_);
    cell_[3 * i + 2] = cell_coordinate(s.pz[i], inv_cell_);
    ++bucket_start_[bucket_of(cell_[3 * i], cell_[3 * i + 1], cell_[3 * i + 2]) + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  // Counting sort; the cursor reuses sorted_ order so spheres stay ascending within a bucket.
  std::vector<std::uint32_t>& start = bucket_start_;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = bucket_of(cell_[3 * i], cell_[3 * i + 1], cell_[3 * i + 2]);
    sorted_[start[b]++] = static_cast<std::uint32_t>(i);
  }
  for (std::size_t b = buckets; b > 0; --b) start[b] = start[b - 1];
  start[0] = 0;
}

void SphereGrid::find_pairs(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                            std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const {
  for (std::size_t i = first; i < last; ++i) {
    row.clear();
    const std::int32_t cx = cell_[3 * i], cy = cell_[3 * i + 1], cz = cell_[3 * i + 2];
    const float xi = s.px[i], yi = s.py[i], zi = s.pz[i], ri_margin = s.radius[i] + margin;
    for (std::int32_t dx = -1; dx <= 1; ++dx)
      for (std::int32_t dy = -1; dy <= 1; ++dy)
        for (std::int32_t dz = -1; dz <= 1; ++dz) {
          const std::uint32_t b = bucket_of(cx + dx, cy + dy, cz + dz);
          for (std::uint32_t k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
            const std::uint32_t j = sorted_[k];
            if (j <= i) continue;
            const float reach = s.radius[j] + ri_margin;
            if (spheres_within(s.px[j] - xi, s.py[j] - yi, s.pz[j] - zi, reach)) row.push_back(j);
          }
        }
    // Two neighbour cells may share a bucket: sort and drop repeats to get brute force's row.
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    for (std::uint32_t j : row) out.push_back({static_cast<std::uint32_t>(i), j});
  }
}

}  // namespace hail
