// SIMD dispatch (kernel/dispatch/simd_dispatch.h): every kernel of every SIMD path this CPU supports
// against its scalar reference, bit for bit, and a small scene's state hash on every path.
// Paths the CPU lacks are skipped (run the suite under `qemu-x86_64 -cpu Nehalem` or
// `-cpu Haswell` to exercise the narrower ones alone; docs/simd.md).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "catch.h"
#include "hail/errors.h"
#include "hail/world.h"
#include "kernel/broadphase/sorted_axis_pairs.h"
#include "kernel/broadphase/sphere_grid.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/ccd/path_box_scan.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/mesh/mesh_collider.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/integrate.h"
#include "kernel/terrain/terrain_parts.h"
#include "scenes/mesh_shapes.h"
#include "scenes/solver_problems.h"
#include "simd_paths.h"

using namespace hail;
using hail::bench::SolverProblem, hail::bench::random_contacts, hail::bench::same_bits;
using hail::testing::ScopedSimdPath;
using hail::testing::supported_paths;

namespace {

float hills(float x, float z) {
  return 3.0f * std::sin(0.15f * x) * std::cos(0.11f * z) + 1.5f * std::sin(0.4f * x + 0.3f * z);
}

/// n spheres in a box of side `side`, radii 0.2..0.7 (three sweep classes with `giants`),
/// random velocities up to `speed`.
SphereSoA random_spheres(std::size_t n, float side, float speed, std::uint32_t seed, bool giants = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), v(-1.0f, 1.0f);
  SphereSoA s;
  for (std::size_t k = 0; k < n; ++k) {
    const float r = giants && k % 50 == 0 ? 3.0f : 0.2f + 0.5f * u(rng);
    s.add({.px = side * u(rng),
           .py = side * u(rng),
           .pz = side * u(rng),
           .vx = speed * v(rng),
           .vy = speed * v(rng),
           .vz = speed * v(rng),
           .wx = 0.0f,
           .wy = 0.0f,
           .wz = 0.0f,
           .radius = r,
           .inv_mass = 1.0f,
           .inv_inertia = 1.0f,
           .restitution = 0.5f,
           .friction = 0.5f,
           .flags = 0});
  }
  return s;
}

bool same_contacts(const std::vector<Contact>& a, const std::vector<Contact>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Contact)) == 0);
}

/// A hilly terrain with spheres raining onto it and a few fast ones shot through the pile.
std::uint64_t small_scene_hash(PairSearch search, int threads) {
  static const auto terrain = std::make_shared<const Terrain>(Heightmap::from_function(48, 48, {}, hills));
  WorldSettings settings;
  settings.threads = threads;
  settings.pair_search = search;
  World world(settings);
  world.set_terrain(terrain, 0.4f, 0.6f);
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int k = 0; k < 700; ++k) {
    const bool fast = k % 97 == 0;
    world.add_sphere({.position = {8.0f + 30.0f * u(rng), 6.0f + 0.9f * float(k / 60), 8.0f + 30.0f * u(rng)},
                      .velocity = {fast ? 400.0f * (u(rng) - 0.5f) : 0.0f, fast ? -300.0f : 0.0f, 0.0f},
                      .radius = 0.3f + 0.2f * u(rng),
                      .mass = 1.0f + u(rng),
                      .restitution = 0.4f,
                      .friction = 0.5f});
  }
  for (int k = 0; k < 120; ++k) world.step(1.0f / 60.0f);
  REQUIRE(world.nan_count() == 0);
  return world.state_hash();
}

}  // namespace

