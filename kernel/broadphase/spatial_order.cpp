#include "kernel/broadphase/spatial_order.h"

#include <algorithm>
#include <cmath>

#include "kernel/geometry/morton.h"
#include "soa/grow.h"

namespace hail {

Aabb finite_centre_bounds(const SphereSoA& s, std::size_t first, std::size_t last) {
  Aabb bounds = empty_aabb();
  for (std::size_t i = first; i < last; ++i) {
    const float p[3] = {s.px[i], s.py[i], s.pz[i]};
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) grow(bounds, p);
  }
  return bounds;
}

void morton_keys(const SphereSoA& s, const Aabb& bounds, std::size_t first, std::size_t last, std::uint64_t* keys) {
  for (std::size_t i = first; i < last; ++i)
    keys[i] = (std::uint64_t{morton_code_3d(bounds, s.px[i], s.py[i], s.pz[i])} << 32) | i;
}

void morton_slot_order(const SphereSoA& s, std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& order) {
  const std::size_t n = s.size();
  const Aabb bounds = finite_centre_bounds(s, 0, n);
  resize_geometric(keys, n);
  morton_keys(s, bounds, 0, n, keys.data());
  std::sort(keys.begin(), keys.end());
  resize_geometric(order, n);
  for (std::size_t k = 0; k < n; ++k) order[k] = static_cast<std::uint32_t>(keys[k]);
}

}  // namespace hail
