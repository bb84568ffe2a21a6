#include "kernel/flat_bvh.h"

#include <algorithm>
#include <string>

#include "kernel/errors.h"

namespace hail {
namespace {

struct Builder {
  std::span<const Aabb> bounds;
  std::vector<float> centroid;  // 3 per primitive
  std::vector<std::uint32_t>& order;
  AlignedArray<FlatNode>& nodes;
  std::uint32_t leaf_size;

  void build(std::uint32_t first, std::uint32_t count) {
    const std::size_t index = nodes.size();
    FlatNode node{};
    for (int a = 0; a < 3; ++a) {
      node.min[a] = 3.0e38f;
      node.max[a] = -3.0e38f;
    }
    float cmin[3] = {3.0e38f, 3.0e38f, 3.0e38f}, cmax[3] = {-3.0e38f, -3.0e38f, -3.0e38f};
    for (std::uint32_t k = first; k < first + count; ++k) {
      const Aabb& b = bounds[order[k]];
      for (int a = 0; a < 3; ++a) {
        node.min[a] = std::min(node.min[a], b.min[a]);
        node.max[a] = std::max(node.max[a], b.max[a]);
        cmin[a] = std::min(cmin[a], centroid[3 * order[k] + a]);
        cmax[a] = std::max(cmax[a], centroid[3 * order[k] + a]);
      }
    }
    nodes.resize(index + 1, node);
    if (count <= leaf_size) {
      nodes[index].leaf = (first << 4) | count;
      nodes[index].skip = static_cast<std::uint32_t>(index + 1);
      return;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (cmax[a] - cmin[a] > cmax[axis] - cmin[axis]) axis = a;
    const std::uint32_t half = count / 2;
    // Median split; ties broken by primitive index so the tree never depends on the sort's whims.
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](std::uint32_t a, std::uint32_t b) {
                       const float ca = centroid[3 * a + axis], cb = centroid[3 * b + axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    build(first, half);
    build(first + half, count - half);
    nodes[index].leaf = 0;
    nodes[index].skip = static_cast<std::uint32_t>(nodes.size());
  }
};

}  // namespace

FlatBvh build_flat_bvh(std::span<const Aabb> bounds, std::uint32_t leaf_size) {
  if (leaf_size < 1 || leaf_size > kMaxLeafSize)
    throw InvalidArgument("hail: BVH leaf_size must be in 1..8, got " + std::to_string(leaf_size));
  if (bounds.size() >= kMaxBvhPrimitives)
    throw InvalidArgument("hail: BVH over " + std::to_string(bounds.size()) + " primitives exceeds 2^28");
  FlatBvh bvh;
  bvh.primitive_order.resize(bounds.size());
  for (std::uint32_t k = 0; k < bounds.size(); ++k) bvh.primitive_order[k] = k;
  if (bounds.empty()) return bvh;
  Builder builder{bounds, std::vector<float>(3 * bounds.size()), bvh.primitive_order, bvh.nodes, leaf_size};
  for (std::size_t k = 0; k < bounds.size(); ++k)
    for (int a = 0; a < 3; ++a) builder.centroid[3 * k + a] = 0.5f * (bounds[k].min[a] + bounds[k].max[a]);
  bvh.nodes.reserve(2 * (bounds.size() / leaf_size + 1));
  builder.build(0, static_cast<std::uint32_t>(bounds.size()));
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i)
    if (bvh.nodes[i].skip == bvh.nodes.size()) bvh.nodes[i].skip = kFlatBvhEnd;
  return bvh;
}

}  // namespace hail
