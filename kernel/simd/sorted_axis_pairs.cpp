// SortedAxisPairs::find_pairs (kernel/broadphase/sorted_axis_pairs.h): per sphere and radius class, the window of
// sorted spheres within reach along the sweep axis, tested a batch at a time with the
// brute-force predicate in its float operations. Compiled once per SIMD path (kernel/dispatch/simd_arch.h).

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "kernel/broadphase/sorted_axis_pairs.h"
#include "kernel/broadphase/sphere_pair_bounds.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/simd/kernels.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

// The binary searches of std::lower_bound / std::upper_bound, here so that no std template is
// instantiated with this path's flags (kernel/dispatch/kernel_table.h). Same results: the first element
// not below `value`, the first above it.
const float* first_not_below(const float* begin, const float* end, float value) {
  std::size_t count = static_cast<std::size_t>(end - begin);
  while (count > 0) {
    const std::size_t half = count / 2;
    if (begin[half] < value) {
      begin += half + 1;
      count -= half + 1;
    } else {
      count = half;
    }
  }
  return begin;
}

const float* first_above(const float* begin, const float* end, float value) {
  std::size_t count = static_cast<std::size_t>(end - begin);
  while (count > 0) {
    const std::size_t half = count / 2;
    if (!(value < begin[half])) {
      begin += half + 1;
      count -= half + 1;
    } else {
      count = half;
    }
  }
  return begin;
}

}  // namespace

void sorted_axis_find_pairs(const SortedAxisPairsView& v, const SphereSoA& s, std::size_t first, std::size_t last,
                            float margin, std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) {
  using batch = xsimd::batch<float, simd_arch>;
  constexpr std::size_t W = batch::size;
  static_assert(kSimdPadding >= W, "the sweep's padding must cover the widest batch");
  const float* sweep = v.axis == 0 ? v.x : v.axis == 1 ? v.y : v.z;
  const float* centre_axis = v.axis == 0 ? s.px.data() : v.axis == 1 ? s.py.data() : s.pz.data();
  const float* px = s.px.data();
  const float* py = s.py.data();
  const float* pz = s.pz.data();
  const float* radius = s.radius.data();
  // A row's partners collect here and go to `row` a buffer at a time (kernel/dispatch/kernel_table.h).
  constexpr std::size_t kBuffer = 128;
  std::uint32_t found[kBuffer];
  for (std::size_t i = first; i < last; ++i) {
    const float xi = px[i], yi = py[i], zi = pz[i], ri_margin = radius[i] + margin;  // brute force's order
    if (!can_pair(xi, yi, zi, ri_margin)) continue;
    std::size_t count = 0;
    const batch bx(xi), by(yi), bz(zi), b_ri_margin(ri_margin);
    const float ci = centre_axis[i];
    for (std::size_t c = 0; c < v.classes; ++c) {
      // Every partner in this class has its centre within `reach` of ci (sphere_pair_bounds.h).
      const float reach = axis_reach_bound(ri_margin, v.class_max_radius[c]);
      const float* run_begin = sweep + v.class_begin[c];
      const float* run_end = sweep + v.class_begin[c + 1];
      const float* lo = first_not_below(run_begin, run_end, ci - reach);
      const float* hi = first_above(lo, run_end, ci + reach);
      const std::size_t begin = static_cast<std::size_t>(lo - sweep), end = static_cast<std::size_t>(hi - sweep);
      for (std::size_t k0 = begin; k0 < end; k0 += W) {
        const batch dx = batch::load_unaligned(v.x + k0) - bx;
        const batch dy = batch::load_unaligned(v.y + k0) - by;
        const batch dz = batch::load_unaligned(v.z + k0) - bz;
        const batch reach_j = batch::load_unaligned(v.radius + k0) + b_ri_margin;
        const batch d2 = dx * dx + dy * dy + dz * dz;
        for (std::uint32_t lanes = lane_bits(d2 < reach_j * reach_j); lanes != 0; lanes &= lanes - 1) {
          const std::size_t k = k0 + lowest_lane(lanes);
          if (k >= end || v.index[k] <= i) continue;
          if (count == kBuffer) append_slots(row, found, count), count = 0;
          found[count++] = v.index[k];
        }
      }
    }
    if (count == 0) continue;  // nothing found (after a flush, count is back above 0 at once)
    append_slots(row, found, count);
    // Classes and centres scramble the indices: sorted, the row is brute force's.
    append_sorted_row(static_cast<std::uint32_t>(i), row, out);
  }
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
