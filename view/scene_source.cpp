#include "view/scene_source.h"

#include <algorithm>

#include "bench/scenes/scene_file.h"
#include "bench/scenes/scene_run.h"
#include "hail/snapshot.h"

namespace hail::view {

SceneFactory scene_factory(const ViewOptions& options) {
  if (!options.scene_file.empty())
    return
        [path = options.scene_file, sleep = options.sleep, ccd = options.continuous_collision](const SceneChoice& c) {
          bench::SceneOverrides overrides;
          overrides.threads = c.threads;
          overrides.spheres = c.spheres;
          overrides.pair_search = c.pair_search;
          // The panel's choice, else --sleep on|off; without either the file's own setting stands.
          overrides.sleep = c.sleep ? c.sleep : sleep;
          overrides.continuous_collision = ccd;
          return bench::load_scene_file(path, overrides);
        };
  bench::SceneParams built_in = options.params;
  built_in.continuous_collision = options.continuous_collision.value_or(built_in.continuous_collision);
  built_in.sleep = options.sleep.value_or(built_in.sleep);
  return [name = options.scene, params = built_in](const SceneChoice& c) {
    bench::SceneParams p = params;
    p.threads = c.threads;
    p.spheres = c.spheres.value_or(p.spheres);
    p.pair_search = c.pair_search.value_or(p.pair_search);
    p.sleep = c.sleep.value_or(p.sleep);
    return bench::find_scene(name).build(p);
  };
}

bench::Scene scene_of_recording(const RecordingHeader& header, std::string& note) {
  bench::Scene scene;
  try {
    const auto& scenes = bench::scene_registry();
    const bool built_in =
        std::any_of(scenes.begin(), scenes.end(), [&](const auto& e) { return header.scene == e.name; });
    if (built_in) {
      bench::SceneParams params;
      params.spheres = 1;
      params.threads = 1;
      scene = bench::find_scene(header.scene).build(params);
    } else {
      bench::SceneOverrides overrides;
      overrides.spheres = 1;
      overrides.threads = 1;
      scene = bench::load_scene_file(header.scene, overrides);
    }
  } catch (const std::exception& e) {
    note = "the recorded scene '" + header.scene + "' cannot be built here (" + e.what() + "): spheres only";
    scene = bench::Scene{};
    scene.world = std::make_unique<World>(WorldSettings{.threads = 1});
    return scene;
  }
  const Terrain* terrain = scene.world->terrain();
  const bool same = header.has_terrain ? terrain && terrain_content_hash(*terrain) == header.terrain_hash : !terrain;
  if (!same) {
    note = "the terrain of '" + header.scene + "' built here differs from the recorded one (content hash): not drawn";
    scene.world->set_terrain(nullptr);
  }
  return scene;
}

}  // namespace hail::view
