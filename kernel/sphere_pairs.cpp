#include "kernel/sphere_pairs.h"

#include <cmath>
#include <xsimd/xsimd.hpp>

namespace hail {

void find_sphere_pairs_scalar(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                              std::vector<SpherePair>& out) {
  const std::size_t n = s.size();
  for (std::size_t i = first; i < last; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const float reach = s.radius[j] + (s.radius[i] + margin);  // the SIMD kernel's order
      if (spheres_within(s.px[j] - s.px[i], s.py[j] - s.py[i], s.pz[j] - s.pz[i], reach))
        out.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
    }
  }
}

void find_sphere_pairs_simd(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                            std::vector<SpherePair>& out) {
  using batch = xsimd::batch<float>;
  constexpr std::size_t W = batch::size;
  static_assert(kSimdPadding % W == 0, "SoA padding must cover the widest batch");
  const std::size_t n = s.size();
  const std::size_t padded = s.padded_size();
  alignas(64) bool hit_lanes[W];
  for (std::size_t i = first; i < last; ++i) {
    const batch xi(s.px[i]), yi(s.py[i]), zi(s.pz[i]), ri_margin(s.radius[i] + margin);
    // Start at the batch holding i + 1; lanes j <= i are dropped below. Padding lanes are inert
    // (zero radius, parked at 1e18), so the loop runs to padded_size with no scalar tail.
    for (std::size_t j0 = (i + 1) / W * W; j0 < padded; j0 += W) {
      const batch dx = batch::load_aligned(&s.px[j0]) - xi;
      const batch dy = batch::load_aligned(&s.py[j0]) - yi;
      const batch dz = batch::load_aligned(&s.pz[j0]) - zi;
      const batch reach = batch::load_aligned(&s.radius[j0]) + ri_margin;
      const batch d2 = dx * dx + dy * dy + dz * dz;
      const auto hit = d2 < reach * reach;
      if (!xsimd::any(hit)) continue;
      hit.store_aligned(hit_lanes);
      for (std::size_t lane = 0; lane < W; ++lane) {
        const std::size_t j = j0 + lane;
        if (hit_lanes[lane] && j > i && j < n)
          out.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
      }
    }
  }
}

float combine_friction(float a, float b) { return std::sqrt(a * b); }

Contact make_sphere_contact(const SphereSoA& s, SpherePair pair) {
  const std::uint32_t a = pair.a, b = pair.b;
  const float dx = s.px[b] - s.px[a], dy = s.py[b] - s.py[a], dz = s.pz[b] - s.pz[a];
  const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
  Contact c;
  c.a = a;
  c.b = b;
  c.gap = distance - s.radius[a] - s.radius[b];
  // Coincident centres have no direction: a fixed fallback normal, never NaN.
  if (distance > 1e-12f) {
    const float inv = 1.0f / distance;
    c.nx = dx * inv;
    c.ny = dy * inv;
    c.nz = dz * inv;
  }
  c.restitution = combine_restitution(s.restitution[a], s.restitution[b]);
  c.friction = combine_friction(s.friction[a], s.friction[b]);
  return c;
}

}  // namespace hail
