#pragma once
// What the renderer draws: one whole step's spheres (centres, radii, speeds, in any order) and
// the figures the panel plots. The simulation thread fills one and hands it over whole, so a
// frame never mixes two steps.

#include <cstdint>
#include <vector>

#include "hail/step_stats.h"

namespace hail::view {

struct Frame {
  std::uint64_t step = 0;     ///< steps taken
  std::vector<float> centre;  ///< x, y, z per sphere
  std::vector<float> radius;  ///< m, per sphere
  std::vector<float> speed;   ///< m/s, per sphere (the colour)
  PhaseTimes phase_ms;        ///< of the step that made it
  double step_ms = 0.0;       ///< wall time of that step
  double kinetic_energy = 0.0;
  /// m, the deepest overlap of two spheres or of a sphere and the ground, and the centres below
  /// the ground (bench's measure_errors); live runs of up to kErrorFiguresUpTo spheres only, else 0.
  double deepest_overlap = 0.0;
  std::size_t tunnelled = 0;
  [[nodiscard]] std::size_t size() const { return radius.size(); }
};

}  // namespace hail::view