TEST_CASE("SIMD paths: names, widths, support and errors", "[simd][dispatch]") {
  for (SimdPath p : kSimdPaths) {
    CHECK(parse_simd_path(simd_path_name(p)) == p);
    if (!simd_path_supported(p)) {
      CHECK_THROWS_AS(set_simd_path(p), InvalidArgument);
      CHECK_THROWS_AS(simd_kernels(p), InvalidArgument);
      continue;
    }
    const SimdKernels& k = simd_kernels(p);
    CHECK(k.path == p);
    CHECK(k.width == simd_path_width(p));
    CHECK(k.width <= kSimdPadding);
  }
  CHECK_THROWS_AS(parse_simd_path("avx9"), InvalidArgument);
  CHECK_THROWS_AS(parse_simd_path(""), InvalidArgument);
  CHECK_THROWS_AS(parse_simd_path("AVX2"), InvalidArgument);  // names are exact
  // Every CPU that runs the base code (x86-64-v2) has the SSE4.2 path, and the widest is chosen.
  CHECK(simd_path_supported(SimdPath::Sse42));
  CHECK(simd_path_supported(best_simd_path()));
  for (SimdPath p : kSimdPaths)
    if (simd_path_supported(p)) CHECK(static_cast<int>(p) <= static_cast<int>(best_simd_path()));
  const SimdPath before = active_simd_path();
  {
    const ScopedSimdPath narrow(SimdPath::Sse42);
    CHECK(active_simd_path() == SimdPath::Sse42);
    CHECK(&simd_kernels() == &simd_kernels(SimdPath::Sse42));
    CHECK(contact_batch_width() == 4);
  }
  CHECK(active_simd_path() == before);
  INFO("supported: " << supported_simd_paths());
  CHECK(!supported_simd_paths().empty());
}

TEST_CASE("Every SIMD path's pair searches equal brute force's scalar reference", "[simd][dispatch][pairs]") {
  for (const std::size_t n : {std::size_t{1}, std::size_t{5}, std::size_t{17}, std::size_t{100}, std::size_t{1003}}) {
    const SphereSoA s = random_spheres(n, 12.0f, 0.0f, static_cast<std::uint32_t>(n), n == 1003);
    const float margin = 0.05f;
    std::vector<SpherePair> reference;
    find_sphere_pairs_scalar(s, 0, n, margin, reference);
    SortedAxisPairs sweep;
    sweep.build(s, margin);
    SphereGrid grid;
    grid.build(s, margin);
    std::vector<SpherePair> grid_scalar;
    std::vector<std::uint32_t> scratch;
    grid.find_pairs_scalar(s, 0, n, margin, grid_scalar, scratch);
    CHECK(grid_scalar == reference);
    for (SimdPath p : supported_paths()) {
      INFO(n << " spheres, path " << simd_path_name(p));
      const SimdKernels& k = simd_kernels(p);
      std::vector<SpherePair> brute, swept;
      std::vector<std::uint32_t> row;
      // In two row blocks whose boundary is not a multiple of any width.
      const std::size_t mid = n / 3;
      k.find_sphere_pairs(s, 0, mid, margin, brute);
      k.find_sphere_pairs(s, mid, n, margin, brute);
      CHECK(brute == reference);
      k.sorted_axis_find_pairs(sweep.view(), s, 0, mid, margin, swept, row);
      k.sorted_axis_find_pairs(sweep.view(), s, mid, n, margin, swept, row);
      CHECK(swept == reference);
      CHECK(row.empty());
      std::vector<SpherePair> gridded;
      k.grid_find_pairs(grid.view(), s, 0, mid, margin, gridded, row);
      k.grid_find_pairs(grid.view(), s, mid, n, margin, gridded, row);
      CHECK(gridded == reference);
      CHECK(row.empty());
    }
  }
}

