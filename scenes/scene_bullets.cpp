// bullets: terrain-rain's terrain with spheres fired at it at 100 to 1,000 m/s, the scene that
// shows what continuous collision prevents (docs/continuous-collision.md). Defined exactly,
// random numbers included, so that other engines can run the same scene.

#include <cmath>
#include <cstdint>

#include "scenes/scenes.h"

namespace hail::bench {
namespace {

/// SplitMix64 (Steele, Lea and Flood 2014): a few lines any engine's harness can copy, unlike
/// std::uniform_real_distribution, whose output differs between standard libraries.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1): the top 24 bits, exact in float.
  float uniform() { return static_cast<float>(next() >> 40) * 0x1p-24f; }
};

}  // namespace

Scene build_bullets(const SceneParams& p) {
  Scene scene = scene_on_terrain(p, Heightmap::from_function(256, 256, {}, terrain_rain_height),
                                 "bullets: terrain-rain's terrain, spheres r 0.25 fired downwards at 100..1000 m/s");
  scene.default_steps = 120;
  // Per sphere, six draws in this order: x, y, z, azimuth, dip below the horizon, speed.
  SplitMix64 rng{2026};
  constexpr float kPi = 3.14159265358979f;
  scene.world->reserve(p.spheres);
  for (std::size_t k = 0; k < p.spheres; ++k) {
    const float x = 28.0f + 200.0f * rng.uniform();
    const float y = 15.0f + 30.0f * rng.uniform();
    const float z = 28.0f + 200.0f * rng.uniform();
    const float azimuth = 2.0f * kPi * rng.uniform();
    const float dip = (10.0f + 80.0f * rng.uniform()) * kPi / 180.0f;
    const float speed = 100.0f + 900.0f * rng.uniform();
    const Vec3 velocity(speed * std::cos(dip) * std::cos(azimuth), -speed * std::sin(dip),
                        speed * std::cos(dip) * std::sin(azimuth));
    scene.ids.push_back(scene.world->add_sphere({.position = {x, y, z},
                                                 .velocity = velocity,
                                                 .radius = 0.25f,
                                                 .mass = 1.0f,
                                                 .restitution = 0.5f,
                                                 .friction = 0.5f}));
  }
  return scene;
}

}  // namespace hail::bench
