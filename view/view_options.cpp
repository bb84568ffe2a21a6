#include "view/view_options.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string_view>

#include "scenes/output_file.h"
#include "scenes/scene_inputs.h"

namespace hail::view {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kFramePrefix = "frame-", kFrameSuffix = ".png";

/// Whether `name` is one a --frames picture may take: "frame-", six digits or more, ".png".
bool is_frame_picture_name(std::string_view name) {
  if (name.size() < kFramePrefix.size() + 6 + kFrameSuffix.size()) return false;
  if (!name.starts_with(kFramePrefix) || !name.ends_with(kFrameSuffix)) return false;
  const std::string_view number =
      name.substr(kFramePrefix.size(), name.size() - kFramePrefix.size() - kFrameSuffix.size());
  return std::all_of(number.begin(), number.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

/// The --frames pictures to check: the first, which stands for the folder (writable, not an
/// input), and every input that lies in DIR under a picture's name. How many pictures a run
/// writes is known only as it goes (a recording's frame count), so any such input is one the
/// sequence may reach.
std::vector<std::string> frame_pictures_to_check(const std::string& dir, const std::vector<std::string>& inputs) {
  std::vector<std::string> pictures{frame_picture_path(dir, 0)};
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    const fs::path path(input);
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (is_frame_picture_name(path.filename().string()) && bench::same_file(folder.string(), dir))
      pictures.push_back(input);
  }
  return pictures;
}

}  // namespace

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

std::string frame_picture_path(const std::string& dir, int k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame-%06d.png", k);
  return (fs::path(dir) / name).string();
}

void check_view_paths(const ViewOptions& o) {
  std::vector<std::string> inputs = bench::scene_file_inputs(o.scene_file);  // the file and its heightmap
  inputs.push_back(o.replay_path);
  std::vector<std::string> outputs{o.screenshot_path};
  if (!o.frames_dir.empty()) {
    bench::prepare_output_dir(o.frames_dir);
    const std::vector<std::string> pictures = frame_pictures_to_check(o.frames_dir, inputs);
    outputs.insert(outputs.end(), pictures.begin(), pictures.end());
  }
  bench::check_output_paths(outputs, inputs);
}

}  // namespace hail::view
