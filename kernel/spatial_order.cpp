#include "kernel/spatial_order.h"

#include <algorithm>
#include <cmath>

#include "kernel/morton.h"
#include "soa/grow.h"

namespace hail {

void morton_slot_order(const SphereSoA& s, std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& order) {
  const std::size_t n = s.size();
  Aabb bounds = empty_aabb();
  for (std::size_t i = 0; i < n; ++i) {
    const float p[3] = {s.px[i], s.py[i], s.pz[i]};
    // A non-finite centre would stretch the box to infinity and put everyone in one cell.
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) grow(bounds, p);
  }
  resize_geometric(keys, n);
  for (std::size_t i = 0; i < n; ++i)
    keys[i] = (std::uint64_t{morton_code_3d(bounds, s.px[i], s.py[i], s.pz[i])} << 32) | i;
  std::sort(keys.begin(), keys.end());
  resize_geometric(order, n);
  for (std::size_t k = 0; k < n; ++k) order[k] = static_cast<std::uint32_t>(keys[k]);
}

}  // namespace hail
