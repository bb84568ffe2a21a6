#pragma once
// Deepest overlap of any two spheres of a world (ra + rb - distance, m; 0 when none overlap),
// by brute force: for the tests' small worlds.

#include <algorithm>
#include <cmath>

#include "hail/world.h"

namespace hail::testing {

inline double max_pair_overlap(const World& w) {
  const SphereState s = w.spheres();
  double worst = 0.0;
  for (std::size_t i = 0; i < w.sphere_count(); ++i)
    for (std::size_t j = i + 1; j < w.sphere_count(); ++j) {
      const double dx = s.px[j] - s.px[i], dy = s.py[j] - s.py[i], dz = s.pz[j] - s.pz[i];
      worst = std::max(worst, s.radius[i] + s.radius[j] - std::sqrt(dx * dx + dy * dy + dz * dz));
    }
  return worst;
}

}  // namespace hail::testing
