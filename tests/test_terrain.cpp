// Heightmap loading (real DEMs and bad files), the flat BVH walks, and spheres on terrain.

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>
#include <random>
#include <set>
#include <string>

#include "catch.h"
#include "hail/world.h"
#include "kernel/terrain/terrain_parts.h"
#include "sample_count.h"

using namespace hail;

namespace {

std::string data(const char* name) { return std::string(HAIL_SOURCE_DIR) + "/data/" + name; }

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = "/tmp/hail_test_" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// Whether triangle k's box touches the sphere: what both the walks (after their leaf
/// candidates are filtered) and the brute-force scan decide.
bool triangle_box_hit(const Terrain& t, std::uint32_t k, float x, float y, float z, float r) {
  FlatNode box{};
  const TerrainTriangles& s = t.triangles();
  box.min[0] = std::min({s.v0x[k], s.v1x[k], s.v2x[k]});
  box.max[0] = std::max({s.v0x[k], s.v1x[k], s.v2x[k]});
  box.min[1] = std::min({s.v0y[k], s.v1y[k], s.v2y[k]});
  box.max[1] = std::max({s.v0y[k], s.v1y[k], s.v2y[k]});
  box.min[2] = std::min({s.v0z[k], s.v1z[k], s.v2z[k]});
  box.max[2] = std::max({s.v0z[k], s.v1z[k], s.v2z[k]});
  return sphere_overlaps(box, x, y, z, r);
}

std::set<std::uint32_t> brute_force(const Terrain& t, float x, float y, float z, float r) {
  std::set<std::uint32_t> hits;
  for (std::uint32_t k = 0; k < t.triangles().size(); ++k)
    if (triangle_box_hit(t, k, x, y, z, r)) hits.insert(k);
  return hits;
}

}  // namespace

TEST_CASE("The real DEMs load with their documented height range and non-square cells", "[heightmap]") {
  HeightmapParams jacksboro{
      .cell_x = 74.573f, .cell_z = 92.475f, .height_scale = 0.0128175783932f, .height_offset = 236.0f};
  const Heightmap a = Heightmap::load_pgm(data("jacksboro_srtm3_403x344.pgm"), jacksboro);
  CHECK(a.cols() == 403);
  CHECK(a.rows() == 344);
  CHECK(a.min_height() == Approx(236.0).margin(0.01));
  CHECK(a.max_height() == Approx(1076.0).margin(0.01));
  CHECK(a.max_z() == Approx(343 * 92.475).epsilon(1e-5));
  HeightmapParams salish{
      .cell_x = 2438.758f, .cell_z = 2431.556f, .height_scale = 0.0555733577478f, .height_offset = -1437.0f};
  const Heightmap b = Heightmap::load_pgm(data("salish_topobathy_120x91.pgm"), salish);
  CHECK(b.min_height() == Approx(-1437.0).margin(0.03));
  CHECK(b.max_height() == Approx(2205.0).margin(0.03));
  const Terrain terrain(b);
  CHECK(terrain.triangles().size() == 2u * 119 * 90);
}

TEST_CASE("P2 and 8-bit P5 load; every bad file is a FileError naming the file", "[heightmap]") {
  const Heightmap ascii = Heightmap::load_pgm(write_file("ok.pgm", "P2\n# comment\n3 2\n10\n0 1 2\n3 4 10\n"), {});
  CHECK(ascii.height(2, 1) == 10.0f);
  const Heightmap binary =
      Heightmap::load_pgm(write_file("ok5.pgm", std::string("P5 2 2 255\n") + "\x01\x02\x03\xff"), {});
  CHECK(binary.height(1, 1) == 255.0f);
  const std::pair<const char*, std::string> bad[] = {
      {"magic.pgm", "P6\n2 2\n255\n\x01\x02\x03\x04"},
      {"truncated.pgm", "P5\n4 4\n255\n\x01\x02"},
      {"zero.pgm", "P5\n0 4\n255\n"},
      {"absurd.pgm", "P5\n60000 60000\n65535\n"},
      {"maxval0.pgm", "P5\n2 2\n0\n\x00\x00\x00\x00"},
      {"garbage.pgm", "P2\n2 x\n255\n1 2 3 4"},
      {"ascii_short.pgm", "P2\n2 2\n255\n1 2 3"},
      {"one_cell_wide.pgm", "P2\n1 3\n255\n1 2 3"},
      {"empty.pgm", ""},
  };
  for (const auto& [name, bytes] : bad) {
    const std::string path = write_file(name, bytes);
    try {
      (void)Heightmap::load_pgm(path, {});
      FAIL("accepted " << name);
    } catch (const FileError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(path) != std::string::npos);
    }
  }
  CHECK_THROWS_AS(Heightmap::load_pgm("/nonexistent/hail.pgm", {}), FileError);
  CHECK_THROWS_AS(Heightmap::from_function(2, 2, {}, [](float, float) { return NAN; }), InvalidArgument);
  CHECK_THROWS_AS(Heightmap::from_function(2, 2, {.cell_x = 0}, [](float, float) { return 0.0f; }), InvalidArgument);
}

