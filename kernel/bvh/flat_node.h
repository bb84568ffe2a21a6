#pragma once
// FlatNode: one node of the flat BVH, 32 bytes so that two share a cache line (the layout and
// the walk are explained at the top of kernel/bvh/flat_bvh.h), and the limits its packing implies.

#include <cstdint>
#include <type_traits>

namespace hail {

/// A node of the depth-first node array. Inner nodes have leaf == 0; their children are
/// i + 1 (left) and nodes[i + 1].skip (right).
struct alignas(32) FlatNode {
  float min[3];
  std::uint32_t skip;  ///< next node when this box is missed: the node after the subtree; kFlatBvhEnd ends the walk
  float max[3];
  std::uint32_t leaf;  ///< 0 for inner nodes; leaves: (first primitive << kLeafCountBits) | count, count 1..8
};
static_assert(sizeof(FlatNode) == 32 && alignof(FlatNode) == 32, "FlatNode must be 32 bytes, two per cache line");
static_assert(std::is_trivially_copyable_v<FlatNode> && std::is_standard_layout_v<FlatNode>);

/// The `skip` of the last subtree: the walk ends here.
inline constexpr std::uint32_t kFlatBvhEnd = 0xFFFFFFFFu;
/// Low bits of FlatNode::leaf holding a leaf's primitive count.
inline constexpr std::uint32_t kLeafCountBits = 4;
/// Largest leaf (BvhBuildOptions::leaf_size): leaves are tested without a loop bound check
/// beyond this, and 8 is one AVX2 batch of triangles.
inline constexpr std::uint32_t kMaxLeafSize = 8;
/// Most primitives one BVH can index: the first primitive of a leaf has 32 - 4 bits.
inline constexpr std::uint32_t kMaxBvhPrimitives = 1u << (32 - kLeafCountBits);
/// Deepest leaf + 1: the stack walk's fixed stack holds at most one entry per level above the
/// current node, so kMaxBvhDepth entries always suffice; the builder guarantees the bound.
inline constexpr int kMaxBvhDepth = 64;

static_assert(kMaxLeafSize < (1u << kLeafCountBits), "a leaf's count must fit its bits, and 0 must mean inner");
// A binary tree over n primitives with non-empty leaves has at most 2n - 1 nodes: indices and
// skips never reach kFlatBvhEnd.
static_assert(2ull * kMaxBvhPrimitives - 1 < kFlatBvhEnd);

/// True for a leaf node.
[[nodiscard]] constexpr bool is_leaf(const FlatNode& n) { return n.leaf != 0; }
/// First primitive (BVH order) of a leaf.
[[nodiscard]] constexpr std::uint32_t leaf_first(const FlatNode& n) { return n.leaf >> kLeafCountBits; }
/// Primitive count of a leaf (1..kMaxLeafSize); 0 for inner nodes.
[[nodiscard]] constexpr std::uint32_t leaf_count(const FlatNode& n) { return n.leaf & ((1u << kLeafCountBits) - 1); }
/// The `leaf` field of a leaf over primitives [first, first + count); requires count in 1..8
/// and first < kMaxBvhPrimitives (the builder checks both).
[[nodiscard]] constexpr std::uint32_t encode_leaf(std::uint32_t first, std::uint32_t count) {
  return (first << kLeafCountBits) | count;
}

}  // namespace hail
