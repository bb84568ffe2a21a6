#pragma once
// Ray-triangle intersection by Möller and Trumbore ("Fast, minimum storage ray-triangle
// intersection", 1997): solves o + t d = a + u (b - a) + v (c - a) by Cramer's rule with two
// cross products and no precomputed plane. Scalar reference; both faces count as hits.

#include <limits>

namespace hail {

/// Returned by ray_triangle for a miss (also NaN-free, so `t >= 0` tests a hit).
inline constexpr float kRayMiss = -1.0f;

/// Distance t >= 0 along o + t d (in units of |d|; d need not be unit) at which the ray meets
/// triangle (a, b, c), or kRayMiss when it passes outside, runs parallel to the plane (no
/// single hit) or meets it behind the origin. Points on an edge (u, v >= 0, u + v <= 1,
/// inclusive) are hits, so a ray through a shared edge hits both triangles.
[[nodiscard]] inline float ray_triangle(const float o[3], const float d[3], const float a[3], const float b[3],
                                        const float c[3]) {
  const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const float p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
  const float det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
  if (det == 0.0f) return kRayMiss;  // parallel to the plane, or a degenerate triangle
  const float inv_det = 1.0f / det;
  const float s[3] = {o[0] - a[0], o[1] - a[1], o[2] - a[2]};
  const float u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv_det;
  if (!(u >= 0.0f && u <= 1.0f)) return kRayMiss;  // written to reject NaN too
  const float q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
  const float v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv_det;
  if (!(v >= 0.0f && u + v <= 1.0f)) return kRayMiss;
  const float t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv_det;
  return t >= 0.0f && t < std::numeric_limits<float>::infinity() ? t : kRayMiss;
}

}  // namespace hail
