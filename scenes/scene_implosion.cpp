#include <cmath>

#include "scenes/scenes.h"

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
    const Vec3 position =
        1.5f * Vec3(static_cast<float>(k % side) - centre, static_cast<float>((k / side) % side) - centre,
                    static_cast<float>(k / (side * side)) - centre);
    const float distance = position.norm();
    const Vec3 velocity = distance > 0.0f ? Vec3(-5.0f * position / distance) : Vec3(Vec3::Zero());
    scene.ids.push_back(scene.world->add_sphere({.position = position,
                                                 .velocity = velocity,
                                                 .radius = 0.5f,
                                                 .mass = 1.0f,
                                                 .restitution = 1.0f,
                                                 .friction = 0.0f}));
  }
  return scene;
}

}  // namespace hail::bench
