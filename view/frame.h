#pragma once
// What the renderer draws: one whole step's spheres (centres, radii, speeds, sleep states, in
// any order), what the colour modes and debug lines that are on need, and the figures the
// panel plots. The simulation thread fills one and hands it over whole, so a
// frame never mixes two steps.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hail/debug_draw.h"
#include "hail/step_stats.h"

namespace hail::view {

/// Floats per contact in Frame::contacts: point x y z, normal x y z, radius of sphere a.
inline constexpr std::size_t kContactFloats = 7;

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
  /// Per sphere: asleep (WorldSettings::sleep; all 0 with sleeping off).
  std::vector<std::uint8_t> sleeping;
  /// What Capture asked for (each empty otherwise). island: per sphere, the label of its island
  /// (island_labels); contacts: per contact of the step, its point on sphere a and its unit
  /// normal from a towards b, and a's radius (kContactFloats floats); grid_cells: World::pair_grid_cells.
  std::vector<std::uint32_t> island;
  std::vector<float> contacts;
  std::vector<DebugBox> grid_cells;
  [[nodiscard]] std::size_t size() const { return radius.size(); }
};

}  // namespace hail::view
