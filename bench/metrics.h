#pragma once
// Error figures every benchmark run reports next to its time. Computed independently of the
// kernel's own contact lists (a grid hash here), so a kernel bug cannot hide its own overlap.

#include <cstddef>
#include <span>

#include "scenes.h"

namespace hail::bench {

struct ErrorFigures {
  double max_sphere_penetration = 0;   ///< m, deepest overlap of two spheres
  double max_terrain_penetration = 0;  ///< m, deepest sphere-triangle (or plane) overlap
  std::size_t tunnelled = 0;           ///< centres below the ground at their (x, z)
  std::size_t fell_off = 0;            ///< centres outside the ground's x/z extent
  std::size_t tunnelled_ever = 0;      ///< spheres below the ground after any step (Scene::track_tunnelling)
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
  std::size_t nan_count = 0;
  double kinetic_energy = 0;           ///< J
};

ErrorFigures measure_errors(const Scene& scene);

/// Deepest overlap (m, >= 0) of any two spheres given by centre coordinates and radii (equal
/// lengths), by a grid hash; spheres with a non-finite centre are skipped.
double max_pair_overlap(std::span<const float> px, std::span<const float> py, std::span<const float> pz,
                        std::span<const float> radius);

/// max_pair_overlap of the spheres of `spheres` (its first size() slots: never the SIMD
/// padding lanes, whose parked centres a sphere of radius 1e18 would reach).
double max_sphere_overlap(const SphereSoA& spheres);

}  // namespace hail::bench
