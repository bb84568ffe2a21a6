#pragma once
// The walks over a depth-first FlatNode array, generic in what is tested: `hits_node(node)`
// decides whether to enter a node and `visit_leaf(first, count)` receives each entered leaf's
// primitive range (BVH order). The named queries (sphere, box, ray) in kernel/bvh/flat_bvh.h are
// these walks with one test plugged in. Nothing here allocates.
//
// An optional last argument counts node visits for benchmarks: `count(i)` is called once per
// node whose box is tested. The default NoNodeCount is an empty inline call, so it costs nothing.

#include <cstdint>
#include <span>

#include "kernel/bvh/flat_node.h"

namespace hail {

/// Counts nothing: the default of every walk.
struct NoNodeCount {
  constexpr void operator()(std::uint32_t) const noexcept {}
};

/// Counts the nodes a walk tests (pass by reference, read `visited` afterwards).
struct NodeVisitCount {
  std::uint64_t visited = 0;
  constexpr void operator()(std::uint32_t) noexcept { ++visited; }
};

/// The stackless walk of docs/design.md: a hit on an inner node goes on to i + 1, a miss jumps to
/// skip. On a leaf hit it also takes skip, which is i + 1 except for the last node, whose skip
/// is kFlatBvhEnd. Every index taken is larger than the last, so each node is tested at most
/// once and the walk always ends.
template <class HitsNode, class VisitLeaf, class Count = NoNodeCount>
void walk_stackless(std::span<const FlatNode> nodes, HitsNode&& hits_node, VisitLeaf&& visit_leaf, Count&& count = {}) {
  if (nodes.empty()) return;
  const FlatNode* node = nodes.data();
  std::uint32_t i = 0;
  while (i != kFlatBvhEnd) {
    const FlatNode& n = node[i];
    count(i);
    if (hits_node(n)) {
      if (!is_leaf(n)) {
        i = i + 1;
        continue;
      }
      visit_leaf(leaf_first(n), leaf_count(n));
    }
    i = n.skip;
  }
}

/// The same walk with a fixed stack of kMaxBvhDepth entries (the seed's alternative, for
/// tests and the benchmark): on an inner-node hit it keeps the right child (nodes[i + 1].skip)
/// and descends into the left (i + 1). The stack holds at most one entry per level, and the
/// builder keeps every leaf above depth kMaxBvhDepth, so it cannot overflow.
template <class HitsNode, class VisitLeaf, class Count = NoNodeCount>
void walk_stack(std::span<const FlatNode> nodes, HitsNode&& hits_node, VisitLeaf&& visit_leaf, Count&& count = {}) {
  if (nodes.empty()) return;
  const FlatNode* node = nodes.data();
  std::uint32_t stack[kMaxBvhDepth];
  int top = 0;
  std::uint32_t i = 0;
  for (;;) {
    const FlatNode& n = node[i];
    count(i);
    if (hits_node(n)) {
      if (!is_leaf(n)) {
        stack[top++] = node[i + 1].skip;
        i = i + 1;
        continue;
      }
      visit_leaf(leaf_first(n), leaf_count(n));
    }
    if (top == 0) return;
    i = stack[--top];
  }
}

}  // namespace hail
