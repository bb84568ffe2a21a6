#pragma once
// The flat BVH (the original design, after Wald et al. 2007 and Laine's restart trail,
// "Restart Trail for Stackless BVH Traversal", HPG 2010): built once over primitive boxes
// (kernel/bvh/bvh_build.h), then stored in depth-first pre-order in one array of 32-byte
// FlatNodes, two per cache line. A node's subtree is the contiguous run of nodes after it, so
// its left child is i + 1, and `skip`, the index of the node after the whole subtree, is at once
// "where to go when this box is missed" and the right child of its parent (nodes[i + 1].skip).
// A query is one loop with no stack and no pointers:
//
//   i = 0; while (i != END) { if (overlaps(node[i])) { if leaf: visit; i = i + 1 } else i = node[i].skip }
//
// (for a leaf i + 1 == skip, except for the last node whose skip is END = 0xFFFFFFFF). The walk
// cannot visit children in front-to-back order or stop early from a stack, which a sphere
// query never needs; the ray query prunes by its best hit so far instead.
//
// Primitive indices: the builder permutes primitives into BVH order so that each leaf covers a
// contiguous range; every query reports k in BVH order. primitive_order[k] is the caller's
// original index. Callers that store per-primitive data in BVH order (as the terrain does)
// index it with k directly.
//
// SIMD: a stackless walk tests one node per step and branches on the result, so there is
// nothing to vectorise per node (3 lanes of 8). The win is in packets of spheres per node and
// in testing a leaf's primitives for all of them at once: kernel/bvh/bvh_packet_walk.h.

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "kernel/bvh/bvh_build.h"
#include "kernel/bvh/bvh_walk.h"
#include "kernel/bvh/flat_node.h"
#include "kernel/geometry/aabb.h"

namespace hail {

/// A built flat BVH: the node array and the primitive permutation. `nodes` lives in a
/// std::vector whose std::allocator (C++17) honours alignas(32), so nodes never straddle a
/// cache line. The members are public for the existing terrain code; treat them as read-only,
/// the walks rely on the skip links the builder wrote.
struct FlatBvh {
  std::vector<FlatNode> nodes;  ///< depth-first; empty for no primitives
  /// primitive_order[k] = index (in the builder's input) of the k-th primitive in BVH order.
  std::vector<std::uint32_t> primitive_order;

