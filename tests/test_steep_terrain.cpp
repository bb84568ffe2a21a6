// Contacts on steep and folded terrain (issue 28, part 1): property tests over generated
// heightmaps with cliffs, spikes, zig-zag folds and slopes past 80 degrees. A sphere whose
// centre is above the surface must never get a contact deeper than its true distance to the
// surface, and no step may move a sphere farther than its speed and the overlap it really had
// allow. Before the heightfield rule (kernel/geometry/sphere_triangle.h, contact_from_closest_point)
// a centre behind a steep triangle's plane took that plane's depth, metres too deep.

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/sphere_triangle.h"
#include "kernel/terrain/terrain_parts.h"
#include "scenes/steep_heightmaps.h"
#include "simd_paths.h"

using namespace hail;
using hail::bench::SteepKind;

namespace {

/// A sphere's true distance from its centre to the terrain's surface: the nearest point of any
/// triangle, brute force.
float true_distance(const Terrain& terrain, float x, float y, float z) {
  const TerrainTriangles& t = terrain.triangles();
  const float q[3] = {x, y, z};
  float best = INFINITY;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]},
                c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
    const TrianglePoint p = closest_point_on_triangle(q, a, b, c);
    const float dx = p.p[0] - x, dy = p.p[1] - y, dz = p.p[2] - z;
    best = std::min(best, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return best;
}

/// Random spheres with their centres above the surface, many of them beside cliffs: radii
/// 0.1..1 m, falling at up to 20 m/s (so contacts reach up to a third of a metre ahead).
SphereSoA spheres_above(const Heightmap& h, std::uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const HeightmapExtent e = h.extent();
  SphereSoA s;
  while (static_cast<int>(s.size()) < count) {
    const float x = e.min_x + 1.0f + (e.max_x - e.min_x - 2.0f) * u(rng);
    const float z = e.min_z + 1.0f + (e.max_z - e.min_z - 2.0f) * u(rng);
    const float r = 0.1f + 0.9f * u(rng);
    const float y = h.surface_height(x, z) + 0.01f + 2.0f * r * u(rng);
    s.add({.px = x,
           .py = y,
           .pz = z,
           .vx = 4.0f * (u(rng) - 0.5f),
           .vy = -20.0f * u(rng),
           .vz = 4.0f * (u(rng) - 0.5f),
           .wx = 0.0f,
           .wy = 0.0f,
           .wz = 0.0f,
           .radius = r,
           .inv_mass = 1.0f,
           .inv_inertia = 1.0f,
           .restitution = 0.3f,
           .friction = 0.5f,
           .flags = 0});
  }
  return s;
}

}  // namespace

TEST_CASE("Steep terrain: no contact of a sphere above the surface is deeper than its true distance",
          "[terrain][steep]") {
  constexpr float dt = 1.0f / 60.0f;
  float worst_excess = 0.0f;  // how much deeper than the truth the worst contact was (m)
  std::size_t contacts_checked = 0;
  for (const SteepKind kind : hail::bench::kSteepKinds) {
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      const auto terrain = std::make_shared<const Terrain>(hail::bench::steep_heightmap(kind, seed));
      const SphereSoA s = spheres_above(terrain->heightmap(), seed * 101 + static_cast<std::uint32_t>(kind), 400);
      std::vector<float> truth(s.size());
      for (std::size_t i = 0; i < s.size(); ++i) truth[i] = true_distance(*terrain, s.px[i], s.py[i], s.pz[i]);
      auto check = [&](const std::vector<Contact>& found, const char* who) {
        for (const Contact& c : found) {
          const std::size_t i = c.a;
          const float too_deep = (truth[i] - s.radius[i]) - c.gap;  // > 0: deeper than the truth
          const float tolerance = 1e-4f * (1.0f + std::fabs(s.py[i]));
          worst_excess = std::max(worst_excess, too_deep);
          ++contacts_checked;
          if (too_deep > tolerance) {
            INFO(who << ", map " << hail::bench::steep_kind_name(kind) << " seed " << seed << ", sphere " << i
                     << " at (" << s.px[i] << ", " << s.py[i] << ", " << s.pz[i] << ") r " << s.radius[i]
                     << ": contact gap " << c.gap << ", true gap " << truth[i] - s.radius[i]);
            CHECK(too_deep <= tolerance);
          }
        }
      };
      std::vector<Contact> reference;
      terrain->find_contacts_scalar(s, 0, s.size(), dt, 0.5f, 0.5f, reference, 1.0f, false);
      check(reference, "scalar");
      for (SimdPath p : hail::testing::supported_paths()) {
        std::vector<Contact> found;
        simd_kernels(p).terrain_contacts(*terrain, s, 0, s.size(), dt, 0.5f, 0.5f, found, 1.0f, false);
        check(found, simd_path_name(p));
      }
    }
  }
  REQUIRE(contacts_checked > 1000);  // the maps and spheres do meet
  WARN("steep maps: " << contacts_checked << " contacts, worst excess depth " << worst_excess << " m");
}

