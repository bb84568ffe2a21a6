#include <cmath>

#include "scenes.h"

namespace hail::bench {

// implosion: N spheres of radius 0.5 on a cubic lattice of spacing 1.5 m centred on the origin,
// each moving towards the origin at 5 m/s; restitution 1, friction 0; no terrain, no gravity.
Scene build_implosion(const SceneParams& p) {
  WorldSettings settings = world_settings(p);
  settings.gravity = Vec3::Zero();
  Scene scene;
  scene.world = std::make_unique<World>(settings);
  scene.default_steps = 600;
  scene.dt = p.dt;
  scene.description = "implosion: cubic lattice, spacing 1.5 m, 5 m/s towards the origin, e = 1, mu = 0";
  const std::size_t side = static_cast<std::size_t>(std::ceil(std::cbrt(static_cast<double>(p.spheres))));
  const float centre = 0.5f * static_cast<float>(side - 1);
  scene.world->reserve(p.spheres);
  scene.ids.reserve(p.spheres);
  for (std::size_t k = 0; k < p.spheres; ++k) {
    const Vec3 position = 1.5f * Vec3(static_cast<float>(k % side) - centre,
                                      static_cast<float>((k / side) % side) - centre,
                                      static_cast<float>(k / (side * side)) - centre);
    const float distance = position.norm();
    const Vec3 velocity = distance > 0.0f ? Vec3(-5.0f * position / distance) : Vec3(Vec3::Zero());
    scene.ids.push_back(scene.world->add_sphere({.position = position, .velocity = velocity, .radius = 0.5f,
                                                 .mass = 1.0f, .restitution = 1.0f, .friction = 0.0f}));
  }
  return scene;
}

const std::vector<SceneEntry>& scene_registry() {
  static const std::vector<SceneEntry> scenes = {
      {"terrain-rain", "the main benchmark: N spheres rain onto a 256^2 sine heightmap (130,050 triangles)", build_terrain_rain},
      {"terrain-rain-dem", "terrain-rain on the real Jacksboro SRTM DEM (403 x 344, 1 m cells, heights / 80)", build_terrain_rain_dem},
      {"bowl-pile", "stiff: a deep column of spheres settling in a paraboloid bowl, 1200 steps", build_bowl_pile},
      {"bullets", "spheres fired at terrain-rain's terrain at 100..1000 m/s: what continuous collision prevents", build_bullets},
      {"implosion", "spheres only: lattice imploding at 5 m/s, e = 1 (momentum and energy must hold)", build_implosion},
  };
  return scenes;
}

}  // namespace hail::bench
