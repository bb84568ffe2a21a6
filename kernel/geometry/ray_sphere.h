#pragma once
// Ray against a solid ball, for the world queries (kernel/world/world_queries.cpp). One float
// formula used by the BVH walk and by the tests' brute force alike, so both give the same bits.

#include <cmath>

#include "kernel/geometry/ray_triangle.h"  // kRayMiss

namespace hail {

/// Distance s >= 0 at which the ray o + s d (d unit) enters the ball (centre c, radius r), 0 when
/// o is inside or on it (a solid ball), or kRayMiss. Moving away from or past the ball misses.
[[nodiscard]] inline float ray_sphere(const float o[3], const float d[3], float cx, float cy, float cz, float r) {
  const float ox = o[0] - cx, oy = o[1] - cy, oz = o[2] - cz;
  const float c = ox * ox + oy * oy + oz * oz - r * r;
  if (c <= 0.0f) return 0.0f;
  const float b = ox * d[0] + oy * d[1] + oz * d[2];
  if (!(b < 0.0f)) return kRayMiss;
  const float disc = b * b - c;
  if (!(disc >= 0.0f)) return kRayMiss;
  const float s = -b - std::sqrt(disc);
  return s >= 0.0f ? s : 0.0f;
}

}  // namespace hail