TEST_CASE("Steep terrain: no step moves a sphere farther than its speed and its true overlap allow",
          "[terrain][steep]") {
  constexpr float dt = 1.0f / 60.0f;
  const float g = 9.81f;
  double worst_excess = 0.0;  // most a sphere moved beyond what its speed and overlap allow (m)
  int moved_checked = 0;
  for (const SteepKind kind : hail::bench::kSteepKinds) {
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      const auto terrain = std::make_shared<const Terrain>(hail::bench::steep_heightmap(kind, seed));
      const HeightmapExtent e = terrain->heightmap().extent();
      World world(WorldSettings{.threads = 1});
      world.set_terrain(terrain, 0.3f, 0.5f);
      // Spheres clear of the ground (true gap >= 1 cm), 4 m apart so that they never meet.
      std::mt19937 rng(seed * 7 + static_cast<std::uint32_t>(kind));
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      std::vector<Vec3> start, start_velocity;
      std::vector<float> radius;
      std::vector<SphereId> ids;
      for (float x = e.min_x + 2.0f; x < e.max_x - 2.0f; x += 4.0f) {
        for (float z = e.min_z + 2.0f; z < e.max_z - 2.0f; z += 4.0f) {
          const float r = 0.1f + 0.9f * u(rng);
          const float px = x + u(rng) - 0.5f, pz = z + u(rng) - 0.5f;
          float py = terrain->heightmap().surface_height(px, pz) + r * (0.2f + 2.0f * u(rng));
          while (true_distance(*terrain, px, py, pz) < r + 0.01f) py += 0.1f * r;
          const Vec3 v{6.0f * (u(rng) - 0.5f), -20.0f * u(rng), 6.0f * (u(rng) - 0.5f)};
          ids.push_back(world.add_sphere({.position = {px, py, pz}, .velocity = v, .radius = r}));
          radius.push_back(r);
          start.push_back({px, py, pz});
          start_velocity.push_back(v);
        }
      }
      world.step(dt);
      for (std::size_t i = 0; i < start.size(); ++i) {
        const Vec3 p1 = world.position(ids[i]), v1 = world.velocity(ids[i]);
        // Impulses against static ground with restitution < 1 never add speed beyond gravity's.
        const float speed_allowed = start_velocity[i].norm() + g * dt;
        CHECK(v1.norm() <= speed_allowed * 1.0001f + 1e-4f);
        // Integration moves it |v1| dt (a swept fast sphere: its path, at most its fastest speed
        // times dt); depenetration at most by the overlap it then really has.
        const Vec3 integrated = start[i] + v1 * dt;
        const float overlap =
            std::max(0.0f, radius[i] - true_distance(*terrain, integrated.x(), integrated.y(), integrated.z()));
        const double moved = (p1 - start[i]).norm();
        const double allowed = std::max(v1.norm(), speed_allowed) * dt + overlap + 1e-3 * radius[i];
        worst_excess = std::max(worst_excess, moved - allowed);
        ++moved_checked;
        if (moved > allowed) {
          INFO("map " << hail::bench::steep_kind_name(kind) << " seed " << seed << ": sphere at (" << start[i].x()
                      << ", " << start[i].y() << ", " << start[i].z() << ") r " << radius[i] << " moved " << moved
                      << " m, allowed " << allowed << " (overlap " << overlap << ")");
          CHECK(moved <= allowed);
        }
      }
    }
  }
  REQUIRE(moved_checked > 100);
  WARN("steep maps: " << moved_checked << " sphere steps, worst move beyond the allowance " << worst_excess << " m");
}
