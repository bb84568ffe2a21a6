#pragma once
// The first half of sphere_triangle_contact (kernel/geometry/sphere_triangle.h) for a batch of
// (sphere, triangle) candidates at once, one per lane: the plane test, the closest point on the
// triangle and its region, and the distance test. closest_point_on_triangle returns at the first
// region that holds; here every region's point is computed and the first that holds is
// selected, with the same float operations in the same order, so each lane has the scalar
// bits. Whatever passes goes to contact_from_closest_point, scalar, for the normal.
//
// Why: the terrain's candidates are about half of its contact search (the other half is the
// walk), and the scalar closest point branches on the region of every candidate.
//
// Inline code for the including translation unit's SIMD path (kernel/dispatch/simd_arch.h); the
// references are closest_point_on_triangle and sphere_triangle_contact, and
// tests/test_simd_dispatch.cpp compares every path with them.

#include <cstdint>

#include "kernel/dispatch/simd_arch.h"
#include "kernel/geometry/sphere_triangle.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

/// closest_point_on_triangle per lane: the point, and the TriangleRegion as a float (0..6).
struct ClosestPointLanes {
  using batch = xsimd::batch<float, simd_arch>;
  batch p[3];
  batch region;
};

namespace triangle_lanes_detail {
using batch = xsimd::batch<float, simd_arch>;
inline batch dot3(const batch u[3], const batch v[3]) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }
inline batch region_value(TriangleRegion region) { return batch(static_cast<float>(region)); }
/// Lanes of `mask` take `point` (from + t dir, as triangle_detail::along) and `region`.
inline void take(const xsimd::batch_bool<float, simd_arch>& mask, const batch from[3], const batch dir[3],
                 const batch& t, TriangleRegion region, ClosestPointLanes& out) {
  for (int d = 0; d < 3; ++d) out.p[d] = xsimd::select(mask, from[d] + t * dir[d], out.p[d]);
  out.region = xsimd::select(mask, region_value(region), out.region);
}
inline void take_vertex(const xsimd::batch_bool<float, simd_arch>& mask, const batch v[3], TriangleRegion region,
                        ClosestPointLanes& out) {
  for (int d = 0; d < 3; ++d) out.p[d] = xsimd::select(mask, v[d], out.p[d]);
  out.region = xsimd::select(mask, region_value(region), out.region);
}
}  // namespace triangle_lanes_detail

/// Closest point of triangle (a, b, c) to q, per lane: closest_point_on_triangle's bits.
[[gnu::always_inline]] inline ClosestPointLanes closest_points_on_triangles(const xsimd::batch<float, simd_arch> q[3],
                                                                            const xsimd::batch<float, simd_arch> a[3],
                                                                            const xsimd::batch<float, simd_arch> b[3],
                                                                            const xsimd::batch<float, simd_arch> c[3]) {
  using namespace triangle_lanes_detail;
  const batch zero(0.0f);
  batch ab[3], ac[3], ap[3], bp[3], cp[3], bc[3];
  for (int d = 0; d < 3; ++d) {
    ab[d] = b[d] - a[d];
    ac[d] = c[d] - a[d];
    ap[d] = q[d] - a[d];
    bp[d] = q[d] - b[d];
    cp[d] = q[d] - c[d];
    bc[d] = c[d] - b[d];
  }
  const batch d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  const batch d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  const batch d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  const batch vc = d1 * d4 - d3 * d2;
  const batch vb = d5 * d2 - d1 * d6;
  const batch va = d3 * d6 - d5 * d4;
  // The face, then each earlier return of the scalar code over it, the first one last.
  ClosestPointLanes out;
  const batch denom = va + vb + vc;
  const batch v = vb / denom, w = vc / denom;
  for (int d = 0; d < 3; ++d) out.p[d] = a[d] + ab[d] * v + ac[d] * w;
  out.region = region_value(TriangleRegion::Face);
  take_vertex(!(denom > zero), a, TriangleRegion::Vertex0, out);  // zero-area triangle
  const batch e1_from_b = d4 - d3, e1_from_c = d5 - d6;
  take((va <= zero) & (e1_from_b >= zero) & (e1_from_c >= zero), b, bc, e1_from_b / (e1_from_b + e1_from_c),
       TriangleRegion::Edge1, out);
  take((vb <= zero) & (d2 >= zero) & (d6 <= zero), a, ac, d2 / (d2 - d6), TriangleRegion::Edge2, out);
  take_vertex((d6 >= zero) & (d5 <= d6), c, TriangleRegion::Vertex2, out);
  take((vc <= zero) & (d1 >= zero) & (d3 <= zero), a, ab, d1 / (d1 - d3), TriangleRegion::Edge0, out);
  take_vertex((d3 >= zero) & (d4 <= d3), b, TriangleRegion::Vertex1, out);
  take_vertex((d1 <= zero) & (d2 <= zero), a, TriangleRegion::Vertex0, out);
  return out;
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
