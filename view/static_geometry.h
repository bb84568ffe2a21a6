#pragma once
// What the renderer draws besides spheres: the terrain's heightmap, its BVH's node boxes (for
// --draw-bvh), the planes and the meshes' triangles, copied out of a World once (they never change during a run), so that the render thread never reads the
// World the simulation thread steps.

#include <optional>
#include <vector>

#include "hail/debug_draw.h"
#include "hail/heightmap.h"
#include "hail/plane.h"
#include "hail/world.h"

namespace hail::view {

struct StaticGeometry {
  std::optional<Heightmap> terrain;
  std::vector<BvhNodeBox> terrain_bvh;  ///< terrain_bvh_boxes: every node, depth-first
  std::vector<Plane> planes;
  std::vector<TerrainTriangle> meshes;  ///< World::mesh_triangles

  [[nodiscard]] static StaticGeometry of(const World& world) {
    StaticGeometry g;
    if (world.terrain()) {
      g.terrain.emplace(world.terrain()->heightmap());
      terrain_bvh_boxes(*world.terrain(), g.terrain_bvh);
    }
    g.planes.assign(world.planes().begin(), world.planes().end());
    world.mesh_triangles(g.meshes);
    return g;
  }
  [[nodiscard]] const Heightmap* heightmap() const { return terrain ? &*terrain : nullptr; }
};

}  // namespace hail::view
