#include "kernel/broadphase/sphere_bvh_pairs.h"

#include <algorithm>
#include <limits>

#include "kernel/broadphase/sphere_pair_bounds.h"
#include "soa/grow.h"

namespace hail {

void SphereBvhPairs::build(const SphereSoA& s, float /*margin: the boxes do not depend on it*/,
                           const BvhBuildOptions& options) {
  constexpr float kFinite = std::numeric_limits<float>::max();
  const std::size_t n = s.size();
  resize_geometric(bounds_, n);
  for (std::size_t i = 0; i < n; ++i) {
    Aabb& box = bounds_[i];
    const float c[3] = {s.px[i], s.py[i], s.pz[i]};
    if (!can_pair(c[0], c[1], c[2], s.radius[i])) {
      // The builder takes finite boxes only. This sphere pairs with nothing; parked at the
      // corner of the float range it is at worst a candidate, which the predicate rejects.
      box = Aabb{{kFinite, kFinite, kFinite}, {kFinite, kFinite, kFinite}};
      continue;
    }
    const float e = box_half_extent(s.radius[i]);
    // Clamping an end that overflowed keeps the box finite and still overlapping every query
    // box around a finite centre on that side, so no pair is lost.
    for (int a = 0; a < 3; ++a) {
      box.min[a] = std::max(c[a] - e, -kFinite);
      box.max[a] = std::min(c[a] + e, kFinite);
    }
  }
  bvh_.build(bounds_, options);
  resize_geometric(leaf_, n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = bvh_.primitive_order[k];
    leaf_[k] = {s.px[i], s.py[i], s.pz[i], s.radius[i]};
  }
}

void SphereBvhPairs::find_pairs(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                                std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const {
  const std::uint32_t* order = bvh_.primitive_order.data();
  const LeafSphere* leaf = leaf_.data();
  for (std::size_t i = first; i < last; ++i) {
    const float xi = s.px[i], yi = s.py[i], zi = s.pz[i], ri_margin = s.radius[i] + margin;  // brute force's order
    if (!can_pair(xi, yi, zi, ri_margin)) continue;
    row.clear();
    // Overlaps every box of a sphere the predicate accepts (sphere_pair_bounds.h).
    const float q = box_half_extent(ri_margin);
    const Aabb query{{xi - q, yi - q, zi - q}, {xi + q, yi + q, zi + q}};
    query_aabb(bvh_, query, [&](std::uint32_t k) {
      const std::uint32_t j = order[k];
      const LeafSphere& o = leaf[k];
      if (j > i && spheres_within(o.x - xi, o.y - yi, o.z - zi, o.radius + ri_margin)) row.push_back(j);
    });
    // The walk reports spheres in BVH order: sort to get brute force's row.
    std::sort(row.begin(), row.end());
    for (std::uint32_t j : row) out.push_back({static_cast<std::uint32_t>(i), j});
  }
}

}  // namespace hail
