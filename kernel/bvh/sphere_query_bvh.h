#pragma once
// The spheres' acceleration structure for the world queries: a flat BVH (kernel/bvh/flat_bvh.h)
// over the spheres' boxes, with the centre, radius, category and handle of each sphere copied
// in BVH order, so that a leaf's spheres are contiguous and a query never goes back to the SoA.
// World builds it lazily (kernel/world/world_queries.cpp, SphereQueryCache).

#include <cstdint>
#include <vector>

#include "hail/sphere_soa.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/geometry/aabb.h"

namespace hail {

struct SphereQueryBvh {
  /// Spheres per leaf: 4 keeps the primitive tests per leaf few for rays that graze a leaf.
  static constexpr int kLeafSize = 4;

  FlatBvh bvh;
  std::vector<float> x, y, z, r;        ///< centre and radius, BVH order, m
  std::vector<std::uint32_t> category;  ///< collision category, BVH order
  std::vector<SphereId> handle;         ///< BVH order
  std::vector<Aabb> bounds;             ///< build input, slot order (kept for its capacity)

  /// Rebuilds over spheres [0, size()): median split (deterministic, depends only on the
  /// boxes), O(n log n) on the calling thread; reuses capacity, so a rebuild at the same size
  /// does not allocate.
  void build(const SphereSoA& spheres);
  [[nodiscard]] std::size_t size() const { return handle.size(); }
};

}  // namespace hail
