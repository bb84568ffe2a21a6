#pragma once
// Smallest and largest radius and inverse mass of a range of spheres (inverse masses of movable
// spheres only): found per block in the step's parallel predict phase, then combined. Minima
// and maxima do not depend on the order they are combined in, so neither does the step.

#include <limits>

namespace hail {

struct SphereExtremes {
  float min_radius = std::numeric_limits<float>::infinity(), max_radius = 0.0f;
  float min_inv_mass = std::numeric_limits<float>::infinity(), max_inv_mass = 0.0f;

  void combine(const SphereExtremes& o) {
    min_radius = o.min_radius < min_radius ? o.min_radius : min_radius;
    max_radius = o.max_radius > max_radius ? o.max_radius : max_radius;
    min_inv_mass = o.min_inv_mass < min_inv_mass ? o.min_inv_mass : min_inv_mass;
    max_inv_mass = o.max_inv_mass > max_inv_mass ? o.max_inv_mass : max_inv_mass;
  }
};

}  // namespace hail