TEST_CASE("Every SIMD path's contact passes equal the scalar rules bit for bit", "[simd][dispatch][solver]") {
  // In every FrictionWork mode: no friction, friction without rotation, the full rules (when
  // compiled in).
  std::vector<FrictionWork> modes = {kNoFriction, kLinearFriction};
  modes.push_back(kWithFriction);
  for (SimdPath p : supported_paths()) {
    const ScopedSimdPath path(p);
    for (const FrictionWork work : modes)
      for (const std::size_t count : {std::size_t{3}, std::size_t{16}, std::size_t{37}, std::size_t{500}}) {
        INFO(count << " contacts, path " << simd_path_name(p) << ", friction mode " << int(work));
        SolverProblem simd = random_contacts(count, static_cast<std::uint32_t>(count));
        SolverProblem scalar = simd;
        const std::uint32_t colour_begin[2] = {0, static_cast<std::uint32_t>(count)};
        ContactBatches batches;
        batches.stage(simd.contacts, colour_begin, 1, simd.bodies);
        REQUIRE(batches.width() == simd_path_width(p));
        // Every contact in a batch, the last batch padded when count % width != 0: the
        // padding lanes must change nothing.
        REQUIRE(batches.batch_end(0) == (count + batches.width() - 1) / batches.width());
        REQUIRE(batches.tail_begin(0) == count);
        const std::span<Contact> tail = std::span(simd.contacts).subspan(batches.tail_begin(0));
        for (std::uint32_t pass = 0; pass < 3; ++pass) {
          const bool a = batches.solve_collision(0, batches.batch_end(0), simd.bodies, 1.0f / 60.0f, 0.5f, pass, work);
          const bool b = solve_collision_run_scalar(tail, simd.bodies, 1.0f / 60.0f, 0.5f, pass, work);
          CHECK((a || b) == solve_collision_run_scalar(scalar.contacts, scalar.bodies, 1.0f / 60.0f, 0.5f, pass, work));
        }
        batches.warm_start(0, batches.batch_end(0), simd.bodies, work);
        warm_start_run_scalar(tail, simd.bodies, work);
        warm_start_run_scalar(scalar.contacts, scalar.bodies, work);
        for (int pass = 0; pass < 3; ++pass) {
          batches.solve_resting(0, batches.batch_end(0), simd.bodies, 60.0f, work);
          solve_resting_run_scalar(tail, simd.bodies, 60.0f, work);
          solve_resting_run_scalar(scalar.contacts, scalar.bodies, 60.0f, work);
        }
        batches.store_impulses(simd.contacts);
        CHECK(same_bits(simd, scalar));  // the bounce impulses included
        if (count >= 16)                 // (3 random contacts need not bounce)
          CHECK(std::any_of(simd.contacts.begin(), simd.contacts.end(),
                            [](const Contact& c) { return c.bounce_impulse > 0.0f; }));
      }
  }
}

