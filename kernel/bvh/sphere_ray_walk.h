#pragma once
// The closest sphere along a ray, through SphereQueryBvh: World::raycast, sphere_cast and
// raycast_batch (kernel/world/world_queries.cpp). One walk, two leaf tests: the scalar
// reference here (closest_sphere_scalar) and the SIMD one that tests a leaf's spheres in lanes
// (kernel/simd/sphere_rays.cpp, SimdKernels::closest_sphere_rays). Both compute each sphere's
// distance with ray_sphere's float operations in its order and keep the candidates by the same
// rule, so they give the same bits (tests/test_queries.cpp). The functions live in the
// per-path namespace (kernel/dispatch/simd_namespace.h): the SIMD translation units include
// them too, and their copies must not be merged with the base ones.

#include <cstdint>

#include "hail/queries.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/bvh/sphere_query_bvh.h"
#include "kernel/dispatch/simd_namespace.h"
#include "kernel/geometry/ray_sphere.h"

namespace hail {

/// A checked ray: origin, unit direction (float division by the float length, the same bits
/// everywhere: -ffp-contract=off), max distance.
struct UnitRay {
  float o[3];
  float d[3];
  float max;
};

/// The closest sphere of a ray: its distance and its index in BVH order (kNoPrimitive: none,
/// and t is then the ray's max).
struct SphereRayHit {
  float t;
  std::uint32_t k;
};

inline namespace HAIL_SIMD_NS {

[[nodiscard]] inline bool sphere_passes(const SphereQueryBvh& s, std::uint32_t k, const QueryFilter& filter) {
  return (s.category[k] & filter.mask) != 0 && !(s.handle[k] == filter.ignore);
}

/// Offers sphere k, met at t (ray_sphere's value), to the best so far: kept when in [0, max)
/// and nearer, or as near with a lower handle index. The minimum of (distance, handle index),
/// so the order in which spheres are offered does not matter.
inline void offer_sphere(const SphereQueryBvh& s, std::uint32_t k, float t, float max, SphereRayHit& best) {
  if (!(t >= 0.0f && t < max && t <= best.t)) return;  // [0, max), and no further than the best
  const bool tie_won = t == best.t && best.k != kNoPrimitive && s.handle[k].index < s.handle[best.k].index;
  if (t < best.t || best.k == kNoPrimitive || tie_won) best = {t, k};
}

/// The walk: stackless, pruned by the best distance so far (closed, so equal distances are
/// still visited and the lower handle index wins). hits_node(node, best_t) is ray_overlaps
/// with t_max = best_t, or code with its answers; test_leaf(first, count, best) offers the
/// leaf's spheres [first, first + count) that pass the filter.
template <class HitsNode, class TestLeaf>
[[nodiscard]] SphereRayHit walk_sphere_ray(const SphereQueryBvh& s, float t_max, HitsNode&& hits_node,
                                           TestLeaf&& test_leaf) {
  SphereRayHit best{t_max, kNoPrimitive};
  walk_stackless(
      s.bvh.nodes, [&](const FlatNode& n) { return hits_node(n, best.t); },
      [&](std::uint32_t first, std::uint32_t count) { test_leaf(first, count, best); });
  return best;
}

/// The scalar leaf test: one sphere at a time.
inline void test_leaf_scalar(const SphereQueryBvh& s, const UnitRay& r, float grow, const QueryFilter& filter,
                             std::uint32_t first, std::uint32_t count, SphereRayHit& best) {
  for (std::uint32_t k = first; k < first + count; ++k)
    if (sphere_passes(s, k, filter))
      offer_sphere(s, k, ray_sphere(r.o, r.d, s.x[k], s.y[k], s.z[k], s.r[k] + grow), r.max, best);
}

/// The scalar reference: the closest sphere hit of a ball of radius `grow` swept along r
/// (grow 0: a ray).
[[nodiscard]] inline SphereRayHit closest_sphere_scalar(const SphereQueryBvh& s, const UnitRay& r, float grow,
                                                        const QueryFilter& filter) {
  const float inv[3] = {1.0f / r.d[0], 1.0f / r.d[1], 1.0f / r.d[2]};
  return walk_sphere_ray(
      s, r.max, [&](const FlatNode& n, float best_t) { return ray_overlaps(n, r.o, inv, best_t, grow); },
      [&](std::uint32_t first, std::uint32_t count, SphereRayHit& best) {
        test_leaf_scalar(s, r, grow, filter, first, count, best);
      });
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