  /// Rebuilds over `bounds` (see build_bvh: deterministic, reuses capacity, throws
  /// InvalidArgument and leaves the BVH unchanged on bad input).
  void build(std::span<const Aabb> bounds, const BvhBuildOptions& options = {});
  /// Number of primitives indexed.
  [[nodiscard]] std::size_t primitive_count() const { return primitive_order.size(); }
};

/// A new FlatBvh over `bounds`.
[[nodiscard]] FlatBvh build_flat_bvh(std::span<const Aabb> bounds, const BvhBuildOptions& options = {});
/// A new median-split FlatBvh with the given leaf size (1..8; InvalidArgument otherwise).
[[nodiscard]] FlatBvh build_flat_bvh(std::span<const Aabb> bounds, std::uint32_t leaf_size);

/// Stackless sphere query: visit(k) for every primitive k (BVH order) of every leaf whose box
/// the sphere touches. These are candidates: the caller tests the primitive itself.
template <class Visit, class Count = NoNodeCount>
void query_sphere(const FlatBvh& bvh, float cx, float cy, float cz, float r, Visit&& visit, Count&& count = {}) {
  walk_stackless(
      bvh.nodes, [&](const FlatNode& n) { return sphere_overlaps(n, cx, cy, cz, r); },
      [&](std::uint32_t first, std::uint32_t n) {
        for (std::uint32_t k = first; k < first + n; ++k) visit(k);
      },
      count);
}

/// query_sphere with the fixed-stack walk: the same candidates, in the same order.
template <class Visit, class Count = NoNodeCount>
void query_sphere_stack(const FlatBvh& bvh, float cx, float cy, float cz, float r, Visit&& visit, Count&& count = {}) {
  walk_stack(
      bvh.nodes, [&](const FlatNode& n) { return sphere_overlaps(n, cx, cy, cz, r); },
      [&](std::uint32_t first, std::uint32_t n) {
        for (std::uint32_t k = first; k < first + n; ++k) visit(k);
      },
      count);
}

/// Stackless box query: visit(k) for every primitive k (BVH order) of every leaf whose box
/// touches `box` (closed boxes: touching faces count).
template <class Visit, class Count = NoNodeCount>
void query_aabb(const FlatBvh& bvh, const Aabb& box, Visit&& visit, Count&& count = {}) {
  walk_stackless(
      bvh.nodes, [&](const FlatNode& n) { return overlaps(n, box); },
      [&](std::uint32_t first, std::uint32_t n) {
        for (std::uint32_t k = first; k < first + n; ++k) visit(k);
      },
      count);
}

/// query_aabb with the fixed-stack walk.
template <class Visit, class Count = NoNodeCount>
void query_aabb_stack(const FlatBvh& bvh, const Aabb& box, Visit&& visit, Count&& count = {}) {
  walk_stack(
      bvh.nodes, [&](const FlatNode& n) { return overlaps(n, box); },
      [&](std::uint32_t first, std::uint32_t n) {
        for (std::uint32_t k = first; k < first + n; ++k) visit(k);
      },
      count);
}

/// kNoPrimitive in RayHit::primitive: the ray hit nothing.
inline constexpr std::uint32_t kNoPrimitive = 0xFFFFFFFFu;

/// Nearest hit of a ray query: t and primitive (BVH order), or {t_max, kNoPrimitive}.
struct RayHit {
  float t;
  std::uint32_t primitive;
};

/// Nearest-hit ray query over o + t d, t in [0, t_max): intersect(k) returns the hit distance
/// of primitive k (BVH order), or anything negative, NaN or >= the best so far for a miss (a
/// tie keeps the first hit found). Stackless; nodes whose entry distance exceeds the best hit
/// so far are skipped. `dir` need not be unit; t is in units of |dir|.
/// Earliest hit of a sphere of radius r swept along o + t d, t in [0, t_max): the stackless ray
/// walk with every node box grown by r, so the path's whole width is covered; intersect(k)
/// returns the sphere's time of impact with primitive k, or anything negative, NaN or >= the
/// best so far for a miss (a tie keeps the first hit found). Only the leaves along
/// the path are visited, and those entered after the earliest hit so far are skipped, where a
/// box around the whole path (query_aabb) would visit every leaf it spans.
template <class Intersect, class Count = NoNodeCount>
[[nodiscard]] RayHit query_swept_sphere(const FlatBvh& bvh, const float origin[3], const float dir[3], float t_max,
                                        float r, Intersect&& intersect, Count&& count = {}) {
  const float inv_dir[3] = {1.0f / dir[0], 1.0f / dir[1], 1.0f / dir[2]};
  RayHit best{t_max, kNoPrimitive};
  walk_stackless(
      bvh.nodes, [&](const FlatNode& n) { return ray_overlaps(n, origin, inv_dir, best.t, r); },
      [&](std::uint32_t first, std::uint32_t n) {
        for (std::uint32_t k = first; k < first + n; ++k) {
          const float t = intersect(k);
          if (t >= 0.0f && t < best.t) best = RayHit{t, k};
        }
      },
      count);
  return best;
}

/// Nearest-hit ray query over o + t d, t in [0, t_max): intersect(k) returns the hit distance
/// of primitive k (BVH order), or anything negative, NaN or >= the best so far for a miss (a
/// tie keeps the first hit found). Stackless; nodes whose entry distance exceeds the best hit
/// so far are skipped. `dir` need not be unit; t is in units of |dir|. (A swept sphere of
/// radius 0: the node boxes are not grown.)
template <class Intersect, class Count = NoNodeCount>
[[nodiscard]] RayHit query_ray(const FlatBvh& bvh, const float origin[3], const float dir[3], float t_max,
                               Intersect&& intersect, Count&& count = {}) {
  return query_swept_sphere(bvh, origin, dir, t_max, 0.0f, std::forward<Intersect>(intersect),
                            std::forward<Count>(count));
}

/// Brute force beside the BVH (tests, benchmark): visit(i) for every box bounds[i] the sphere
/// touches, in index order. Exact per primitive, where the BVH gives leaf candidates.
template <class Visit>
void brute_force_sphere(std::span<const Aabb> bounds, float cx, float cy, float cz, float r, Visit&& visit) {
  for (std::uint32_t i = 0; i < bounds.size(); ++i)
    if (sphere_overlaps(bounds[i], cx, cy, cz, r)) visit(i);
}

/// Brute force: visit(i) for every box bounds[i] that touches `box`.
template <class Visit>
void brute_force_aabb(std::span<const Aabb> bounds, const Aabb& box, Visit&& visit) {
  for (std::uint32_t i = 0; i < bounds.size(); ++i)
    if (overlaps(bounds[i], box)) visit(i);
}

/// Brute force nearest hit over primitives 0..count-1, with query_ray's rules for intersect.
template <class Intersect>
[[nodiscard]] RayHit brute_force_ray(std::uint32_t count, float t_max, Intersect&& intersect) {
  RayHit best{t_max, kNoPrimitive};
  for (std::uint32_t k = 0; k < count; ++k) {
    const float t = intersect(k);
    if (t >= 0.0f && t < best.t) best = RayHit{t, k};
  }
  return best;
}

}  // namespace hail
