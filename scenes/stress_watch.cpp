#include "scenes/stress_watch.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace hail::bench {
namespace {

/// Worst overlap / smaller radius over all pairs: brute force for small worlds, a hashed grid
/// of the largest diameter beyond (independent of the kernel's own pair searches).
double worst_pair_penetration(const SphereSoA& s) {
  const std::size_t n = s.size();
  double worst = 0.0;
  auto test = [&](std::size_t i, std::size_t j) {
    const double dx = double(s.px[j]) - s.px[i], dy = double(s.py[j]) - s.py[i], dz = double(s.pz[j]) - s.pz[i];
    const double overlap = double(s.radius[i]) + s.radius[j] - std::sqrt(dx * dx + dy * dy + dz * dz);
    if (overlap > 0.0) worst = std::max(worst, overlap / std::min(s.radius[i], s.radius[j]));
  };
  if (n <= 2000) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) test(i, j);
    return worst;
  }
  float largest = 0.0f;
  for (std::size_t i = 0; i < n; ++i) largest = std::max(largest, s.radius[i]);
  const double cell = 2.0 * largest;
  auto key = [](long x, long y, long z) { return (x * 73856093L) ^ (y * 19349663L) ^ (z * 83492791L); };
  std::unordered_multimap<long, std::size_t> grid;
  for (std::size_t i = 0; i < n; ++i)
    grid.emplace(key(std::lround(std::floor(s.px[i] / cell)), std::lround(std::floor(s.py[i] / cell)),
                     std::lround(std::floor(s.pz[i] / cell))),
                 i);
  for (std::size_t i = 0; i < n; ++i) {
    const long cx = std::lround(std::floor(s.px[i] / cell)), cy = std::lround(std::floor(s.py[i] / cell)),
               cz = std::lround(std::floor(s.pz[i] / cell));
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          auto [a, b] = grid.equal_range(key(cx + dx, cy + dy, cz + dz));
          for (auto it = a; it != b; ++it)
            if (it->second > i) test(i, it->second);
        }
  }
  return worst;
}

}  // namespace

double StressWatch::mechanical_energy(const World& w) {
  const SphereSoA& s = w.soa();
  const Vec3 g = w.settings().gravity;
  double potential = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.inv_mass[i] > 0.0f)
      potential -= (double(g.x()) * s.px[i] + double(g.y()) * s.py[i] + double(g.z()) * s.pz[i]) / s.inv_mass[i];
  return w.kinetic_energy() + potential;
}

StressWatch::StressWatch(const World& w, double energy_scale, double momentum_scale)
    : e0_(mechanical_energy(w)), energy_scale_(energy_scale), momentum_scale_(momentum_scale) {
  const Eigen::Vector3d p = w.linear_momentum();
  p0_[0] = p.x(), p0_[1] = p.y(), p0_[2] = p.z();
}

void StressWatch::after_step(const World& w, bool check_pairs) {
  const SphereSoA& s = w.soa();
  ++worst_.steps;
  worst_.non_finite = std::max(worst_.non_finite, w.nan_count());
  std::size_t below = 0;
  double ground = 0.0;
  const Terrain* terrain = w.terrain();
  for (std::size_t i = 0; i < s.size(); ++i) {
    for (const Plane& p : w.planes())
      ground = std::max(ground, -double(plane_gap(p, s.px[i], s.py[i], s.pz[i], s.radius[i])) / s.radius[i]);
    if (w.mesh_count() > 0)
      ground = std::max(ground, double(w.mesh_penetration(Vec3(s.px[i], s.py[i], s.pz[i]), s.radius[i])) / s.radius[i]);
    if (!terrain) continue;
    const Heightmap& h = terrain->heightmap();
    const float x = s.px[i], z = s.pz[i];
    if (!(x >= h.x_of(0) && x <= h.max_x() && z >= h.z_of(0) && z <= h.max_z())) continue;
    if (s.py[i] < h.surface_height(x, z)) ++below;
    ground = std::max(ground, double(terrain->penetration(x, s.py[i], z, s.radius[i])) / s.radius[i]);
  }
  worst_.below_surface = std::max(worst_.below_surface, below);
  worst_.ground_penetration = std::max(worst_.ground_penetration, ground);
  if (check_pairs) worst_.sphere_penetration = std::max(worst_.sphere_penetration, worst_pair_penetration(s));
  const double e = mechanical_energy(w);
  worst_.energy_growth = std::max(worst_.energy_growth, (e - e0_) / std::max(std::fabs(e0_), energy_scale_));
  const Eigen::Vector3d p = w.linear_momentum();
  const double dp = std::sqrt((p.x() - p0_[0]) * (p.x() - p0_[0]) + (p.y() - p0_[1]) * (p.y() - p0_[1]) +
                              (p.z() - p0_[2]) * (p.z() - p0_[2]));
  const double p0 = std::sqrt(p0_[0] * p0_[0] + p0_[1] * p0_[1] + p0_[2] * p0_[2]);
  worst_.momentum_drift = std::max(worst_.momentum_drift, dp / std::max(p0, momentum_scale_));
}

}  // namespace hail::bench
