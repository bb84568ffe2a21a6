#pragma once
// The flat BVH (the original design, after Wald et al. 2007 and Laine's restart trail): built
// once by splitting at the median along the longest axis, then stored depth-first in one array
// of 32-byte nodes, two per cache line. Each node keeps `skip`, the index of the node after its
// whole subtree, so a query is one loop with no stack and no pointers:
//
//   i = 0; while (i != END) { if (overlaps(node[i])) { if leaf: visit; i = i + 1 } else i = node[i].skip }
//
// (for a leaf i + 1 == skip; the last subtree's skip is END = 0xFFFFFFFF).

#include <cstdint>
#include <span>
#include <vector>

#include "soa/aligned_array.h"

namespace hail {

struct alignas(32) FlatNode {
  float min[3];
  std::uint32_t skip;  ///< next node when this box is missed (after the subtree); kFlatBvhEnd ends the walk
  float max[3];
  std::uint32_t leaf;  ///< 0 for inner nodes; leaves: (first primitive << 4) | count, count 1..8
};
static_assert(sizeof(FlatNode) == 32 && alignof(FlatNode) == 32, "FlatNode must be 32 bytes, two per cache line");

inline constexpr std::uint32_t kFlatBvhEnd = 0xFFFFFFFFu;
inline constexpr std::uint32_t kMaxLeafSize = 8;
inline constexpr std::uint32_t kMaxBvhPrimitives = 1u << 28;

inline std::uint32_t leaf_first(const FlatNode& n) { return n.leaf >> 4; }
inline std::uint32_t leaf_count(const FlatNode& n) { return n.leaf & 0xFu; }

/// Axis-aligned bounds of one primitive.
struct Aabb {
  float min[3], max[3];
};

struct FlatBvh {
  AlignedArray<FlatNode> nodes;
  /// primitive_order[k] = index (in the caller's input) of the k-th primitive in BVH order;
  /// leaves cover ranges of BVH order.
  std::vector<std::uint32_t> primitive_order;
};

/// Builds the flat BVH over `bounds` by median split on the longest axis of the centroids'
/// bounds; leaf_size in 1..8 (InvalidArgument otherwise). Deterministic.
FlatBvh build_flat_bvh(std::span<const Aabb> bounds, std::uint32_t leaf_size = 4);

/// True when the sphere touches the node's box (squared distance from the centre to the box).
inline bool sphere_overlaps_node(const FlatNode& n, float cx, float cy, float cz, float r) {
  auto excess = [](float c, float lo, float hi) { return c < lo ? lo - c : (c > hi ? c - hi : 0.0f); };
  const float dx = excess(cx, n.min[0], n.max[0]), dy = excess(cy, n.min[1], n.max[1]), dz = excess(cz, n.min[2], n.max[2]);
  return dx * dx + dy * dy + dz * dz <= r * r;
}

/// Stackless walk: visit(k) for every primitive k (BVH order) in a leaf the sphere touches.
/// Allocation-free.
template <class Visit>
void query_sphere_stackless(const FlatBvh& bvh, float cx, float cy, float cz, float r, Visit&& visit) {
  const FlatNode* nodes = bvh.nodes.data();
  if (bvh.nodes.size() == 0) return;
  std::uint32_t i = 0;
  while (i != kFlatBvhEnd) {
    const FlatNode& n = nodes[i];
    if (sphere_overlaps_node(n, cx, cy, cz, r)) {
      if (n.leaf != 0) {
        const std::uint32_t first = leaf_first(n), count = leaf_count(n);
        for (std::uint32_t k = first; k < first + count; ++k) visit(k);
        i = n.skip;  // == i + 1 for a leaf, and END after the last one
      } else {
        i = i + 1;
      }
    } else {
      i = n.skip;
    }
  }
}

/// The seed's alternative: the same query with a small fixed stack (left child i + 1, right
/// child = the left child's skip). For tests and the benchmark.
template <class Visit>
void query_sphere_stack(const FlatBvh& bvh, float cx, float cy, float cz, float r, Visit&& visit) {
  if (bvh.nodes.size() == 0) return;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t i = stack[--top];
    const FlatNode& n = bvh.nodes[i];
    if (!sphere_overlaps_node(n, cx, cy, cz, r)) continue;
    if (n.leaf != 0) {
      for (std::uint32_t k = leaf_first(n); k < leaf_first(n) + leaf_count(n); ++k) visit(k);
      continue;
    }
    stack[top++] = bvh.nodes[i + 1].skip;  // right child
    stack[top++] = i + 1;                  // left child first
  }
}

}  // namespace hail
