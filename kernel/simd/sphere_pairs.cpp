// The brute-force pair search of kernel/broadphase/sphere_pairs.h, one sphere i against a batch of j per
// instruction. Compiled once per SIMD path (kernel/dispatch/simd_arch.h); the scalar reference is
// find_sphere_pairs_scalar in kernel/broadphase/sphere_pairs.cpp, which evaluates the same float operations.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/simd/kernels.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

void find_sphere_pairs(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                       std::vector<SpherePair>& out) {
  using batch = xsimd::batch<float, simd_arch>;
  constexpr std::size_t W = batch::size;
  static_assert(kSimdPadding % W == 0, "SoA padding must cover the widest batch");
  const std::size_t n = s.size();
  const std::size_t padded = s.padded_size();
  const float* px = s.px.data();
  const float* py = s.py.data();
  const float* pz = s.pz.data();
  const float* radius = s.radius.data();
  // Pairs collect here and go to `out` a buffer at a time (append_pairs: the vector grows in
  // base code, see kernel/dispatch/kernel_table.h).
  constexpr std::size_t kBuffer = 256;
  SpherePair found[kBuffer];
  std::size_t count = 0;
  for (std::size_t i = first; i < last; ++i) {
    const batch xi(px[i]), yi(py[i]), zi(pz[i]), ri_margin(radius[i] + margin);
    // Start at the batch holding i + 1; lanes j <= i are dropped below. Padding lanes are inert
    // (zero radius, parked at 1e18), so the loop runs to padded_size with no scalar tail.
    for (std::size_t j0 = (i + 1) / W * W; j0 < padded; j0 += W) {
      const batch dx = batch::load_aligned(px + j0) - xi;
      const batch dy = batch::load_aligned(py + j0) - yi;
      const batch dz = batch::load_aligned(pz + j0) - zi;
      const batch reach = batch::load_aligned(radius + j0) + ri_margin;
      const batch d2 = dx * dx + dy * dy + dz * dz;
      for (std::uint32_t lanes = lane_bits(d2 < reach * reach); lanes != 0; lanes &= lanes - 1) {
        const std::size_t j = j0 + lowest_lane(lanes);
        if (j <= i || j >= n) continue;
        if (count == kBuffer) append_pairs(out, found, count), count = 0;
        found[count++] = {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)};
      }
    }
  }
  if (count > 0) append_pairs(out, found, count);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
