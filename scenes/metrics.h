#pragma once
// Error figures every benchmark run reports next to its time. Computed independently of the
// kernel's own contact lists (a grid hash here), so a kernel bug cannot hide its own overlap.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "scenes/scenes.h"

namespace hail::bench {

struct ErrorFigures {
  double max_sphere_penetration = 0;   ///< m, deepest overlap of two spheres
  double max_terrain_penetration = 0;  ///< m, deepest sphere-triangle (terrain or mesh) or plane overlap
  std::size_t tunnelled = 0;           ///< centres below the ground at their (x, z)
  std::size_t fell_off = 0;            ///< centres outside the ground's x/z extent
  /// m, the deepest overlap any timed step's contacts started from (-gap at detection, so the
  /// state the previous step left), between spheres and against static geometry: the worst over
  /// the run, where the two above are the end state alone.
  double worst_sphere_penetration = 0;
  double worst_static_penetration = 0;
  /// m, each timed step's deepest such overlap, averaged over the timed steps: how deep
  /// spheres typically go, where the worst is one moment of a chaotic run (so a comparison of
  /// two solver variants is less at the mercy of a single impact).
  double mean_step_sphere_penetration = 0;
  double mean_step_static_penetration = 0;
  std::size_t nan_count = 0;  ///< non-finite state components and derived figures (energy, penetrations, drifts)
  double kinetic_energy = 0;  ///< J
};

ErrorFigures measure_errors(const Scene& scene);

/// Tunnelling over a whole run, checked after every step (TunnellingCounter).
struct TunnellingFigures {
  std::size_t events = 0;   ///< sphere-steps that ended with the centre inside the static geometry
  std::size_t spheres = 0;  ///< distinct spheres among them
  double worst_depth = 0;   ///< m, the deepest such centre (centre_depth)
  int steps = 0;            ///< steps checked
};

/// How deep the centre (x, y, z) lies inside the world's static geometry: the larger of the
/// terrain's surface height minus y (only inside the terrain's extent, where
/// Heightmap::surface_height is not NaN) and, for each plane, offset - n.x (the distance behind
/// it). > 0 means the centre has gone through: a sphere that merely overlaps the ground keeps
/// its centre outside and is penetration, not tunnelling, and the solver pushes a sphere whose
/// centre has crossed out on the far side. <= 0 (or NaN, for a NaN centre) otherwise.
[[nodiscard]] double centre_depth(const World& world, float x, float y, float z);

/// Counts tunnelling after every step of a run, for any scene with a terrain or planes: one
/// pass over the spheres, no allocation except when a sphere tunnels for the first time. The
/// end state alone (ErrorFigures::tunnelled) misses a sphere that went through and came back,
/// or fell on out of the terrain's extent.
class TunnellingCounter {
 public:
  /// Checks every sphere of `world` as it stands now (call after each step).
  void after_step(const World& world);
  [[nodiscard]] const TunnellingFigures& figures() const { return figures_; }

 private:
  TunnellingFigures figures_;
  std::vector<std::uint8_t> seen_;  ///< by SphereId index: has this sphere tunnelled yet
};

/// Deepest overlap (m, >= 0) of any two spheres given by centre coordinates and radii (equal
/// lengths), by a grid hash; spheres with a non-finite centre are skipped.
double max_pair_overlap(std::span<const float> px, std::span<const float> py, std::span<const float> pz,
                        std::span<const float> radius);

/// max_pair_overlap of the spheres of `spheres` (its first size() slots: never the SIMD
/// padding lanes, whose parked centres a sphere of radius 1e18 would reach).
double max_sphere_overlap(const SphereSoA& spheres);

}  // namespace hail::bench