TEST_CASE("Every SIMD path's terrain contacts and packet walks equal the single scalar walks",
          "[simd][dispatch][terrain]") {
  const Terrain terrain(Heightmap::from_function(40, 40, {}, hills), 4);
  // Spheres resting on, hovering over and sunk into the surface, some fast.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  SphereSoA s;
  for (int k = 0; k < 301; ++k) {
    const float x = 1.0f + 37.0f * u(rng), z = 1.0f + 37.0f * u(rng), r = 0.2f + 0.6f * u(rng);
    const float fall = k % 23 == 0 ? -200.0f : -6.0f * u(rng);
    s.add({.px = x,
           .py = hills(x, z) + r * (2.0f * u(rng) - 0.3f),
           .pz = z,
           .vx = 2.0f * u(rng),
           .vy = fall,
           .vz = 0.0f,
           .wx = 0.0f,
           .wy = 0.0f,
           .wz = 0.0f,
           .radius = r,
           .inv_mass = k % 31 == 0 ? 0.0f : 1.0f,
           .inv_inertia = 1.0f,
           .restitution = 0.3f,
           .friction = 0.7f,
           .flags = 0});
  }
  // The packet queries also get two spheres with a NaN coordinate, mid-packet: they touch no
  // box, in the scalar test and in every lane of the packet test alike.
  std::vector<float> x(s.size()), y(s.size()), z(s.size()), r(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) x[i] = s.px[i], y[i] = s.py[i], z[i] = s.pz[i], r[i] = s.radius[i] + 0.25f;
  x[5] = std::numeric_limits<float>::quiet_NaN();
  z[40] = std::numeric_limits<float>::quiet_NaN();
  std::uint64_t scalar_hits = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    query_sphere(terrain.bvh(), x[i], y[i], z[i], r[i], [&](std::uint32_t k) {
      scalar_hits += sphere_overlaps(terrain.triangle_bounds()[k], x[i], y[i], z[i], r[i]);
    });
  REQUIRE(scalar_hits > 0);
  CHECK_FALSE(sphere_overlaps(terrain.triangle_bounds()[0], x[5], y[5], z[5], 1e30f));
  for (const bool sweep_fast : {false, true}) {
    std::vector<Contact> reference;
    terrain.find_contacts_scalar(s, 0, 150, 1.0f / 60.0f, 0.5f, 0.5f, reference, 1.0f, sweep_fast);
    terrain.find_contacts_scalar(s, 150, s.size(), 1.0f / 60.0f, 0.5f, 0.5f, reference, 1.0f, sweep_fast);
    REQUIRE(reference.size() > 100);
    for (SimdPath p : supported_paths()) {
      INFO("path " << simd_path_name(p) << ", sweep_fast " << sweep_fast);
      const SimdKernels& k = simd_kernels(p);
      std::vector<Contact> found;
      k.terrain_contacts(terrain, s, 0, 150, 1.0f / 60.0f, 0.5f, 0.5f, found, 1.0f, sweep_fast);
      k.terrain_contacts(terrain, s, 150, s.size(), 1.0f / 60.0f, 0.5f, 0.5f, found, 1.0f, sweep_fast);
      CHECK(same_contacts(found, reference));
    }
  }
  for (SimdPath p : supported_paths()) {
    INFO("path " << simd_path_name(p));
    const SimdKernels& k = simd_kernels(p);
    std::uint64_t nodes = 0;
    CHECK(k.count_packet_hits(terrain.bvh(), terrain.triangle_bounds().data(), x.data(), y.data(), z.data(), r.data(),
                              s.size(), PacketLeafTest::LeafCandidates, &nodes) == scalar_hits);
    CHECK(k.count_packet_hits(terrain.bvh(), terrain.triangle_bounds().data(), x.data(), y.data(), z.data(), r.data(),
                              s.size(), PacketLeafTest::LeafBoxes, nullptr) == scalar_hits);
    CHECK(nodes > 0);
  }
}

TEST_CASE("Every SIMD path's packet push-out moves spheres exactly as Terrain::push_out does one by one",
          "[simd][dispatch][terrain]") {
  for (const std::uint32_t leaf : {1u, 4u, 8u}) {
    const Terrain terrain(Heightmap::from_function(40, 40, {}, hills), leaf);
    // Spheres sunk into the surface by up to a radius and more, some above it, some off the
    // map; a few deep enough to need more than one round.
    std::mt19937 rng(11 + leaf);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    SphereSoA start;
    for (int k = 0; k < 203; ++k) {
      const float x = -2.0f + 43.0f * u(rng), z = -2.0f + 43.0f * u(rng), r = 0.2f + 0.6f * u(rng);
      start.add({.px = x,
                 .py = hills(x, z) + r * (1.5f - 3.0f * u(rng)),
                 .pz = z,
                 .vx = 0.0f,
                 .vy = 0.0f,
                 .vz = 0.0f,
                 .wx = 0.0f,
                 .wy = 0.0f,
                 .wz = 0.0f,
                 .radius = r,
                 .inv_mass = 1.0f,
                 .inv_inertia = 1.0f,
                 .restitution = 0.3f,
                 .friction = 0.7f,
                 .flags = 0});
    }
    // Every third sphere, so that the packets hold spheres that are not neighbours in the SoA.
    std::vector<std::uint32_t> slots;
    for (std::uint32_t i = 0; i < start.size(); i += 3) slots.push_back(i);
    SphereSoA reference = start;
    std::size_t reference_moved = 0;
    for (std::uint32_t i : slots)
      reference_moved += terrain.push_out(reference.px[i], reference.py[i], reference.pz[i], reference.radius[i]);
    REQUIRE(reference_moved > 10);
    REQUIRE(reference_moved < slots.size());
    for (SimdPath p : supported_paths()) {
      INFO("path " << simd_path_name(p) << ", leaf size " << leaf);
      SphereSoA s = start;
      CHECK(simd_kernels(p).terrain_push_out(terrain, s, slots.data(), slots.size()) == reference_moved);
      CHECK(std::memcmp(s.px.data(), reference.px.data(), s.size() * sizeof(float)) == 0);
      CHECK(std::memcmp(s.py.data(), reference.py.data(), s.size() * sizeof(float)) == 0);
      CHECK(std::memcmp(s.pz.data(), reference.pz.data(), s.size() * sizeof(float)) == 0);
    }
  }
}

