// hail-feature-cost SCENE [--spheres N] [--steps S] [--threads T] [--rotation on|off]
//
// Steps implosion or terrain-rain in whatever this build of hail has compiled in
// (hail/features.h) and prints one line: the build's features, the median ms per step over
// the scene's timed steps, the state hash, and the optional parts of the step that ran.
// scripts/feature_cost.sh runs it from builds with and without features, alternating, and
// compares the medians: a feature a scene does not use should cost it nothing.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/scenes/scenes.h"
#include "hail/features.h"

namespace {

using namespace hail;
using namespace hail::bench;

int usage(const char* why) {
  std::fprintf(
      stderr,
      "hail-feature-cost: %s\nusage: hail-feature-cost implosion|terrain-rain [--spheres N] [--steps S] [--threads T] "
      "[--rotation on|off]\n",
      why);
  return 2;
}

std::string parts_that_ran(const std::vector<StepParts>& steps) {
  struct Part {
    const char* name;
    bool StepParts::*flag;
  };
  const Part parts[] = {{"reorder", &StepParts::reorder},
                        {"detect-static", &StepParts::detect_static},
                        {"detect-pairs", &StepParts::detect_pairs},
                        {"solve", &StepParts::solve},
                        {"friction", &StepParts::friction},
                        {"rotation", &StepParts::rotation},
                        {"shock", &StepParts::shock},
                        {"sweep", &StepParts::sweep},
                        {"depenetrate", &StepParts::depenetrate},
                        {"terrain-guard", &StepParts::terrain_guard}};
  std::string out;
  for (const Part& p : parts) {
    const auto count = std::count_if(steps.begin(), steps.end(), [&](const StepParts& s) { return s.*(p.flag); });
    if (count == 0) continue;
    if (!out.empty()) out.append(",");
    out.append(p.name);
  }
  return out.empty() ? "none" : out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage("which scene?");
  const std::string scene_name = argv[1];
  SceneParams params;
  int steps = 600;
  for (int k = 2; k + 1 < argc; k += 2) {
    const std::string flag = argv[k];
    if (flag == "--rotation") {  // default: on where compiled in (WorldSettings::rotation)
      const std::string v = argv[k + 1];
      if (v != "on" && v != "off") return usage("--rotation must be on or off");
      params.rotation = v == "on";
      continue;
    }
    const long value = std::strtol(argv[k + 1], nullptr, 10);
    if (value <= 0) return usage(("bad value for " + flag).c_str());
    if (flag == "--spheres")
      params.spheres = static_cast<std::size_t>(value);
    else if (flag == "--steps")
      steps = static_cast<int>(value);
    else if (flag == "--threads")
      params.threads = static_cast<int>(value);
    else
      return usage(("unknown option " + flag).c_str());
  }
  Scene scene;
  try {  // (a setting this build lacks, e.g. --rotation on without HAIL_WITH_ROTATION, is refused)
    if (scene_name == "implosion") {
      scene = build_implosion(params);
#if HAIL_WITH_TERRAIN
    } else if (scene_name == "terrain-rain") {
      scene = build_terrain_rain(params);
#endif
    } else {
      return usage(("scene '" + scene_name + "' is not in this build").c_str());
    }
  } catch (const InvalidArgument& e) {
    return usage(e.what());
  }
  World& world = *scene.world;
  const int warmup = steps > 120 ? 60 : 0;  // the scenes' definition, as hail-bench run
  std::vector<double> ms;
  std::vector<StepParts> ran;
  for (int k = 0; k < steps; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step(scene.dt);
    const double elapsed = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (k >= warmup) ms.push_back(elapsed);
    ran.push_back(world.last_step_stats().ran);
  }
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  std::printf(
      "features terrain=%d ccd=%d reference-walks=%d rotation=%d  %s %zu spheres%s  median %.4f ms/step  hash %016llx  "
      "ran %s\n",
      HAIL_WITH_TERRAIN, HAIL_WITH_CONTINUOUS_COLLISION, HAIL_WITH_REFERENCE_WALKS, HAIL_WITH_ROTATION,
      scene_name.c_str(), world.sphere_count(), world.settings().rotation ? "" : " (rotation off)", ms[ms.size() / 2],
      static_cast<unsigned long long>(world.state_hash()), parts_that_ran(ran).c_str());
  return 0;
}
