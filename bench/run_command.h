#pragma once
// `hail-bench run <scene>`: builds a scene, steps it, prints time next to its error figures.

#include <string>
#include <vector>

#include "bench/scenes/scene_run.h"

namespace hail::bench {

/// What `hail-bench run --quiet` prints, one line: "NAME: N spheres, S steps, T ms/step, worst
/// penetration P m, tunnelled K (E sphere-steps), NaN 0, hash H" (the worst penetration of any
/// timed step, spheres or ground; "tunnelled -" for a world with no terrain or planes).
std::string summary_line(const RunResult& r);

int run_command(const std::vector<std::string>& args);

}  // namespace hail::bench