TEST_CASE("Stackless and stack walks return exactly the brute-force triangle set", "[bvh]") {
  struct Map {
    const char* name;
    std::uint32_t cols, rows;
    float (*h)(float, float);
  };
  const Map maps[] = {
      {"flat", 33, 17, [](float, float) { return 0.0f; }},
      {"single cell", 2, 2, [](float x, float z) { return x * 0.3f + z; }},
      {"1x2 cells", 2, 3, [](float x, float) { return x; }},
      {"cliff", 20, 20, [](float x, float) { return x < 10 ? 0.0f : 50.0f; }},
      {"huge range", 30, 30, [](float x, float z) { return 1e4f * std::sin(x) * std::cos(z); }},
      {"sines", 64, 64,
       [](float x, float z) {
         return 8 * std::sin(0.05f * x) * std::cos(0.07f * z) + 3 * std::sin(0.21f * x + 0.13f * z);
       }},
  };
  std::mt19937 rng(42);
  for (const Map& m : maps) {
    for (std::uint32_t leaf : {1u, 4u, 8u}) {
      const Terrain t(Heightmap::from_function(m.cols, m.rows, {}, m.h), leaf);
      std::uniform_real_distribution<float> ux(-2, float(m.cols) + 1), uz(-2, float(m.rows) + 1),
          uy(t.heightmap().min_height() - 3, t.heightmap().max_height() + 3), ur(0.01f, 3.0f);
      const int queries = hail::test::sample_count(m.cols * m.rows > 1000 ? 2000 : 10000 / 3);
      for (int q = 0; q < queries; ++q) {
        const float x = ux(rng), y = uy(rng), z = uz(rng), r = ur(rng);
        // The walks hand out every triangle of each leaf they reach; the visitor's box test
        // (as in Terrain::find_contacts' triangle test) keeps those that touch.
        std::set<std::uint32_t> stackless, stack;
        std::size_t visits = 0, distinct = 0;
        std::set<std::uint32_t> all_visited;
        query_sphere(t.bvh(), x, y, z, r, [&](std::uint32_t k) {
          ++visits;
          all_visited.insert(k);
          if (triangle_box_hit(t, k, x, y, z, r)) stackless.insert(k);
        });
        distinct = all_visited.size();
        query_sphere_stack(t.bvh(), x, y, z, r, [&](std::uint32_t k) {
          if (triangle_box_hit(t, k, x, y, z, r)) stack.insert(k);
        });
        const std::set<std::uint32_t> brute = brute_force(t, x, y, z, r);
        INFO(m.name << ", leaf " << leaf);
        REQUIRE(stackless == brute);
        REQUIRE(stack == brute);
        REQUIRE(visits == distinct);  // no leaf (so no triangle) visited twice
      }
    }
  }
}

