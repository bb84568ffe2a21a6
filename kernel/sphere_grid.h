#pragma once
// Uniform-grid pair search for many spheres: spheres are counting-sorted into hashed cells of
// the largest diameter (plus margin), and each sphere tests the 27 cells around its own. It
// returns exactly the pairs of the brute-force search, in the same order (rows i ascending,
// j ascending within a row), so the choice of pair search never changes a simulation.

#include <cstdint>
#include <vector>

#include "kernel/sphere_pairs.h"
#include "soa/sphere_soa.h"

namespace hail {

class SphereGrid {
 public:
  /// Sorts the spheres into cells for this margin. Serial, O(n); allocates only on growth.
  void build(const SphereSoA& spheres, float margin);
  /// Appends the pairs (i, j), i in [first, last), i < j, within `margin` (the one given to
  /// build). `row` is caller-owned scratch so that blocks can run in parallel.
  void find_pairs(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                  std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const;

 private:
  [[nodiscard]] std::uint32_t bucket_of(std::int32_t x, std::int32_t y, std::int32_t z) const;
  float inv_cell_ = 1.0f;
  std::uint32_t mask_ = 0;
  std::vector<std::int32_t> cell_;          // per sphere: x, y, z cell coordinates
  std::vector<std::uint32_t> bucket_start_; // bucket b holds sorted_[bucket_start_[b] .. [b+1])
  std::vector<std::uint32_t> sorted_;       // sphere indices grouped by bucket
};

}  // namespace hail
