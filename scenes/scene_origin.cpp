// `hail-bench run --origin D`: the same scene, moved D metres along x and z, to measure what
// distance from the origin costs in precision (docs/accuracy.md, "Precision far from the
// origin"). The scene is built where it always is and then moved with World::shift_origin, so
// each starting position is rounded once, to the float spacing where it lands, exactly as a
// scene built out there would be.
#include "scenes/scenes.h"

namespace hail::bench {

void move_scene(Scene& scene, const Vec3& by) {
  World& world = *scene.world;
  world.shift_origin(-by);
  scene.min_x += by.x(), scene.max_x += by.x();
  scene.min_z += by.z(), scene.max_z += by.z();
  if (const Terrain* terrain = world.terrain()) {
    // The World holds a moved copy now: judge tunnelling on it, not on the old terrain shifted
    // back (x - D would round again).
    scene.min_x = terrain->heightmap().x_of(0), scene.max_x = terrain->heightmap().max_x();
    scene.min_z = terrain->heightmap().z_of(0), scene.max_z = terrain->heightmap().max_z();
    scene.ground_height = [&world](float x, float z) { return world.terrain()->heightmap().surface_height(x, z); };
  } else if (scene.ground_height) {
    scene.ground_height = [old = scene.ground_height, by](float x, float z) {
      return old(x - by.x(), z - by.z()) + by.y();
    };
  }
  scene.description +=
      " (moved by (" + std::to_string(by.x()) + ", " + std::to_string(by.y()) + ", " + std::to_string(by.z()) + ") m)";
}

}  // namespace hail::bench
