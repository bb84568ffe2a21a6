// World::pair_grid_cells (the pair grid of the last step as boxes, include/hail/debug_draw.h) and
// World::mesh_triangles (the meshes' triangles): what hail-view and a game's overlay draw.

#include "hail/world.h"
#include "kernel/mesh/mesh_set.h"
#include "kernel/world/step_scratch.h"

namespace hail {

void World::pair_grid_cells(std::vector<DebugBox>& out) const {
  // The grid's arrays outlive the step that built them (scratch reused by the next one):
  // stats_ says whether the last step built them.
  if (!stats_.ran.detect_pairs || stats_.pair_search != PairSearch::Grid) {
    out.clear();
    return;
  }
  scratch_->grid.occupied_cells(out);
}

void World::mesh_triangles(std::vector<TerrainTriangle>& out) const {
  out.clear();
  for (std::size_t m = 0; m < mesh_count(); ++m) {
    const TerrainTriangles& t = (*meshes_)[m].triangles;
    for (std::size_t k = 0; k < t.size(); ++k)
      out.push_back({Vec3(t.v0x[k], t.v0y[k], t.v0z[k]), Vec3(t.v1x[k], t.v1y[k], t.v1z[k]),
                     Vec3(t.v2x[k], t.v2y[k], t.v2z[k]), Vec3(t.nx[k], t.ny[k], t.nz[k])});
  }
}

}  // namespace hail
