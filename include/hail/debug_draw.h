#pragma once
// Read-only views of the kernel's acceleration structures as boxes, for drawing them (hail-view's
// debug lines, a game's debug overlay): the terrain BVH's nodes (terrain_bvh_boxes) and the
// occupied cells of the pair grid the last step searched (World::pair_grid_cells). They copy
// into the caller's vector and change nothing; neither is meant for a hot loop.

#include <cstdint>
#include <vector>

#include "hail/vec3.h"

namespace hail {

class Terrain;

/// An axis-aligned box, m.
struct DebugBox {
  Vec3 min{0.0f, 0.0f, 0.0f};
  Vec3 max{0.0f, 0.0f, 0.0f};
};

/// One node of a BVH: its box, its depth (the root's is 0) and whether it is a leaf.
struct BvhNodeBox {
  DebugBox box;
  std::uint32_t depth = 0;
  bool leaf = false;
};

/// Every node of the terrain's BVH (Terrain::bvh), depth-first (the root first, each node's
/// left subtree before its right), into `out` (replacing what it held). Terrain-rain's map
/// has about 2 x triangles / 8 nodes (leaves of 8 triangles).
void terrain_bvh_boxes(const Terrain& terrain, std::vector<BvhNodeBox>& out);

}  // namespace hail
