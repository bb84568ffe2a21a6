#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hail/triangle_mesh.h"
#include "scenes/scenes.h"

namespace hail::bench {

float terrain_rain_height(float x, float z) {
  return 8.0f * std::sin(0.05f * x) * std::cos(0.07f * z) + 3.0f * std::sin(0.21f * x + 0.13f * z);
}

namespace {

Scene with_terrain(const SceneParams& p, Heightmap heightmap, float first_layer_y, std::size_t max_side, float spacing,
                   float centre_x, float centre_z, const char* description) {
  Scene scene = scene_on_terrain(p, std::move(heightmap), description);
  // Layer side s = min(max_side, ceil(sqrt(N))); s/2 is a real division.
  const std::size_t s =
      std::min<std::size_t>(max_side, static_cast<std::size_t>(std::ceil(std::sqrt(double(p.spheres)))));
  const float half = static_cast<float>(s) / 2.0f;
  scene.world->reserve(p.spheres);
  scene.ids.reserve(p.spheres);
  for (std::size_t k = 0; k < p.spheres; ++k) {
    const float x = centre_x + (static_cast<float>(k % s) - half) * spacing;
    const float z = centre_z + (static_cast<float>((k / s) % s) - half) * spacing;
    const float y = first_layer_y + static_cast<float>(k / (s * s)) * spacing;
    scene.ids.push_back(scene.world->add_sphere(
        {.position = {x, y, z}, .radius = 0.5f, .mass = 1.0f, .restitution = 0.5f, .friction = 0.5f}));
  }
  return scene;
}

}  // namespace

Scene scene_on_terrain(const SceneParams& p, Heightmap heightmap, const std::string& description) {
  Scene scene;
  scene.world = std::make_unique<World>(world_settings(p));
  scene.has_terrain = true;
  scene.min_x = heightmap.x_of(0);
  scene.max_x = heightmap.max_x();
  scene.min_z = heightmap.z_of(0);
  scene.max_z = heightmap.max_z();
  auto terrain = std::make_shared<const Terrain>(std::move(heightmap));
  scene.ground_height = [terrain](float x, float z) { return terrain->heightmap().surface_height(x, z); };
  if (p.terrain_as_mesh) {
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> indices;
    vertices.reserve(3 * terrain->triangle_count());
    for (std::uint32_t k = 0; k < terrain->triangle_count(); ++k) {
      const TerrainTriangle t = terrain->triangle(k);
      for (const Vec3& v : {t.a, t.b, t.c}) {
        indices.push_back(static_cast<std::uint32_t>(vertices.size()));
        vertices.push_back(v);  // corners apart: the mesh welds them back into a surface
      }
    }
    scene.world->add_mesh(TriangleMesh(std::move(vertices), std::move(indices)), {}, 0.5f, 0.5f);
  } else {
    scene.world->set_terrain(terrain, 0.5f, 0.5f);
  }
  scene.description = description + (p.terrain_as_mesh ? " (terrain as a mesh)" : "");
  scene.dt = p.dt;
  return scene;
}

Scene build_terrain_rain(const SceneParams& p) {
  Heightmap heightmap = Heightmap::from_function(256, 256, {}, terrain_rain_height);
  return with_terrain(p, std::move(heightmap), 13.0f, 160, 1.5f, 127.5f, 127.5f,
                      "terrain-rain: 256^2 heightmap, 1 m cells, spheres r 0.5 in 1.5 m layers from y = 13");
}

Scene build_bowl_pile(const SceneParams& p) {
  Heightmap heightmap = Heightmap::from_function(256, 256, {}, [](float x, float z) {
    return 0.002f * ((x - 127.5f) * (x - 127.5f) + (z - 127.5f) * (z - 127.5f));
  });
  const float lowest = heightmap.min_height();
  Scene scene = with_terrain(p, std::move(heightmap), lowest + 2.0f, 40, 1.05f, 127.5f, 127.5f,
                             "bowl-pile: paraboloid bowl, column of spheres, spacing 1.05 m");
  scene.default_steps = 1200;
  return scene;
}

Scene build_terrain_rain_dem(const SceneParams& p) {
  // The Jacksboro SRTM DEM at 1 m cells, heights divided by 80 (data/README.md).
  HeightmapParams params;
  params.height_scale = kJacksboroScaleM / 80.0f;
  params.height_offset = kJacksboroOffsetM / 80.0f;
  Heightmap heightmap = Heightmap::load_pgm(std::string(HAIL_SOURCE_DIR) + "/data/" + kJacksboroFile, params);
  const float top = heightmap.max_height();
  return with_terrain(p, std::move(heightmap), top + 2.0f, 160, 1.5f, 201.0f, 171.5f,
                      "terrain-rain-dem: Jacksboro SRTM DEM, 1 m cells, heights / 80");
}

}  // namespace hail::bench
