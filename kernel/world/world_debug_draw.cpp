// World::pair_grid_cells: the pair grid of the last step as boxes, for drawing
// (include/hail/debug_draw.h).

#include "hail/world.h"
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

}  // namespace hail
