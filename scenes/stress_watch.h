#pragma once
// Invariants a stress case checks after every step, and the worst value each reached:
// non-finite state, centres below the terrain surface, penetration (sphere-sphere relative to
// the smaller radius, sphere-ground relative to the radius), growth of the mechanical energy
// (kinetic + potential in the world's gravity), and drift of the linear momentum.

#include <string>
#include <vector>

#include "hail/world.h"

namespace hail::bench {

struct StressWorst {
  std::size_t non_finite = 0;     ///< worst count of non-finite components after a step
  std::size_t below_surface = 0;  ///< worst count of centres below the terrain surface
  double sphere_penetration = 0;  ///< worst overlap / smaller radius
  double ground_penetration = 0;  ///< worst terrain, mesh or plane overlap / radius
  double energy_growth = 0;       ///< worst (E - E0) / max(|E0|, energy_scale), E = KE + PE
  double momentum_drift = 0;      ///< worst |p - p0| / max(|p0|, momentum_scale)
  int steps = 0;
};

class StressWatch {
 public:
  /// Records the starting energy and momentum. `energy_scale` and `momentum_scale` keep the
  /// relative figures meaningful when the start values are near zero.
  StressWatch(const World& world, double energy_scale = 1.0, double momentum_scale = 1.0);
  /// Checks the world after a step; the pair test is skipped unless check_pairs (O(n^2) for
  /// up to 2,000 spheres, then a grid).
  void after_step(const World& world, bool check_pairs = true);
  [[nodiscard]] const StressWorst& worst() const { return worst_; }
  /// Mechanical energy: kinetic plus potential in the world's gravity (J).
  [[nodiscard]] static double mechanical_energy(const World& world);

 private:
  double e0_, p0_[3], energy_scale_, momentum_scale_;
  StressWorst worst_;
};

}  // namespace hail::bench
