#pragma once
// Which spheres' paths over part of a step may reach a box: the broadphase of continuous
// collision (kernel/ccd/continuous_collision.h). Sphere j moves p_j + v_j t; over [t0, t1] its
// centre stays in the box spanned by its two end points, and its surface within that box grown
// by r_j. visit(j) is called, in slot order, for every j whose grown box overlaps `box`
// (closed boxes). Candidates only: the caller runs the exact time-of-impact test.
//
// One fast sphere scans every slot, so the scan is SIMD (4, 8 or 16 spheres per instruction
// under SSE4.2, AVX2, AVX-512) with the scalar reference beside it; both visit exactly the same
// slots (tests/test_continuous_collision.cpp, tests/test_simd_dispatch.cpp).
//
// The templates are compiled for the including translation unit's SIMD path, in its own
// namespace (kernel/dispatch/simd_arch.h). The step runs the copies of kernel/simd/path_box_scan.cpp,
// chosen at start-up: SimdKernels::scan_path_boxes (kernel/dispatch/kernel_table.h).

#include <algorithm>
#include <cstdint>

#include "hail/sphere_soa.h"
#include "kernel/dispatch/simd_arch.h"

namespace hail {

struct PathBox {
  float min[3], max[3];
};

inline namespace HAIL_SIMD_NS {

template <class Visit>
void scan_path_boxes_scalar(const SphereSoA& s, const PathBox& box, float t0, float t1, Visit&& visit) {
  const float* p[3] = {s.px.data(), s.py.data(), s.pz.data()};
  const float* v[3] = {s.vx.data(), s.vy.data(), s.vz.data()};
  for (std::size_t j = 0; j < s.size(); ++j) {
    bool overlaps = true;
    for (int d = 0; d < 3; ++d) {
      const float a = p[d][j] + v[d][j] * t0, b = p[d][j] + v[d][j] * t1;
      const float lo = std::min(a, b) - s.radius[j], hi = std::max(a, b) + s.radius[j];
      overlaps = overlaps && lo <= box.max[d] && hi >= box.min[d];
    }
    if (overlaps) visit(static_cast<std::uint32_t>(j));
  }
}

template <class Visit>
void scan_path_boxes_simd(const SphereSoA& s, const PathBox& box, float t0, float t1, Visit&& visit) {
  using batch = xsimd::batch<float, simd_arch>;
  constexpr std::size_t W = batch::size;
  static_assert(kSimdPadding % W == 0, "SoA padding must cover the widest batch");
  const float* p[3] = {s.px.data(), s.py.data(), s.pz.data()};
  const float* v[3] = {s.vx.data(), s.vy.data(), s.vz.data()};
  const batch bt0(t0), bt1(t1);
  // Padding lanes are inert (radius 0, parked far away), so no scalar tail is needed; slots at
  // or past size() are still dropped below.
  for (std::size_t j0 = 0; j0 < s.padded_size(); j0 += W) {
    const batch r = batch::load_aligned(&s.radius[j0]);
    auto overlaps = batch(0.0f) == batch(0.0f);
    for (int d = 0; d < 3; ++d) {
      const batch pd = batch::load_aligned(p[d] + j0), vd = batch::load_aligned(v[d] + j0);
      const batch a = pd + vd * bt0, b = pd + vd * bt1;
      const batch lo = xsimd::min(a, b) - r, hi = xsimd::max(a, b) + r;
      overlaps = overlaps && (lo <= batch(box.max[d])) && (hi >= batch(box.min[d]));
    }
    for (std::uint32_t lanes = lane_bits(overlaps); lanes != 0; lanes &= lanes - 1) {
      const std::size_t j = j0 + lowest_lane(lanes);
      if (j < s.size()) visit(static_cast<std::uint32_t>(j));
    }
  }
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
