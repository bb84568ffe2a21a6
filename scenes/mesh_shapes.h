#pragma once
// Simple meshes the stress battery and the tests build scenes from.

#include <cstdint>
#include <vector>

#include "hail/triangle_mesh.h"

namespace hail::bench {

/// An axis-aligned box from `lo` to `hi`, each face two triangles wound counter-clockwise seen
/// from outside: a closed mesh (a solid).
inline TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> v;
  for (int k = 0; k < 8; ++k) v.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const std::uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  std::vector<std::uint32_t> idx;
  for (const auto& q : quads) idx.insert(idx.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  return TriangleMesh(std::move(v), std::move(idx));
}

}  // namespace hail::bench
