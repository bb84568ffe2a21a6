#pragma once
// Pair search through a per-step BVH over the spheres: each sphere's box (centre +- its
// radius, widened) goes to the flat BVH builder (kernel/bvh/bvh_build.h), and each sphere queries
// it with its own box grown by the margin, through the stackless walk (query_aabb in
// kernel/bvh/flat_bvh.h). Candidates are tested with the brute-force predicate. It returns exactly
// the pairs of the brute-force search, in the same order (rows i ascending, j ascending within
// a row), so the choice of pair search never changes a simulation.
//
// Unlike a uniform grid, whose cells must fit the largest sphere, the tree adapts to mixed
// radii: a giant costs the walks that pass near it, not every lookup.

#include <cstdint>
#include <vector>

#include "hail/sphere_soa.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/geometry/aabb.h"
#include "soa/heap_bytes.h"

namespace hail {

class SphereBvhPairs {
 public:
  /// Build settings by default: median split, leaves of 8 spheres. Smaller leaves cost more
  /// time, build and walk together (hail-bench pairs: docs/benchmarks.md, "Figures behind the
  /// code's choices"); 8 is the builder's largest leaf.
  static constexpr BvhBuildOptions kDefaultOptions{.split = BvhSplit::Median, .leaf_size = 8};

  /// Rebuilds the BVH over the spheres' boxes. Serial, O(n log n); allocates only on growth.
  /// The boxes do not depend on the margin (the query box carries it), so find_pairs may be
  /// given any margin; `margin` is taken for the common interface.
  void build(const SphereSoA& spheres, float margin, const BvhBuildOptions& options = kDefaultOptions);
  /// Appends the pairs (i, j), i in [first, last), i < j, within `margin`, of the spheres as
  /// they were at the last build. `row` is caller-owned scratch so that disjoint row blocks can
  /// run in parallel.
  void find_pairs(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                  std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const;
  /// The BVH of the last build (primitive k in BVH order is sphere bvh().primitive_order[k]).
  [[nodiscard]] const FlatBvh& bvh() const { return bvh_; }

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(bvh_.nodes, bvh_.primitive_order, bounds_, leaf_);
  }

 private:
  /// A sphere as a leaf test reads it, stored in BVH order so that a leaf's spheres are adjacent.
  struct LeafSphere {
    float x, y, z, radius;
  };
  FlatBvh bvh_;
  std::vector<Aabb> bounds_;      // per sphere, input order (build scratch)
  std::vector<LeafSphere> leaf_;  // per primitive, BVH order
};

}  // namespace hail
