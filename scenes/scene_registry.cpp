#include "scenes/scenes.h"

namespace hail::bench {

const std::vector<SceneEntry>& scene_registry() {
  static const std::vector<SceneEntry> scenes = {
      {"terrain-rain", "the main benchmark: N spheres rain onto a 256^2 sine heightmap (130,050 triangles)",
       build_terrain_rain},
      {"terrain-rain-dem", "terrain-rain on the real Jacksboro SRTM DEM (403 x 344, 1 m cells, heights / 80)",
       build_terrain_rain_dem},
      {"bowl-pile", "stiff: a deep column of spheres settling in a paraboloid bowl, 1200 steps", build_bowl_pile},
      {"bullets", "spheres fired at terrain-rain's terrain at 100..1000 m/s: what continuous collision prevents",
       build_bullets},
      {"implosion", "spheres only: lattice imploding at 5 m/s, e = 1 (momentum and energy must hold)", build_implosion},
  };
  return scenes;
}

}  // namespace hail::bench
