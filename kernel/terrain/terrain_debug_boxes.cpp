#include <utility>

#include "hail/debug_draw.h"
#include "hail/terrain.h"
#include "kernel/bvh/flat_bvh.h"

namespace hail {

void terrain_bvh_boxes(const Terrain& terrain, std::vector<BvhNodeBox>& out) {
  const std::vector<FlatNode>& nodes = terrain.bvh().nodes;
  out.clear();
  out.reserve(nodes.size());
  // Depth-first pre-order: an inner node's children are i + 1 (left) and nodes[i + 1].skip
  // (right, flat_bvh.h), both one level below it. A leaf has none, so the depth of node i + 1
  // is set by whichever inner node names it; walking in index order, that node comes first.
  std::vector<std::uint32_t> depth(nodes.size(), 0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const FlatNode& n = nodes[i];
    if (!is_leaf(n)) {
      const std::size_t left = i + 1, right = nodes[left].skip;
      depth[left] = depth[i] + 1;
      if (right < nodes.size()) depth[right] = depth[i] + 1;
    }
    out.push_back({.box = {.min = Vec3(n.min[0], n.min[1], n.min[2]), .max = Vec3(n.max[0], n.max[1], n.max[2])},
                   .depth = depth[i],
                   .leaf = is_leaf(n)});
  }
}

}  // namespace hail
