#pragma once
// hail-view's command line: what to show (a built-in scene, a scene file or a recording) and
// how (a window, or --headless pictures).

#include <optional>
#include <string>

#include "bench/scenes/scenes.h"
#include "view/draw_choices.h"

namespace hail::view {

struct ViewOptions {
  std::string scene = "terrain-rain";        ///< a built-in scene (bench/scenes)
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

}  // namespace hail::view
