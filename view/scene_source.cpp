#include "view/scene_source.h"

#include <algorithm>

#include "hail/snapshot.h"
#include "scenes/scene_file.h"
#include "scenes/scene_run.h"
#include "scenes/setting_text.h"

namespace hail::view {

SceneFactory scene_factory(const ViewOptions& options) {
  if (!options.scene_file.empty())
    return
        [path = options.scene_file, sleep = options.sleep, ccd = options.continuous_collision](const SceneChoice& c) {
          bench::SceneOverrides overrides;
          overrides.threads = c.threads;
          overrides.spheres = c.spheres;
          // By the settings' table names (scenes/setting_text.h); what is not given, the file's own
          // setting stands. Sleep: the panel's choice, else --sleep on|off.
          WorldSettings chosen;
          auto choose = [&](const char* name) {
            overrides.set.push_back(std::string(name) + "=" + bench::setting_text(chosen, name));
          };
          if (c.pair_search) chosen.pair_search = *c.pair_search, choose("pair_search");
          if (const std::optional<bool> asleep = c.sleep ? c.sleep : sleep) chosen.sleep = *asleep, choose("sleep");
          if (ccd) chosen.continuous_collision = *ccd, choose("continuous_collision");
          return bench::load_scene_file(path, overrides);
        };
  bench::SceneParams built_in = options.params;
  built_in.settings.continuous_collision =
      options.continuous_collision.value_or(built_in.settings.continuous_collision);
  built_in.settings.sleep = options.sleep.value_or(built_in.settings.sleep);
  return [name = options.scene, params = built_in](const SceneChoice& c) {
    bench::SceneParams p = params;
    p.threads = c.threads;
    p.spheres = c.spheres.value_or(p.spheres);
    p.settings.pair_search = c.pair_search.value_or(p.settings.pair_search);
    p.settings.sleep = c.sleep.value_or(p.settings.sleep);
    return bench::find_scene(name).build(p);
  };
}

namespace {

bool is_built_in_scene(const std::string& name) {
  const auto& scenes = bench::scene_registry();
  return std::any_of(scenes.begin(), scenes.end(), [&](const bench::SceneEntry& e) { return name == e.name; });
}

/// A scene with nothing in it: the spheres of a recording are drawn on their own.
bench::Scene empty_scene() {
  bench::Scene scene;
  scene.world = std::make_unique<World>(WorldSettings{.threads = 1});
  return scene;
}

bench::Scene built_in_with_one_sphere(const std::string& name) {
  bench::SceneParams params;
  params.spheres = 1;
  params.threads = 1;
  return bench::find_scene(name).build(params);
}

/// The scene file's scene with one sphere, or whole where its spheres cannot be resized (the
/// reader resizes only a file's one lattice or random generator; lists stay as they are).
bench::Scene scene_file_with_few_spheres(const std::string& path) {
  try {
    return bench::load_scene_file(path, {.spheres = 1, .threads = 1});
  } catch (const std::invalid_argument&) {
    return bench::load_scene_file(path, {.threads = 1});  // a file that is wrong fails again, and says why
  }
}

/// Whether the scene's terrain is the one recorded (or, as recorded, there is none).
bool terrain_as_recorded(const bench::Scene& scene, const RecordingHeader& header) {
  const Terrain* terrain = scene.world->terrain();
  return header.has_terrain ? terrain && terrain_content_hash(*terrain) == header.terrain_hash : !terrain;
}

}  // namespace

bench::Scene scene_of_recording(const RecordingHeader& header, const std::string& scene_file, std::string& note) {
  bench::Scene scene;
  std::string shown;  // the scene named in the notes
  if (!scene_file.empty()) {
    scene = scene_file_with_few_spheres(scene_file);
    shown = scene_file;
  } else if (!is_built_in_scene(header.scene)) {
    note = "the recorded scene '" + header.scene +
           "' is not a built-in scene: spheres only (--scene FILE.json draws that scene file's terrain under them)";
    return empty_scene();
  } else {
    try {
      scene = built_in_with_one_sphere(header.scene);
    } catch (const std::exception& e) {
      note = "the recorded scene '" + header.scene + "' cannot be built here (" + e.what() + "): spheres only";
      return empty_scene();
    }
    shown = header.scene;
  }
  if (!terrain_as_recorded(scene, header)) {
    note = "the terrain of '" + shown + "' built here differs from the recorded one (content hash): not drawn";
    scene.world->set_terrain(nullptr);
  }
  return scene;
}

}  // namespace hail::view
