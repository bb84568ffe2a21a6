#include "scenes/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace hail::bench {

double max_pair_overlap(std::span<const float> px, std::span<const float> py, std::span<const float> pz,
                        std::span<const float> radius) {
  const std::size_t n = radius.size();
  float max_radius = 0.0f;
  for (std::size_t i = 0; i < n; ++i) max_radius = std::max(max_radius, radius[i]);
  if (n < 2 || max_radius <= 0.0f) return 0.0;
  const double cell = 2.0 * max_radius;
  auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
           (static_cast<std::uint64_t>(z) * 83492791u);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  grid.reserve(n);
  std::vector<std::int64_t> cx(n), cy(n), cz(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(px[i]) || !std::isfinite(py[i]) || !std::isfinite(pz[i])) continue;
    cx[i] = static_cast<std::int64_t>(std::floor(px[i] / cell));
    cy[i] = static_cast<std::int64_t>(std::floor(py[i] / cell));
    cz[i] = static_cast<std::int64_t>(std::floor(pz[i] / cell));
    grid[key(cx[i], cy[i], cz[i])].push_back(static_cast<std::uint32_t>(i));
  }
  double deepest = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(px[i]) || !std::isfinite(py[i]) || !std::isfinite(pz[i])) continue;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(key(cx[i] + dx, cy[i] + dy, cz[i] + dz));
          if (it == grid.end()) continue;
          for (std::uint32_t j : it->second) {
            if (j <= i) continue;
            const double ddx = double(px[j]) - px[i], ddy = double(py[j]) - py[i], ddz = double(pz[j]) - pz[i];
            const double overlap = double(radius[i]) + radius[j] - std::sqrt(ddx * ddx + ddy * ddy + ddz * ddz);
            deepest = std::max(deepest, overlap);
          }
        }
  }
  return deepest;
}

double max_sphere_overlap(const SphereSoA& s) {
  // The arrays are padded for SIMD (SphereSoA::padded_size): only the first size() are spheres.
  const std::size_t n = s.size();
  return max_pair_overlap(s.px.span().first(n), s.py.span().first(n), s.pz.span().first(n), s.radius.span().first(n));
}

ErrorFigures measure_errors(const Scene& scene) {
  const World& world = *scene.world;
  const SphereSoA& s = world.soa();
  ErrorFigures e;
  e.nan_count = world.nan_count();
  e.kinetic_energy = world.kinetic_energy();
  e.max_sphere_penetration = max_sphere_overlap(s);
  for (std::size_t i = 0; i < s.size(); ++i) {
    for (const Plane& p : world.planes())
      e.max_terrain_penetration =
          std::max(e.max_terrain_penetration, -double(plane_gap(p, s.px[i], s.py[i], s.pz[i], s.radius[i])));
    if (world.mesh_count() > 0)
      e.max_terrain_penetration = std::max<double>(
          e.max_terrain_penetration, world.mesh_penetration(Vec3(s.px[i], s.py[i], s.pz[i]), s.radius[i]));
    if (!scene.ground_height) continue;
    const float x = s.px[i], z = s.pz[i];
    if (!(x >= scene.min_x && x <= scene.max_x && z >= scene.min_z && z <= scene.max_z)) {
      ++e.fell_off;
      continue;
    }
    const double ground = scene.ground_height(x, z);
    if (s.py[i] < ground) ++e.tunnelled;
    if (const Terrain* terrain = world.terrain())
      e.max_terrain_penetration =
          std::max<double>(e.max_terrain_penetration, terrain->penetration(x, s.py[i], z, s.radius[i]));
  }
  // Derived figures count too: a broken mass or inertia makes the energy NaN with every
  // position and velocity finite.
  for (double figure : {e.kinetic_energy, e.max_sphere_penetration, e.max_terrain_penetration})
    e.nan_count += std::isfinite(figure) ? 0 : 1;
  return e;
}

double centre_depth(const World& world, float x, float y, float z) {
  double depth = -std::numeric_limits<double>::infinity();
  if (const Terrain* terrain = world.terrain()) {
    const float surface = terrain->heightmap().surface_height(x, z);  // NaN outside the extent
    if (!std::isnan(surface)) depth = double(surface) - double(y);
  }
  for (const Plane& p : world.planes())
    depth = std::max(depth, double(p.offset) - (double(p.nx) * x + double(p.ny) * y + double(p.nz) * z));
  return depth;
}

void TunnellingCounter::after_step(const World& world) {
  ++figures_.steps;
  if (world.terrain() == nullptr && world.planes().empty()) return;
  const SphereSoA& s = world.soa();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double depth = centre_depth(world, s.px[i], s.py[i], s.pz[i]);
    if (!(depth > 0.0)) continue;
    ++figures_.events;
    figures_.worst_depth = std::max(figures_.worst_depth, depth);
    const std::uint32_t id = s.id_at(i).index;
    if (seen_.size() <= id) seen_.resize(std::size_t{id} + 1, 0);
    if (seen_[id] == 0) ++figures_.spheres;
    seen_[id] = 1;
  }
}

}  // namespace hail::bench