TEST_CASE("Every SIMD path's batch closest points equal closest_point_on_triangle in every region",
          "[simd][dispatch][terrain]") {
  // Points around random triangles, some of them degenerate (a repeated vertex, three in a
  // line), and a few NaN points, so that each of the seven regions and the last resort (no
  // region test holds, as for a NaN: vertex a) come up.
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  constexpr std::size_t kCount = 3001;  // not a multiple of any width: the last batch is partial
  std::vector<float> v[15];
  for (auto& array : v) array.resize(kCount);
  for (std::size_t k = 0; k < kCount; ++k) {
    for (int e = 0; e < 12; ++e) v[e][k] = u(rng);
    if (k % 7 == 0)
      for (int d = 0; d < 3; ++d) v[9 + d][k] = v[6 + d][k];  // c = b
    if (k % 11 == 0)
      for (int d = 0; d < 3; ++d) v[9 + d][k] = 2.0f * v[6 + d][k] - v[3 + d][k];  // c on the line through a, b
    if (k % 97 == 0) v[k % 3][k] = std::numeric_limits<float>::quiet_NaN();  // no region test holds: the last resort
  }
  const TriangleQueries queries{{v[0].data(), v[1].data(), v[2].data()},
                                {v[3].data(), v[4].data(), v[5].data()},
                                {v[6].data(), v[7].data(), v[8].data()},
                                {v[9].data(), v[10].data(), v[11].data()}};
  std::vector<TrianglePoint> reference(kCount);
  int regions_seen[7] = {};
  for (std::size_t k = 0; k < kCount; ++k) {
    const float q[3] = {v[0][k], v[1][k], v[2][k]}, a[3] = {v[3][k], v[4][k], v[5][k]},
                b[3] = {v[6][k], v[7][k], v[8][k]}, c[3] = {v[9][k], v[10][k], v[11][k]};
    reference[k] = closest_point_on_triangle(q, a, b, c);
    ++regions_seen[static_cast<int>(reference[k].region)];
  }
  for (int r = 0; r < 7; ++r) CHECK(regions_seen[r] > 10);
  for (SimdPath path : supported_paths()) {
    INFO("path " << simd_path_name(path));
    float* const p[3] = {v[12].data(), v[13].data(), v[14].data()};
    std::vector<std::uint8_t> region(kCount, 255);
    simd_kernels(path).closest_points(queries, kCount, p, region.data());
    std::size_t differ = 0;
    for (std::size_t k = 0; k < kCount; ++k) {
      const float point[3] = {p[0][k], p[1][k], p[2][k]};
      differ += region[k] != static_cast<std::uint8_t>(reference[k].region) ||
                std::memcmp(reference[k].p, point, sizeof point) != 0;
    }
    CHECK(differ == 0);
  }
}

