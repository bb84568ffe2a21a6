#include "kernel/broadphase/sphere_pairs.h"

#include <cmath>

#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/coincident_normal.h"

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
  if (first >= last) return;
  simd_kernels().find_sphere_pairs(s, first, last, margin, out);
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
  if (!centres_coincide(distance, s.radius[a], s.radius[b])) {
    const float inv = 1.0f / distance;
    c.nx = dx * inv;
    c.ny = dy * inv;
    c.nz = dz * inv;
  } else {
    // No direction from the centres: the pair's own, from the spheres' stable ids (slots move).
    float n[3];
    coincident_normal(s.id_at(a).index, s.id_at(b).index, n);
    c.nx = n[0], c.ny = n[1], c.nz = n[2];
  }
  c.restitution = combine_restitution(s.restitution[a], s.restitution[b]);
  c.friction = combine_friction(s.friction[a], s.friction[b]);
  return c;
}

}  // namespace hail
