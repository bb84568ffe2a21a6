#pragma once
// The benchmark scenes of docs/scenes.md, built exactly as defined there so that runs
// compare with other engines' runs of the same scene.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hail/world.h"
#include "scenes/setting_text.h"

namespace hail::bench {

struct SceneParams {
  std::size_t spheres = 4000;
  int threads = 0;
  float dt = 1.0f / 60.0f;
  /// The world's settings but threads (the field above): the command line's flags (--reorder,
  /// --pairs, --warm-start, --resting, --tile, --solver, --integrator, the soft step's, --ccd,
  /// --rotation, --sleep) write them here.
  WorldSettings settings{};
  /// --set NAME=VALUE: any setting of the settings table by its name, applied after the fields
  /// above (scenes/setting_text.h).
  std::vector<std::string> set{};
  /// --terrain-as-mesh: a heightmap scene's triangles given to World::add_mesh instead of
  /// set_terrain (the same triangles, met through the mesh path), to compare the two walks.
  bool terrain_as_mesh = false;
};

/// The WorldSettings the command-line parameters ask for: p.settings with p.threads, then the
/// --set assignments.
inline WorldSettings world_settings(const SceneParams& p) {
  WorldSettings s = p.settings;
  s.threads = p.threads;
  set_settings(s, p.set);
  return s;
}

/// What a scene builds and how its results are judged.
struct Scene {
  std::unique_ptr<World> world;
  int default_steps = 600;
  bool has_terrain = false;
  /// Height of the ground under (x, z), for tunnelling checks; empty when there is none.
  std::function<float(float, float)> ground_height;
  float min_x = 0, max_x = 0, min_z = 0, max_z = 0;  ///< ground extent (fell_off outside)
  std::string description;
  float dt = 1.0f / 60.0f;  ///< s per step (SceneParams::dt, or the scene file's)
  /// Handles of the spheres in the order they were added (the World re-sorts its slots), so
  /// that `--dump-state` writes sphere k on row k.
  std::vector<SphereId> ids;
};

using SceneBuilder = Scene (*)(const SceneParams&);

struct SceneEntry {
  const char* name;
  const char* summary;
  SceneBuilder build;
};

/// Every scene hail-bench knows.
const std::vector<SceneEntry>& scene_registry();

/// terrain-rain's height field, h(x, z) = 8 sin(0.05 x) cos(0.07 z) + 3 sin(0.21 x + 0.13 z).
float terrain_rain_height(float x, float z);

/// A scene on this heightmap (terrain material 0.5 / 0.5) with no spheres yet: the World from
/// world_settings(p), the terrain, its extent and ground height, dt.
Scene scene_on_terrain(const SceneParams& p, Heightmap heightmap, const std::string& description);

/// Moves the whole scene by `by` (World::shift_origin(-by)), with its extent and ground height
/// (`hail-bench run --origin D`: by = (D, 0, D)); scenes/scene_origin.cpp.
void move_scene(Scene& scene, const Vec3& by);

Scene build_implosion(const SceneParams& params);
Scene build_terrain_rain(const SceneParams& params);
Scene build_terrain_rain_dem(const SceneParams& params);

/// The Jacksboro DEM's file and sample scale (data/jacksboro_srtm3_403x344.txt: height_m =
/// offset_m + sample * scale_m), for the scenes and stress cases that load it.
inline constexpr const char* kJacksboroFile = "jacksboro_srtm3_403x344.pgm";
inline constexpr float kJacksboroScaleM = 0.0128175783932f, kJacksboroOffsetM = 236.0f;
Scene build_bowl_pile(const SceneParams& params);
Scene build_bullets(const SceneParams& params);

}  // namespace hail::bench
