#pragma once
// Morton (Z-order) codes: points close in space get close codes, so sorting by code puts
// neighbours next to each other in memory. Queries walked in this order reuse the BVH nodes
// and triangles the previous query just loaded (see `hail-bench query`).

#include <algorithm>
#include <cstdint>

#include "kernel/geometry/aabb.h"

namespace hail {

/// Spreads the low 10 bits of v so that bit k lands at bit 3k.
[[nodiscard]] constexpr std::uint32_t spread_bits_3d(std::uint32_t v) {
  v &= 0x3FFu;
  v = (v | (v << 16)) & 0x030000FFu;
  v = (v | (v << 8)) & 0x0300F00Fu;
  v = (v | (v << 4)) & 0x030C30C3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

/// 30-bit Morton code of point p inside `bounds`, on a grid of cubic cells: every axis is
/// quantised in steps of (longest extent) / 1024, so that a flat box (a terrain: 255 m wide,
/// 22 m tall) does not interleave fine height bits with coarse x/z bits and scatter neighbours.
/// Points outside the box are clamped to its faces, NaN to the low face.
[[nodiscard]] inline std::uint32_t morton_code_3d(const Aabb& bounds, float x, float y, float z) {
  const float p[3] = {x, y, z};
  float extent = 0.0f;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, bounds.max[a] - bounds.min[a]);
  const float scale = extent > 0.0f ? 1023.0f / extent : 0.0f;
  std::uint32_t q[3];
  for (int a = 0; a < 3; ++a) {
    const float t = (p[a] - bounds.min[a]) * scale;
    // Written so that NaN fails the first test and lands on 0.
    const float clamped = t > 0.0f ? (t < 1023.0f ? t : 1023.0f) : 0.0f;
    q[a] = static_cast<std::uint32_t>(clamped);
  }
  return (spread_bits_3d(q[0]) << 2) | (spread_bits_3d(q[1]) << 1) | spread_bits_3d(q[2]);
}

}  // namespace hail
