#pragma once
// Flat terrain at height 0 for the tests' small worlds: `cells` x `cells` heights 1 m apart,
// from (0, 0).

#include <memory>

#include "hail/heightmap.h"
#include "kernel/terrain/terrain_parts.h"

namespace hail::testing {

inline std::shared_ptr<const Terrain> flat_ground(int cells = 64) {
  return std::make_shared<const Terrain>(
      Heightmap::from_function(cells, cells, HeightmapParams{}, [](float, float) { return 0.0f; }));
}

}  // namespace hail::testing