TEST_CASE("The flat BVH layout: 32-byte nodes, skip = end of subtree, every triangle in one leaf", "[bvh]") {
  const Terrain t(Heightmap::from_function(40, 30, {}, [](float x, float z) { return std::sin(x) + z * 0.1f; }), 4);
  const auto& nodes = t.bvh().nodes;
  REQUIRE(nodes.size() > 1);
  CHECK(nodes[0].skip == kFlatBvhEnd);
  std::vector<int> seen(t.triangles().size(), 0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const FlatNode& n = nodes[i];
    if (n.leaf != 0) {
      CHECK(leaf_count(n) >= 1);
      CHECK(leaf_count(n) <= 4);
      CHECK((n.skip == i + 1 || (n.skip == kFlatBvhEnd && i + 1 == nodes.size())));
      for (std::uint32_t k = leaf_first(n); k < leaf_first(n) + leaf_count(n); ++k) ++seen[k];
    } else {
      // The children (i + 1 and its skip) lie inside this node's box.
      for (std::uint32_t child : {std::uint32_t(i + 1), nodes[i + 1].skip})
        for (int a = 0; a < 3; ++a) {
          CHECK(nodes[child].min[a] >= n.min[a]);
          CHECK(nodes[child].max[a] <= n.max[a]);
        }
    }
  }
  CHECK(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
  // A stackless walk with a huge sphere visits every node exactly once and ends.
  std::size_t leaves_visited = 0;
  query_sphere(t.bvh(), 20, 0, 15, 1e6f, [&](std::uint32_t) { ++leaves_visited; });
  CHECK(leaves_visited == t.triangles().size());
  CHECK_THROWS_AS(Terrain(Heightmap::from_function(3, 3, {}, [](float, float) { return 0.0f; }), 9), InvalidArgument);
}

TEST_CASE("Internal edges: every shared edge of a flat map is internal, a sharp ridge is not", "[heightmap]") {
  const Terrain flat(Heightmap::from_function(6, 6, {}, [](float, float) { return 1.0f; }));
  const Terrain ridge(Heightmap::from_function(6, 6, {}, [](float x, float) { return x <= 2 ? x : 4 - x; }));
  int flat_internal = 0, ridge_internal = 0;
  for (std::size_t k = 0; k < flat.triangles().size(); ++k)
    flat_internal += std::popcount(unsigned(flat.triangles().internal_edges[k]));
  for (std::size_t k = 0; k < ridge.triangles().size(); ++k)
    ridge_internal += std::popcount(unsigned(ridge.triangles().internal_edges[k]));
  // 5x5 cells: edges shared by two triangles = 25 diagonals + 2 * 20 grid edges = 65, counted from both sides.
  CHECK(flat_internal == 2 * 65);
  CHECK(ridge_internal < flat_internal);
  for (std::size_t k = 0; k < flat.triangles().size(); ++k) CHECK(flat.triangles().ny[k] == 1.0f);
}

TEST_CASE("A pushed sphere on flat, finely triangulated terrain keeps a straight path and rolls at 5/7 v0",
          "[terrain]") {
  auto world = std::make_unique<World>(WorldSettings{.threads = 1});
  world->set_terrain(std::make_shared<const Terrain>(Heightmap::from_function(
                         101, 101, {.cell_x = 0.25f, .cell_z = 0.25f}, [](float, float) { return 0.0f; })),
                     0.0f, 0.3f);
  const float v0 = 3.0f;
  const SphereId id = world->add_sphere({.position = {2, 0.5f, 2.1f},
                                         .velocity = {v0, 0, 0.3f * v0},
                                         .radius = 0.5f,
                                         .mass = 1,
                                         .restitution = 0,
                                         .friction = 0.3f});
  double max_height_error = 0;
  for (int k = 0; k < 2000; ++k) {
    world->step(1.0f / 1000);
    max_height_error = std::max(max_height_error, std::abs(double(world->position(id).y()) - 0.5));
  }
  const Vec3 v = world->velocity(id), p = world->position(id);
  const double speed0 = v0 * std::sqrt(1.09);
  CHECK(std::hypot(v.x(), v.z()) == Approx(5.0 / 7.0 * speed0).epsilon(0.01));
  CHECK(std::abs(v.y()) < 1e-3);  // no bumps at triangle edges
  CHECK(max_height_error < 2e-3);
  CHECK(v.z() / v.x() == Approx(0.3).epsilon(1e-3));  // straight path: direction unchanged
  CHECK((p.z() - 2.1) / (p.x() - 2.0) == Approx(0.3).epsilon(1e-3));
}

TEST_CASE("A sphere rolls down a slope at 5/7 g sin(theta)", "[terrain]") {
  const float theta = 0.2f, g = 9.81f, r = 0.5f;
  auto world = std::make_unique<World>(WorldSettings{.threads = 1});
  world->set_terrain(
      std::make_shared<const Terrain>(Heightmap::from_function(200, 20, {.cell_x = 0.5f, .cell_z = 0.5f},
                                                               [&](float x, float) { return -std::tan(theta) * x; })),
      0.0f, 1.0f);
  const float x0 = 5, ground = -std::tan(theta) * x0;
  const SphereId id = world->add_sphere({.position = {x0 + r * std::sin(theta), ground + r * std::cos(theta), 5},
                                         .radius = r,
                                         .mass = 1,
                                         .restitution = 0,
                                         .friction = 1.0f});
  const float dt = 1.0f / 1000, t_end = 2.0f;
  for (int k = 0; k < int(t_end / dt); ++k) world->step(dt);
  const double along = world->velocity(id).norm();
  const double exact = 5.0 / 7.0 * g * std::sin(theta) * t_end;
  INFO("speed " << along << " exact " << exact);
  CHECK(along == Approx(exact).epsilon(0.01));
}
