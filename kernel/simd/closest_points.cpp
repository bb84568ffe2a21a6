// closest_points_on_triangles (kernel/simd/sphere_triangle_lanes.h) over arrays, for the tests
// that hold every path to closest_point_on_triangle (tests/test_simd_dispatch.cpp). Compiled
// once per SIMD path (kernel/dispatch/simd_arch.h).

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include <algorithm>

#include "kernel/simd/kernels.h"
#include "kernel/simd/sphere_triangle_lanes.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

void closest_points(const TriangleQueries& in, std::size_t count, float* const p[3], std::uint8_t* region) {
  using batch = xsimd::batch<float, simd_arch>;
  constexpr std::size_t W = batch::size;
  for (std::size_t o = 0; o < count; o += W) {
    const std::size_t n = std::min(W, count - o);
    // Through aligned copies, so the last batch reads no further than `count`.
    alignas(64) float lanes[13][W] = {};
    const float* const from[12] = {in.q[0], in.q[1], in.q[2], in.a[0], in.a[1], in.a[2],
                                   in.b[0], in.b[1], in.b[2], in.c[0], in.c[1], in.c[2]};
    for (int k = 0; k < 12; ++k) std::copy(from[k] + o, from[k] + o + n, lanes[k]);
    batch v[12];
    for (int k = 0; k < 12; ++k) v[k] = batch::load_aligned(lanes[k]);
    const ClosestPointLanes out = closest_points_on_triangles(v, v + 3, v + 6, v + 9);
    for (int d = 0; d < 3; ++d) {
      out.p[d].store_aligned(lanes[d]);
      std::copy(lanes[d], lanes[d] + n, p[d] + o);
    }
    out.region.store_aligned(lanes[12]);
    for (std::size_t l = 0; l < n; ++l) region[o + l] = static_cast<std::uint8_t>(lanes[12][l]);
  }
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