TEST_CASE("Every SIMD path's integration without planes equals the scalar reference bit for bit",
          "[simd][dispatch][integrate]") {
  // 1,003 spheres (a partial last batch on every path): some static, some with gravity scales
  // and forces, start velocities scattered about the end ones so that the uniform
  // integrator's acceleration falls inside, on and outside its ball, and (with skip) every
  // seventh sphere moved already.
  SphereSoA s = random_spheres(1003, 40.0f, 5.0f, 21);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> v(-1.0f, 1.0f);
  const std::size_t n = s.size();
  std::vector<float> start[3];
  for (std::vector<float>& c : start) c.resize(n);
  std::vector<std::uint8_t> skip(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 11 == 0) s.inv_mass[i] = 0.0f;
    s.gravity_scale[i] = i % 5 == 0 ? 2.0f * v(rng) : 1.0f;
    s.force_x[i] = i % 3 == 0 ? 20.0f * v(rng) : 0.0f;
    s.force_y[i] = i % 3 == 0 ? 20.0f * v(rng) : 0.0f;
    s.force_z[i] = 0.0f;
    const float scatter = i % 4 == 0 ? 0.0f : i % 4 == 1 ? 0.01f : 0.5f;
    start[0][i] = s.vx[i] + scatter * v(rng);
    start[1][i] = s.vy[i] + 9.81f / 60.0f + scatter * v(rng);
    start[2][i] = s.vz[i] + scatter * v(rng);
    skip[i] = i % 7 == 0 ? 1 : 0;
  }
  for (const Integrator integrator : {Integrator::UniformAcceleration, Integrator::SemiImplicitEuler}) {
    for (const bool scaled : {false, true}) {
      for (const bool forces : {false, true}) {
        for (const std::uint8_t* skipped : {static_cast<const std::uint8_t*>(nullptr), static_cast<const std::uint8_t*>(skip.data())}) {
          IntegrationParams p;
          p.modes.integrator = integrator;
          p.modes.gravity_scaled = scaled;
          p.modes.forces = forces;
          p.dt = 1.0f / 60.0f;
          p.start_vx = start[0].data(), p.start_vy = start[1].data(), p.start_vz = start[2].data();
          SphereSoA reference = s;
          integrate_free_scalar(reference, 0, n, p, skipped);
          for (SimdPath path : supported_paths()) {
            INFO("path " << simd_path_name(path) << ", uniform " << (integrator == Integrator::UniformAcceleration)
                         << ", scaled " << scaled << ", forces " << forces << ", skip " << (skipped != nullptr));
            SphereSoA moved = s;
            simd_kernels(path).integrate_free(moved, 0, n, p, skipped);
            for (auto member : {&SphereSoA::px, &SphereSoA::py, &SphereSoA::pz, &SphereSoA::vx, &SphereSoA::vy,
                                &SphereSoA::vz})
              CHECK(std::memcmp((moved.*member).data(), (reference.*member).data(), n * sizeof(float)) == 0);
          }
        }
      }
    }
  }
}

TEST_CASE("Every SIMD path's path-box scan visits exactly the scalar reference's spheres", "[simd][dispatch][ccd]") {
  const SphereSoA s = random_spheres(1003, 40.0f, 300.0f, 11);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 40.0f);
  for (int trial = 0; trial < 40; ++trial) {
    PathBox box;
    for (int d = 0; d < 3; ++d) box.min[d] = u(rng), box.max[d] = box.min[d] + 0.2f * u(rng);
    std::vector<std::uint32_t> reference;
    scan_path_boxes_scalar(s, box, 0.001f, 1.0f / 60.0f, [&](std::uint32_t j) { reference.push_back(j); });
    for (SimdPath p : supported_paths()) {
      INFO("path " << simd_path_name(p) << ", trial " << trial);
      std::vector<std::uint32_t> found;
      auto visit = [&](std::uint32_t j) { found.push_back(j); };
      simd_kernels(p).scan_path_boxes(s, box, 0.001f, 1.0f / 60.0f, slot_sink(visit));
      CHECK(found == reference);
    }
  }
}

