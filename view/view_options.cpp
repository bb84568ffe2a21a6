#include "view/view_options.h"

#include <CLI/CLI.hpp>
#include <stdexcept>

namespace hail::view {

std::optional<ViewOptions> parse_view_options(int argc, char** argv) {
  ViewOptions o;
  CLI::App app("hail-view: watch a hail scene live, tune it, replay a recording, or render a picture");
  std::vector<std::string> names;
  for (const bench::SceneEntry& e : bench::scene_registry()) names.emplace_back(e.name);
  app.add_option("scene", o.scene, "a built-in scene (default terrain-rain)")->check(CLI::IsMember(names));
  app.add_option("--scene", o.scene_file,
                 "a scene file (docs/scene_format.md); with --replay, the scene whose terrain is drawn under it")
      ->check(CLI::ExistingFile);
  app.add_option("--replay", o.replay_path, "play a recording (hail-bench run ... --record FILE)")
      ->check(CLI::ExistingFile);
  app.add_option("--spheres", o.params.spheres, "sphere count of a built-in scene")->check(CLI::Range(1, 100'000'000));
  app.add_option("--threads", o.params.threads, "worker threads (0: all)")->check(CLI::Range(0, 4096));
  std::string sleep;
  app.add_option("--sleep", sleep, "sleeping on or off (WorldSettings::sleep, on by default; default: the scene's own)")
      ->check(CLI::IsMember({"on", "off"}));
  std::string ccd;
  app.add_option("--ccd", ccd, "continuous collision on or off (default: the scene's own)")
      ->check(CLI::IsMember({"on", "off"}));
  std::string colour = "speed";
  app.add_option("--colour", colour, "colour spheres by speed, island, or sleep (asleep grey-blue, awake by speed)")
      ->check(CLI::IsMember({"speed", "island", "sleep"}));
  app.add_flag("--draw-normals", o.draw.normals, "draw each contact's normal (yellow)");
  app.add_option("--draw-bvh", o.draw.bvh_depth, "draw the terrain BVH's boxes at this depth (cyan; root 0)")
      ->check(CLI::Range(0, 64));
  app.add_flag("--draw-grid", o.draw.grid, "draw the pair grid's occupied cells (white), when the grid search runs");
  app.add_flag("--headless", o.headless, "render without showing a window (under Xvfb, say) and write --screenshot");
  app.add_option("--steps", o.steps, "headless: steps before the picture; replay: the frame to show first")
      ->check(CLI::Range(0, 100'000'000));
  app.add_option("--screenshot", o.screenshot_path, "headless: the PNG to write")->type_name("FILE.png");
  app.add_option("--frames", o.frames_dir,
                 "headless: an image sequence into DIR, frame-000000.png, ..., at step 0 and every --every K steps "
                 "up to --steps (a replay: every K-th recorded frame)")
      ->type_name("DIR");
  app.add_option("--every", o.every, "with --frames: steps (or recorded frames) between pictures")
      ->check(CLI::Range(1, 100'000'000));
  app.add_option("--zoom", o.zoom, "the camera starts this many times closer than its framing of the spheres")
      ->check(CLI::Range(0.01f, 100.0f));
  app.add_option("--width", o.width, "pixels")->check(CLI::Range(64, 8192));
  app.add_option("--height", o.height, "pixels")->check(CLI::Range(64, 8192));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::printf("%s", app.help().c_str());
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    throw std::invalid_argument(e.what());
  }
  if (!ccd.empty()) o.continuous_collision = ccd == "on";
  if (!sleep.empty()) o.sleep = sleep == "on";
  for (std::size_t k = 0; k < kColourModeNames.size(); ++k)
    if (colour == kColourModeNames[k]) o.colour = ColourMode(k);
  if (o.headless && o.screenshot_path.empty() && o.frames_dir.empty())
    throw std::invalid_argument("--headless needs --screenshot FILE.png or --frames DIR");
  if (!o.headless && (!o.screenshot_path.empty() || !o.frames_dir.empty()))
    throw std::invalid_argument("--screenshot and --frames need --headless");
  if (!o.screenshot_path.empty() && !o.frames_dir.empty())
    throw std::invalid_argument("give --screenshot FILE.png or --frames DIR, not both");
  return o;
}

}  // namespace hail::view
