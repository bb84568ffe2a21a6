#pragma once
// The BVH builder: primitive bounds in, the depth-first FlatNode array and the permutation of
// the primitives into BVH order out. Generic over primitives (terrain triangles now, spheres
// later): it only reads their Aabbs.

#include <cstdint>
#include <span>
#include <vector>

#include "kernel/bvh/flat_node.h"
#include "kernel/geometry/aabb.h"

namespace hail {

/// How a node's primitives are divided between its two children.
enum class BvhSplit : std::uint8_t {
  /// Half the primitives each side of the median centroid along the longest axis of the
  /// centroids' bounds (the original design). Balanced: depth ceil(log2(n / leaf_size)).
  Median,
  /// Binned surface area heuristic (16 bins per axis). Fewer nodes visited on uneven data;
  /// from depth 35 on it falls back to Median so that no leaf is deeper than kMaxBvhDepth.
  BinnedSah,
  /// Each node's range halved in input order, nothing moved (primitive_order is the identity):
  /// for primitives that already lie in a spatially coherent order, such as a World's slots in
  /// Morton order. The shape depends on the count alone, so the boxes are computed bottom-up in
  /// O(n), with no centroid pass or partition per level: for BVHs rebuilt every step (the
  /// sweep's path boxes). On incoherent input every node's box is large and queries slow down.
  InputOrder,
};

/// Build settings; both fields are checked (InvalidArgument).
struct BvhBuildOptions {
  BvhSplit split = BvhSplit::Median;
  /// Most primitives per leaf, 1..kMaxLeafSize. A node becomes a leaf exactly when it holds
  /// this many or fewer. Small: more nodes (32 B each) and node tests; large: more primitive tests.
  int leaf_size = 4;
};

/// Builds the flat BVH over `bounds` into `nodes` and `primitive_order` (their previous
/// contents are replaced; their capacity is reused, so a rebuild of the same size does not
/// allocate). primitive_order[k] is the index in `bounds` of the k-th primitive in BVH order;
/// leaves cover ranges of BVH order, sorted by input index within a leaf. The result depends
/// only on `bounds` and `options` (deterministic, independent of the standard library's
/// sort). Empty input gives no nodes. Throws InvalidArgument, leaving the outputs unchanged,
/// for a bad option, more than kMaxBvhPrimitives primitives, or a non-finite or inverted box.
/// Extra memory beyond the outputs: O(depth); centroids are recomputed, not stored.
void build_bvh(std::span<const Aabb> bounds, const BvhBuildOptions& options, std::vector<FlatNode>& nodes,
               std::vector<std::uint32_t>& primitive_order);

}  // namespace hail
