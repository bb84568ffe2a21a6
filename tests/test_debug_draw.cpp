// include/hail/debug_draw.h: the terrain BVH's nodes and the pair grid's occupied cells as boxes
// (what hail-view draws with --draw-bvh and --draw-grid).

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "hail/debug_draw.h"
#include "hail/world.h"
#include "tests/catch.h"

using namespace hail;

namespace {

bool inside(const DebugBox& box, const Vec3& p, float slack = 0.0f) {
  return (p.array() >= box.min.array() - slack).all() && (p.array() <= box.max.array() + slack).all();
}

}  // namespace

TEST_CASE(
    "terrain_bvh_boxes: the root first, children one level down and inside their parent, every triangle in a leaf",
    "[debug-draw]") {
  const Terrain terrain(Heightmap::from_function(40, 30, {}, [](float x, float z) { return std::sin(x) + 0.1f * z; }),
                        4);
  std::vector<BvhNodeBox> nodes = {{}};  // replaced, not appended to
  terrain_bvh_boxes(terrain, nodes);
  REQUIRE(nodes.size() > 1);
  CHECK(nodes[0].depth == 0);
  CHECK_FALSE(nodes[0].leaf);
  // Pre-order: node i's parent is the last node before it one level up, whose box holds it.
  std::uint32_t deepest = 0;
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    REQUIRE(nodes[i].depth >= 1);
    REQUIRE(nodes[i].depth <= nodes[i - 1].depth + 1);
    std::size_t parent = i - 1;
    while (nodes[parent].depth != nodes[i].depth - 1) --parent;
    CHECK_FALSE(nodes[parent].leaf);
    CHECK(inside(nodes[parent].box, nodes[i].box.min));
    CHECK(inside(nodes[parent].box, nodes[i].box.max));
    deepest = std::max(deepest, nodes[i].depth);
  }
  CHECK(deepest >= 5);  // 2 x 39 x 29 triangles in leaves of at most 4
  // Every triangle lies in a leaf box, and at every depth the nodes there and the leaves above
  // cover every triangle (hail-view's --draw-bvh DEPTH draws those).
  for (std::uint32_t t = 0; t < terrain.triangle_count(); ++t) {
    const TerrainTriangle tri = terrain.triangle(t);
    const Vec3 centroid = (tri.a + tri.b + tri.c) / 3.0f;
    const auto holds = [&](const BvhNodeBox& n) {
      return inside(n.box, tri.a) && inside(n.box, tri.b) && inside(n.box, tri.c);
    };
    CHECK(std::any_of(nodes.begin(), nodes.end(), [&](const BvhNodeBox& n) { return n.leaf && holds(n); }));
    for (std::uint32_t d = 0; d <= deepest; ++d)
      CHECK(std::any_of(nodes.begin(), nodes.end(), [&](const BvhNodeBox& n) {
        return (n.depth == d || (n.leaf && n.depth < d)) && inside(n.box, centroid);
      }));
  }
}

TEST_CASE(
    "World::pair_grid_cells: the cells of the last step's grid, each once, holding every sphere; empty without the "
    "grid",
    "[debug-draw]") {
  WorldSettings settings;
  settings.threads = 1;
  settings.gravity = Vec3(0.0f, 0.0f, 0.0f);
  settings.pair_search = PairSearch::Grid;
  World world(settings);
  std::vector<Vec3> starts;
  for (int k = 0; k < 60; ++k) {  // two clusters, far apart
    const Vec3 p(float(k % 5) * 1.5f + (k >= 30 ? 100.0f : 0.0f), float((k / 5) % 3) * 1.5f, float(k / 15) * 1.5f);
    world.add_sphere({.position = p, .radius = 0.5f});
    starts.push_back(p);
  }
  std::vector<DebugBox> cells = {{}};
  world.pair_grid_cells(cells);
  CHECK(cells.empty());  // no step yet
  world.step(1.0f / 60.0f);
  REQUIRE(world.last_step_stats().pair_search == PairSearch::Grid);
  world.pair_grid_cells(cells);
  REQUIRE(!cells.empty());
  CHECK(cells.size() <= starts.size());
  const float side = cells[0].max.x() - cells[0].min.x();
  CHECK(side >= 2.0f * 2.0f * 0.5f);  // two reaches: at least two diameters
  for (const DebugBox& c : cells) {
    CHECK((c.max - c.min - Vec3::Constant(side)).norm() < 1e-4f * side);
    // Each once: no two cells share a corner.
    CHECK(std::count_if(cells.begin(), cells.end(),
                        [&](const DebugBox& o) { return (o.min - c.min).norm() < 1e-3f; }) == 1);
  }
  // The spheres were at rest (no gravity, not touching): they sat at their starts when the grid
  // was built, each in one of the cells.
  for (const Vec3& p : starts)
    CHECK(std::any_of(cells.begin(), cells.end(), [&](const DebugBox& c) { return inside(c, p, 1e-4f); }));
  // The two clusters are 100 m apart: the cells are not one block around both.
  const float span = std::max_element(cells.begin(), cells.end(), [](const DebugBox& a, const DebugBox& b) {
                       return a.max.x() < b.max.x();
                     })->max.x();
  CHECK(float(cells.size()) * side * side * side < span * side * side);

  WorldSettings brute = settings;
  brute.pair_search = PairSearch::BruteForce;
  World other(brute);
  for (const Vec3& p : starts) other.add_sphere({.position = p, .radius = 0.5f});
  other.step(1.0f / 60.0f);
  other.pair_grid_cells(cells);
  CHECK(cells.empty());
}
