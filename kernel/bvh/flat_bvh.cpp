#include "kernel/bvh/flat_bvh.h"

#include <string>

#include "hail/errors.h"

namespace hail {

void FlatBvh::build(std::span<const Aabb> bounds, const BvhBuildOptions& options) {
  build_bvh(bounds, options, nodes, primitive_order);
}

FlatBvh build_flat_bvh(std::span<const Aabb> bounds, const BvhBuildOptions& options) {
  FlatBvh bvh;
  bvh.build(bounds, options);
  return bvh;
}

FlatBvh build_flat_bvh(std::span<const Aabb> bounds, std::uint32_t leaf_size) {
  // Checked here so that a huge unsigned value is reported as given, not wrapped into an int.
  if (leaf_size < 1 || leaf_size > kMaxLeafSize)
    throw InvalidArgument("hail: BVH leaf_size must be in 1.." + std::to_string(kMaxLeafSize) + ", got " +
                          std::to_string(leaf_size));
  return build_flat_bvh(bounds, BvhBuildOptions{.split = BvhSplit::Median, .leaf_size = static_cast<int>(leaf_size)});
}

}  // namespace hail
