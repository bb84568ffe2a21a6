#pragma once
// hail-view's command line: what to show (a built-in scene, a scene file or a recording) and
// how (a window, or --headless pictures).

#include <optional>
#include <string>

#include "scenes/scenes.h"
#include "view/draw_choices.h"

namespace hail::view {

struct ViewOptions {
  std::string scene = "terrain-rain";        ///< a built-in scene (scenes/)
  std::string scene_file;                    ///< --scene FILE.json instead; with --replay, the terrain drawn under it
  std::string replay_path;                   ///< --replay FILE: play a recording (hail-bench run --record)
  bench::SceneParams params;                 ///< --spheres, --threads
  std::optional<bool> continuous_collision;  ///< --ccd on|off (nullopt: the scene's own)
  std::optional<bool> sleep;                 ///< --sleep on|off (nullopt: the scene's own)
  bool headless = false;                     ///< --headless: no window shown; render --steps N, write --screenshot
  int steps = 0;                             ///< --steps N before the picture (headless), or the frame shown (replay)
  std::string screenshot_path;               ///< --screenshot FILE.png
  std::string frames_dir;          ///< --frames DIR: headless, a picture every --every K steps (or recorded frames)
  int every = 10;                  ///< --every K
  int width = 1280, height = 720;  ///< window or picture size, pixels
  ColourMode colour = ColourMode::Speed;  ///< --colour speed|island|sleep
  DebugDraw draw;                         ///< --draw-normals, --draw-bvh DEPTH, --draw-grid
  float zoom = 1.0f;                      ///< --zoom Z: the first framing seen from 1/Z the distance
};

/// Parses argv; std::nullopt after --help (printed). Throws std::invalid_argument (CLI11's
/// message) on a bad flag.
std::optional<ViewOptions> parse_view_options(int argc, char** argv);

/// The path of --frames DIR's picture number `k`: DIR/frame-000000.png, ...
[[nodiscard]] std::string frame_picture_path(const std::string& dir, int k);

/// Refuses, with std::invalid_argument (bench::check_output_paths's message), a picture path
/// that cannot be written or that is the same file as an input (--scene, --replay): run first,
/// before anything is built, so a long run never ends unable to save its picture and never
/// writes it over the recording or scene it shows. Creates --frames DIR. A scene file's
/// heightmap is not checked: the scene reader's API does not say which file it names.
void check_view_paths(const ViewOptions& options);

}  // namespace hail::view