TEST_CASE("A small terrain scene has the same state hash on every SIMD path",
          "[simd][dispatch][determinism][threads]") {
  // Brute force and sweep and prune (the two SIMD pair searches), contacts batched by the path's
  // width, the packet walk, the path-box scan of the fast spheres: bitwise the same state.
  for (const PairSearch search : {PairSearch::BruteForce, PairSearch::SweepAndPrune}) {
    std::uint64_t first = 0;
    for (SimdPath p : supported_paths()) {
      const ScopedSimdPath path(p);
      const std::uint64_t hash = small_scene_hash(search, 2);
      INFO("path " << simd_path_name(p) << ", pair search " << static_cast<int>(search) << ", hash " << std::hex
                   << hash);
      if (first == 0) first = hash;
      CHECK(hash == first);
    }
  }
}

TEST_CASE("Every SIMD path's mesh contacts equal the scalar reference's, shell and solid", "[simd][dispatch][mesh]") {
  // A bumpy sheet (a shell) and a closed box (a solid) of many triangles; spheres in front of,
  // on, behind and through them, some fast, some static.
  const int cells = 24;
  std::vector<Vec3> v;
  std::vector<std::uint32_t> idx;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) v.emplace_back(float(i), 0.8f * std::sin(0.5f * i) * std::cos(0.4f * j), float(j));
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (cells + 1) + a); };
      idx.insert(idx.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  const TriangleMesh sheet(v, idx);
  const TriangleMesh box = hail::bench::box_mesh({4.0f, -3.0f, 4.0f}, {20.0f, 1.0f, 20.0f});
  REQUIRE(box.closed());
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  SphereSoA s;
  for (int k = 0; k < 401; ++k) {
    const float r = 0.2f + 0.6f * u(rng);
    s.add({.px = 24.0f * u(rng),
           .py = -2.5f + 4.0f * u(rng),
           .pz = 24.0f * u(rng),
           .vx = 2.0f * u(rng),
           .vy = k % 23 == 0 ? -200.0f : -6.0f * u(rng),
           .vz = 0.0f,
           .wx = 0.0f,
           .wy = 0.0f,
           .wz = 0.0f,
           .radius = r,
           .inv_mass = k % 31 == 0 ? 0.0f : 1.0f,
           .inv_inertia = 1.0f,
           .restitution = 0.3f,
           .friction = 0.7f,
           .flags = 0});
  }
  for (const TriangleMesh* mesh : {&sheet, &box}) {
    const MeshCollider collider = build_mesh_collider(*mesh, {}, 0.4f, 0.6f, 1000);
    CHECK(collider.two_sided == !mesh->closed());
    for (const bool sweep_fast : {false, true}) {
      std::vector<Contact> reference;
      collider.find_contacts_scalar(s, 0, 150, 1.0f / 60.0f, reference, 1.0f, sweep_fast);
      collider.find_contacts_scalar(s, 150, s.size(), 1.0f / 60.0f, reference, 1.0f, sweep_fast);
      REQUIRE(reference.size() > 50);
      for (SimdPath p : supported_paths()) {
        INFO("path " << simd_path_name(p) << ", sweep_fast " << sweep_fast << ", closed " << mesh->closed());
        const SimdKernels& k = simd_kernels(p);
        std::vector<Contact> found;
        k.mesh_contacts(collider, s, 0, 150, 1.0f / 60.0f, found, 1.0f, sweep_fast);
        k.mesh_contacts(collider, s, 150, s.size(), 1.0f / 60.0f, found, 1.0f, sweep_fast);
        CHECK(same_contacts(found, reference));
      }
    }
  }
}
