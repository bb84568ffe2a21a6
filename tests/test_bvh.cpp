// The flat BVH against brute force: sphere, box and ray queries over random boxes and over
// heightmap-like triangle grids (made here, independent of kernel/heightmap*), for both split
// methods and leaf sizes 1, 4, 8; its layout (skip links, leaf ranges, nested boxes, depth);
// determinism; and its argument checks.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "catch.h"
#include "hail/errors.h"
#include "kernel/bvh/bvh_packet_walk.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/geometry/morton.h"
#include "kernel/geometry/ray_triangle.h"
#include "sample_count.h"

using namespace hail;

namespace {

struct Triangle {
  float v[3][3];
};

/// A primitive set: boxes, and the triangles they bound (empty for box-only sets).
struct PrimitiveSet {
  std::string name;
  std::vector<Aabb> bounds;
  std::vector<Triangle> triangles;
};

Aabb bounds_of(const Triangle& t) {
  Aabb b = empty_aabb();
  for (const auto& v : t.v) grow(b, v);
  return b;
}

/// Two triangles per cell of a (cells_x + 1) x (cells_z + 1) vertex grid of spacing `cell`,
/// heights from `height(i, j)` at vertex (i, j): the shape of a heightmap's triangles.
PrimitiveSet grid(std::string name, int cells_x, int cells_z, float cell,
                  const std::function<float(int, int)>& height) {
  PrimitiveSet set{std::move(name), {}, {}};
  for (int j = 0; j < cells_z; ++j)
    for (int i = 0; i < cells_x; ++i) {
      auto vertex = [&](int di, int dj, float* out) {
        out[0] = (i + di) * cell;
        out[1] = height(i + di, j + dj);
        out[2] = (j + dj) * cell;
      };
      Triangle a, b;
      vertex(0, 0, a.v[0]), vertex(0, 1, a.v[1]), vertex(1, 0, a.v[2]);
      vertex(1, 0, b.v[0]), vertex(0, 1, b.v[1]), vertex(1, 1, b.v[2]);
      set.triangles.push_back(a);
      set.triangles.push_back(b);
    }
  for (const Triangle& t : set.triangles) set.bounds.push_back(bounds_of(t));
  return set;
}

PrimitiveSet random_boxes(int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-50.0f, 50.0f), u(0.0f, 1.0f);
  PrimitiveSet set{"random boxes", {}, {}};
  for (int k = 0; k < count; ++k) {
    Aabb b;
    const float size = u(rng) < 0.1f ? 0.0f : 10.0f * std::pow(u(rng), 3.0f);  // some points, mostly small
    for (int a = 0; a < 3; ++a) {
      b.min[a] = pos(rng);
      b.max[a] = b.min[a] + size * u(rng);
    }
    set.bounds.push_back(b);
  }
  return set;
}

std::vector<PrimitiveSet> primitive_sets() {
  std::vector<PrimitiveSet> sets;
  sets.push_back(random_boxes(3000, 7));
  sets.push_back(grid("flat grid", 40, 30, 1.0f, [](int, int) { return 0.0f; }));
  sets.push_back(grid("single cell", 1, 1, 2.0f, [](int i, int j) { return 0.3f * i + 0.1f * j; }));
  sets.push_back(grid("1x2 cells", 1, 2, 1.0f, [](int i, int j) { return 0.5f * float(i * j); }));
  sets.push_back(grid("cliff", 30, 20, 1.0f, [](int i, int) { return i <= 15 ? 0.0f : 100.0f; }));
  sets.push_back(grid("1e4 m range", 32, 32, 10.0f, [](int i, int j) {
    return 1.0e4f * std::sin(0.7f * i) * std::cos(0.4f * j) + (i == 5 ? 1.0e4f : 0.0f);
  }));
  sets.push_back(grid("rolling", 50, 50, 0.5f, [](int i, int j) { return std::sin(0.3f * i) + 0.2f * j; }));
  return sets;
}

struct Sphere {
  float c[3], r;
};

Aabb set_bounds(const PrimitiveSet& set) {
  Aabb all = empty_aabb();
  for (const Aabb& b : set.bounds) grow(all, b);
  return all;
}

/// Spheres over the set's bounds (and a margin around them): radii log-uniform from 1/1000
/// to 1/2 of the bounds' diagonal, some zero (point queries), a few covering everything.
std::vector<Sphere> random_spheres(const PrimitiveSet& set, int count, std::uint32_t seed) {
  const Aabb all = set_bounds(set);
  float diagonal = 0.0f;
  for (int a = 0; a < 3; ++a) diagonal += (all.max[a] - all.min[a]) * (all.max[a] - all.min[a]);
  diagonal = std::max(std::sqrt(diagonal), 1.0f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Sphere> spheres(count);
  for (Sphere& s : spheres) {
    for (int a = 0; a < 3; ++a)
      s.c[a] = all.min[a] - 0.1f * diagonal + (all.max[a] - all.min[a] + 0.2f * diagonal) * u(rng);
    const float pick = u(rng);
    s.r = pick < 0.05f ? 0.0f : pick > 0.99f ? 2.0f * diagonal : diagonal * std::pow(10.0f, -3.0f + 2.7f * u(rng));
  }
  return spheres;
}

struct Structure {
  bool ok = true;
  std::string problem;
  int max_depth = 0;
  void fail(const std::string& what) {
    if (ok) problem = what;
    ok = false;
  }
};

/// Parses the subtree at i independently of the skip links and checks them; returns its end.
std::uint32_t check_subtree(const FlatBvh& bvh, std::span<const Aabb> bounds, std::uint32_t i, int depth,
                            std::uint32_t& next_primitive, int leaf_size, Structure& s) {
  const auto count = static_cast<std::uint32_t>(bvh.nodes.size());
  if (i >= count || depth >= kMaxBvhDepth) {
    s.fail("node index or depth out of range at " + std::to_string(i));
    return count;
  }
  s.max_depth = std::max(s.max_depth, depth);
  const FlatNode& n = bvh.nodes[i];
  Aabb expected = empty_aabb();
  std::uint32_t end;
  if (is_leaf(n)) {
    end = i + 1;
    // Leaves cover BVH order left to right, contiguously, sorted by input index inside.
    if (leaf_first(n) != next_primitive) s.fail("leaf ranges not contiguous at node " + std::to_string(i));
    if (leaf_count(n) < 1 || leaf_count(n) > std::uint32_t(leaf_size)) s.fail("bad leaf count at " + std::to_string(i));
    for (std::uint32_t k = leaf_first(n); k < leaf_first(n) + leaf_count(n) && k < bvh.primitive_count(); ++k) {
      grow(expected, bounds[bvh.primitive_order[k]]);
      if (k > leaf_first(n) && bvh.primitive_order[k - 1] >= bvh.primitive_order[k]) s.fail("leaf not sorted");
    }
    next_primitive = leaf_first(n) + leaf_count(n);
  } else {
    const std::uint32_t left = i + 1;
    const std::uint32_t right = check_subtree(bvh, bounds, left, depth + 1, next_primitive, leaf_size, s);
    if (right >= count) {
      s.fail("inner node " + std::to_string(i) + " has no right child");
      return count;
    }
    if (bvh.nodes[left].skip != right) s.fail("left child's skip is not the right child at " + std::to_string(i));
    end = check_subtree(bvh, bounds, right, depth + 1, next_primitive, leaf_size, s);
    for (std::uint32_t child : {left, right}) {
      const FlatNode& c = bvh.nodes[child];
      for (int a = 0; a < 3; ++a)
        if (c.min[a] < n.min[a] || c.max[a] > n.max[a]) s.fail("child box outside parent at " + std::to_string(i));
      grow(expected, c);
    }
  }
  // Boxes are exact unions: of the leaf's primitives, of an inner node's children.
  for (int a = 0; a < 3; ++a)
    if (n.min[a] != expected.min[a] || n.max[a] != expected.max[a]) s.fail("box not the union at " + std::to_string(i));
  if (n.skip != (end == count ? kFlatBvhEnd : end)) s.fail("skip != i + subtree size at " + std::to_string(i));
  return end;
}

Structure check_structure(const FlatBvh& bvh, std::span<const Aabb> bounds, int leaf_size) {
  Structure s;
  if (bvh.primitive_count() != bounds.size()) s.fail("primitive_order has the wrong size");
  std::vector<int> seen(bounds.size(), 0);
  for (std::uint32_t p : bvh.primitive_order)
    if (p >= bounds.size() || seen[p]++) s.fail("primitive_order is not a permutation");
  if (bounds.empty()) {
    if (!bvh.nodes.empty()) s.fail("nodes for no primitives");
    return s;
  }
  if (reinterpret_cast<std::uintptr_t>(bvh.nodes.data()) % 32 != 0) s.fail("nodes not 32-byte aligned");
  if (bvh.nodes[0].skip != kFlatBvhEnd) s.fail("root's skip is not END");
  std::uint32_t next_primitive = 0;
  const std::uint32_t end = check_subtree(bvh, bounds, 0, 0, next_primitive, leaf_size, s);
  if (end != bvh.nodes.size()) s.fail("the root's subtree is not the whole array");
  // With contiguous leaf ranges from 0, this says every primitive is in exactly one leaf.
  if (next_primitive != bounds.size()) s.fail("leaves do not cover every primitive once");
  return s;
}

/// Counts per node and query, without clearing between queries: stamp[i] = the last query
/// that visited node i, so a second visit in one query is seen at once.
struct OnceCheck {
  std::vector<std::uint32_t>* stamp;
  std::uint32_t query;
  std::uint64_t* visits;
  bool* twice;
  void operator()(std::uint32_t i) {
    if ((*stamp)[i] == query) *twice = true;
    (*stamp)[i] = query;
    ++*visits;
  }
};

const char* split_name(BvhSplit split) {
  return split == BvhSplit::Median ? "median" : split == BvhSplit::BinnedSah ? "binned SAH" : "input order";
}

/// Fills the packet with spheres[first ..] (as many as fit); returns the end of that range.
std::size_t load_packet(SpherePacket& packet, const std::vector<Sphere>& spheres, std::size_t first) {
  packet.clear();
  const std::size_t last = std::min(spheres.size(), first + kSpherePacketWidth);
  for (std::size_t q = first; q < last; ++q)
    packet.add(spheres[q].c[0], spheres[q].c[1], spheres[q].c[2], spheres[q].r);
  return last;
}

/// Builds `bvh` over the set's boxes and returns the boxes in BVH order (what the packet walks'
/// leaf tests read).
std::vector<Aabb> build_with_bvh_order_bounds(FlatBvh& bvh, const PrimitiveSet& set, int leaf_size) {
  bvh.build(set.bounds, {.leaf_size = leaf_size});
  std::vector<Aabb> bvh_bounds(set.bounds.size());
  for (std::size_t k = 0; k < bvh_bounds.size(); ++k) bvh_bounds[k] = set.bounds[bvh.primitive_order[k]];
  return bvh_bounds;
}

}  // namespace

TEST_CASE("Sphere and box queries return exactly the brute-force primitive sets", "[bvh]") {
  for (const PrimitiveSet& set : primitive_sets()) {
    const std::vector<Sphere> spheres = random_spheres(set, hail::test::sample_count(10000), 42);
    // Brute force once per set, in input indices; every BVH below must reproduce it.
    std::vector<std::vector<std::uint32_t>> expected(spheres.size()), expected_box(spheres.size());
    for (std::size_t q = 0; q < spheres.size(); ++q) {
      const Sphere& s = spheres[q];
      brute_force_sphere(set.bounds, s.c[0], s.c[1], s.c[2], s.r, [&](std::uint32_t i) { expected[q].push_back(i); });
      const Aabb box{{s.c[0] - s.r, s.c[1] - s.r, s.c[2] - s.r}, {s.c[0] + s.r, s.c[1] + s.r, s.c[2] + s.r}};
      brute_force_aabb(set.bounds, box, [&](std::uint32_t i) { expected_box[q].push_back(i); });
    }
    for (BvhSplit split : {BvhSplit::Median, BvhSplit::BinnedSah, BvhSplit::InputOrder})
      for (int leaf_size : {1, 4, 8}) {
        INFO(set.name << ", " << split_name(split) << ", leaf size " << leaf_size);
        FlatBvh bvh;
        bvh.build(set.bounds, {.split = split, .leaf_size = leaf_size});
        const Structure structure = check_structure(bvh, set.bounds, leaf_size);
        INFO(structure.problem);
        CHECK(structure.ok);
        std::vector<std::uint32_t> stamp(bvh.nodes.size(), 0xFFFFFFFFu);
        std::size_t mismatches = 0, order_mismatches = 0, box_mismatches = 0;
        std::uint64_t most_visits = 0;
        bool twice = false;
        std::vector<std::uint32_t> stackless, stack, found;
        for (std::uint32_t q = 0; q < spheres.size(); ++q) {
          const Sphere& s = spheres[q];
          stackless.clear();
          stack.clear();
          std::uint64_t visits = 0;
          query_sphere(
              bvh, s.c[0], s.c[1], s.c[2], s.r, [&](std::uint32_t k) { stackless.push_back(k); },
              OnceCheck{&stamp, 2 * q, &visits, &twice});
          most_visits = std::max(most_visits, visits);
          visits = 0;
          query_sphere_stack(
              bvh, s.c[0], s.c[1], s.c[2], s.r, [&](std::uint32_t k) { stack.push_back(k); },
              OnceCheck{&stamp, 2 * q + 1, &visits, &twice});
          most_visits = std::max(most_visits, visits);
          // Both walks enter the same leaves in the same (depth-first) order.
          if (stack != stackless) ++order_mismatches;
          // Candidates filtered by the primitive's own box, as a caller would, in input indices.
          found.clear();
          for (std::uint32_t k : stackless) {
            const std::uint32_t p = bvh.primitive_order[k];
            if (sphere_overlaps(set.bounds[p], s.c[0], s.c[1], s.c[2], s.r)) found.push_back(p);
          }
          std::sort(found.begin(), found.end());
          if (found != expected[q]) ++mismatches;

          const Aabb box{{s.c[0] - s.r, s.c[1] - s.r, s.c[2] - s.r}, {s.c[0] + s.r, s.c[1] + s.r, s.c[2] + s.r}};
          auto box_matches = [&](auto walk) {
            found.clear();
            walk([&](std::uint32_t k) {
              const std::uint32_t p = bvh.primitive_order[k];
              if (overlaps(set.bounds[p], box)) found.push_back(p);
            });
            std::sort(found.begin(), found.end());
            return found == expected_box[q];
          };
          box_mismatches += !box_matches([&](auto&& visit) { query_aabb(bvh, box, visit); });
          box_mismatches += !box_matches([&](auto&& visit) { query_aabb_stack(bvh, box, visit); });
        }
        CHECK(mismatches == 0);
        CHECK(order_mismatches == 0);
        CHECK(box_mismatches == 0);
        CHECK_FALSE(twice);  // no node visited twice in one query
        CHECK(most_visits <= bvh.nodes.size());
      }
  }
}

TEST_CASE("The ray query finds the brute-force nearest triangle", "[bvh]") {
  for (const PrimitiveSet& set : primitive_sets()) {
    if (set.triangles.empty()) continue;
    const Aabb all = set_bounds(set);
    std::mt19937 rng(123);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    struct Ray {
      float o[3], d[3], t_max;
    };
    std::vector<Ray> rays(static_cast<std::size_t>(hail::test::sample_count(3000)));
    for (std::size_t q = 0; q < rays.size(); ++q) {
      Ray& ray = rays[q];
      const float lift = 1.0f + 0.5f * (all.max[1] - all.min[1]);
      for (int a = 0; a < 3; ++a) ray.o[a] = all.min[a] - 1.0f + (all.max[a] - all.min[a] + 2.0f) * u(rng);
      ray.o[1] += lift;
      if (q % 4 == 0) {  // straight down, half of them on grid lines: zero direction components, edge hits
        ray.d[0] = 0.0f, ray.d[1] = -1.0f, ray.d[2] = 0.0f;
        if (q % 8 == 0) ray.o[0] = std::round(ray.o[0]);
      } else {  // random direction, mostly downwards
        float len = 0.0f;
        for (int a = 0; a < 3; ++a) {
          ray.d[a] = 2.0f * u(rng) - 1.0f;
          len += ray.d[a] * ray.d[a];
        }
        if (q % 4 != 3) ray.d[1] = -std::fabs(ray.d[1]);
        for (float& d : ray.d) d /= std::sqrt(len);
      }
      ray.t_max = q % 3 == 0 ? std::numeric_limits<float>::infinity() : lift * (0.5f + 3.0f * u(rng));
    }
    auto intersect = [&](const Ray& ray, std::uint32_t p) {
      const Triangle& t = set.triangles[p];
      return ray_triangle(ray.o, ray.d, t.v[0], t.v[1], t.v[2]);
    };
    for (BvhSplit split : {BvhSplit::Median, BvhSplit::BinnedSah, BvhSplit::InputOrder})
      for (int leaf_size : {1, 4, 8}) {
        INFO(set.name << ", " << split_name(split) << ", leaf size " << leaf_size);
        FlatBvh bvh;
        bvh.build(set.bounds, {.split = split, .leaf_size = leaf_size});
        std::size_t mismatches = 0, hits = 0;
        for (const Ray& ray : rays) {
          const RayHit want = brute_force_ray(static_cast<std::uint32_t>(set.triangles.size()), ray.t_max,
                                              [&](std::uint32_t p) { return intersect(ray, p); });
          NodeVisitCount visits;
          const RayHit got = query_ray(
              bvh, ray.o, ray.d, ray.t_max, [&](std::uint32_t k) { return intersect(ray, bvh.primitive_order[k]); },
              visits);
          hits += want.primitive != kNoPrimitive;
          // Same distance; a different primitive only where both are hit at it (a shared edge).
          const bool same =
              got.t == want.t && (got.primitive == kNoPrimitive) == (want.primitive == kNoPrimitive) &&
              (got.primitive == kNoPrimitive || intersect(ray, bvh.primitive_order[got.primitive]) == want.t);
          if (!same || visits.visited > bvh.nodes.size()) ++mismatches;
        }
        CHECK(mismatches == 0);
        CHECK(hits > 0);  // the rays do meet the surface
      }
  }
}

TEST_CASE("Binned SAH on degenerate boxes stays within the walk's stack depth", "[bvh]") {
  // Points on a line have zero area, so every SAH cost is 0 and the first plane wins: each
  // split peels one bin (1/16) off the range, which without the median fallback would make the
  // tree log(2000) / log(16 / 15) = 118 levels deep and overflow the 64-entry walk stack.
  constexpr int kBoxes = 2000;
  std::vector<Aabb> bounds;
  for (int k = 0; k < kBoxes; ++k) {
    const float x = static_cast<float>(k);
    bounds.push_back(Aabb{{x, 0.0f, 0.0f}, {x, 0.0f, 0.0f}});
  }
  FlatBvh bvh;
  bvh.build(bounds, {.split = BvhSplit::BinnedSah, .leaf_size = 1});
  const Structure structure = check_structure(bvh, bounds, 1);
  INFO(structure.problem);
  CHECK(structure.ok);
  CHECK(structure.max_depth > 35);  // SAH went deep enough for the fallback to take over
  CHECK(structure.max_depth < kMaxBvhDepth);
  std::size_t mismatches = 0;
  for (int k = 0; k < kBoxes; k += 7) {
    std::vector<std::uint32_t> a, b, want;
    const float y = 0.0f;
    query_sphere(bvh, float(k), y, 0.0f, 0.0f, [&](std::uint32_t p) { a.push_back(bvh.primitive_order[p]); });
    query_sphere_stack(bvh, float(k), y, 0.0f, 0.0f, [&](std::uint32_t p) { b.push_back(bvh.primitive_order[p]); });
    brute_force_sphere(bounds, float(k), y, 0.0f, 0.0f, [&](std::uint32_t p) { want.push_back(p); });
    auto filtered = [&](std::vector<std::uint32_t> v) {
      std::erase_if(v, [&](std::uint32_t p) { return !sphere_overlaps(bounds[p], float(k), y, 0.0f, 0.0f); });
      std::sort(v.begin(), v.end());
      return v;
    };
    mismatches += filtered(a) != want || a != b;
  }
  CHECK(mismatches == 0);
}

TEST_CASE("BVH builds are deterministic and reuse their storage", "[bvh]") {
  const PrimitiveSet set = random_boxes(5000, 99);
  for (BvhSplit split : {BvhSplit::Median, BvhSplit::BinnedSah, BvhSplit::InputOrder}) {
    FlatBvh a, b;
    a.build(set.bounds, {.split = split});
    b.build(set.bounds, {.split = split});
    REQUIRE(a.nodes.size() == b.nodes.size());
    CHECK(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(FlatNode)) == 0);
    CHECK(a.primitive_order == b.primitive_order);
    const FlatNode* storage = a.nodes.data();
    a.build(set.bounds, {.split = split});  // a rebuild of the same size does not reallocate
    CHECK(a.nodes.data() == storage);
    CHECK(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(FlatNode)) == 0);
  }
  // Median split reserves exactly: balanced halves, depth ceil(log2(n / leaf)).
  FlatBvh median;
  median.build(set.bounds, {});
  CHECK(median.nodes.size() == median.nodes.capacity());
  CHECK(check_structure(median, set.bounds, 4).max_depth <= 11);  // ceil(log2(5000 / 4)) = 11
  // Input order: nothing moved, the median split's shape (so its exact reservation).
  FlatBvh in_order;
  in_order.build(set.bounds, {.split = BvhSplit::InputOrder});
  std::vector<std::uint32_t> identity(set.bounds.size());
  std::iota(identity.begin(), identity.end(), 0u);
  CHECK(in_order.primitive_order == identity);
  CHECK(in_order.nodes.size() == median.nodes.size());
  CHECK(in_order.nodes.size() == in_order.nodes.capacity());
  CHECK(check_structure(in_order, set.bounds, 4).max_depth <= 11);
}

TEST_CASE("Empty and one-primitive BVHs", "[bvh]") {
  FlatBvh empty;
  empty.build({}, {});
  CHECK(empty.nodes.empty());
  int visits = 0;
  query_sphere(empty, 0, 0, 0, 1e9f, [&](std::uint32_t) { ++visits; });
  query_sphere_stack(empty, 0, 0, 0, 1e9f, [&](std::uint32_t) { ++visits; });
  const float o[3] = {0, 0, 0}, d[3] = {1, 0, 0};
  CHECK(query_ray(empty, o, d, 1e9f, [&](std::uint32_t) { return 0.0f; }).primitive == kNoPrimitive);
  CHECK(visits == 0);

  const std::vector<Aabb> one{Aabb{{1, 1, 1}, {2, 2, 2}}};
  const FlatBvh single = build_flat_bvh(one, {.split = BvhSplit::BinnedSah, .leaf_size = 1});
  REQUIRE(single.nodes.size() == 1);
  CHECK(single.nodes[0].skip == kFlatBvhEnd);
  CHECK(leaf_first(single.nodes[0]) == 0);
  CHECK(leaf_count(single.nodes[0]) == 1);
  query_sphere(single, 0, 0, 0, 1.8f, [&](std::uint32_t) { ++visits; });  // sqrt(3) = 1.73 away
  query_sphere(single, 0, 0, 0, 1.7f, [&](std::uint32_t) { ++visits; });
  CHECK(visits == 1);
}

TEST_CASE("BVH arguments are checked and a failed build leaves the BVH unchanged", "[bvh]") {
  const std::vector<Aabb> bounds{Aabb{{0, 0, 0}, {1, 1, 1}}, Aabb{{2, 0, 0}, {3, 1, 1}}};
  FlatBvh bvh;
  bvh.build(bounds, {});
  const std::vector<FlatNode> before = bvh.nodes;
  for (int leaf_size : {0, -1, 9, 1000}) CHECK_THROWS_AS(bvh.build(bounds, {.leaf_size = leaf_size}), InvalidArgument);
  CHECK_THROWS_AS(build_flat_bvh(bounds, 9u), InvalidArgument);
  CHECK_THROWS_AS(build_flat_bvh(bounds, 0xFFFFFFFFu), InvalidArgument);
  CHECK_THROWS_AS(bvh.build(bounds, {.split = static_cast<BvhSplit>(7)}), InvalidArgument);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const Aabb& bad : {Aabb{{nan, 0, 0}, {1, 1, 1}}, Aabb{{0, 0, 0}, {1, inf, 1}}, Aabb{{0, 2, 0}, {1, 1, 1}}}) {
    std::vector<Aabb> with_bad = bounds;
    with_bad.push_back(bad);
    CHECK_THROWS_AS(bvh.build(with_bad, {}), InvalidArgument);
  }
  REQUIRE(bvh.nodes.size() == before.size());
  CHECK(std::memcmp(bvh.nodes.data(), before.data(), before.size() * sizeof(FlatNode)) == 0);
  CHECK(bvh.primitive_count() == 2);
}

TEST_CASE("Möller-Trumbore: hits inside and on edges, misses outside, parallel and behind", "[bvh]") {
  const float a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 0, 1};
  const float down[3] = {0, -1, 0}, up[3] = {0, 1, 0}, along[3] = {1, 0, 0};
  const float above[3] = {0.25f, 2, 0.25f}, edge[3] = {0.5f, 2, 0.5f}, outside[3] = {0.75f, 2, 0.75f};
  CHECK(ray_triangle(above, down, a, b, c) == 2.0f);
  CHECK(ray_triangle(edge, down, a, b, c) == 2.0f);  // on the hypotenuse: inclusive
  CHECK(ray_triangle(outside, down, a, b, c) == kRayMiss);
  CHECK(ray_triangle(above, up, a, b, c) == kRayMiss);  // behind the origin
  const float in_plane[3] = {-1, 0, 0.25f};
  CHECK(ray_triangle(in_plane, along, a, b, c) == kRayMiss);  // parallel
  const float scaled[3] = {0, -4, 0};
  CHECK(ray_triangle(above, scaled, a, b, c) == 0.5f);  // t in units of |d|
}

TEST_CASE("Packet walks give each lane exactly its single-sphere walk, in order", "[bvh]") {
  for (const PrimitiveSet& set : primitive_sets()) {
    // 1001 spheres: the last packet is partial, so inert lanes are exercised too.
    const std::vector<Sphere> spheres = random_spheres(set, 1001, 99);
    for (int leaf_size : {1, 4, 8}) {
      INFO(set.name << ", leaf size " << leaf_size);
      FlatBvh bvh;
      const std::vector<Aabb> bvh_bounds = build_with_bvh_order_bounds(bvh, set, leaf_size);
      std::vector<std::uint32_t> stamp(bvh.nodes.size(), 0xFFFFFFFFu);
      std::uint64_t visits = 0;
      bool twice = false;
      std::size_t candidate_mismatches = 0, exact_mismatches = 0, lanes_checked = 0;
      SpherePacket packet;
      std::vector<std::uint32_t> per_lane[kSpherePacketWidth], per_lane_exact[kSpherePacketWidth];
      std::uint32_t packet_index = 0;
      for (std::size_t first = 0; first < spheres.size(); first += kSpherePacketWidth, ++packet_index) {
        const std::size_t last = load_packet(packet, spheres, first);
        for (auto& v : per_lane) v.clear();
        for (auto& v : per_lane_exact) v.clear();
        query_sphere_packet(
            bvh, packet, [&](std::uint32_t lane, std::uint32_t k) { per_lane[lane].push_back(k); },
            OnceCheck{&stamp, packet_index, &visits, &twice});
        query_sphere_packet_exact(bvh, bvh_bounds, packet,
                                  [&](std::uint32_t lane, std::uint32_t k) { per_lane_exact[lane].push_back(k); });
        for (std::size_t q = first; q < kSpherePacketWidth + first; ++q) {
          const std::uint32_t lane = static_cast<std::uint32_t>(q - first);
          std::vector<std::uint32_t> single, single_exact;
          if (q < last) {
            const Sphere& s = spheres[q];
            query_sphere(bvh, s.c[0], s.c[1], s.c[2], s.r, [&](std::uint32_t k) {
              single.push_back(k);
              if (sphere_overlaps(bvh_bounds[k], s.c[0], s.c[1], s.c[2], s.r)) single_exact.push_back(k);
            });
          }
          // Inert lanes (q >= last) must see nothing.
          candidate_mismatches += per_lane[lane] != single;
          exact_mismatches += per_lane_exact[lane] != single_exact;
          ++lanes_checked;
        }
      }
      CHECK(lanes_checked >= spheres.size());
      CHECK(candidate_mismatches == 0);
      CHECK(exact_mismatches == 0);
      CHECK_FALSE(twice);  // each node tested at most once per packet
    }
  }
}

TEST_CASE("The packet walk in stretches gives query_sphere_packet_exact's pairs in its order", "[bvh]") {
  // PacketWalkExact stops before a leaf that might not fit the buffer and resumes there; with
  // buffers from one leaf's worst case up to twice that, it stops often, mid-walk.
  const std::uint32_t leaf_slots = kMaxLeafSize * kSpherePacketWidth;
  std::size_t stretches = 0, packets = 0;  // over all sets: small sets' walks fit one buffer
  for (const PrimitiveSet& set : primitive_sets()) {
    const std::vector<Sphere> spheres = random_spheres(set, 515, 7);
    for (int leaf_size : {1, 4, 8}) {
      INFO(set.name << ", leaf size " << leaf_size);
      FlatBvh bvh;
      const std::vector<Aabb> bvh_bounds = build_with_bvh_order_bounds(bvh, set, leaf_size);
      std::size_t mismatches = 0, pairs = 0;
      for (const std::uint32_t capacity : {leaf_slots, leaf_slots + 5, 2 * leaf_slots}) {
        SpherePacket packet;
        for (std::size_t first = 0; first < spheres.size(); first += kSpherePacketWidth, ++packets) {
          load_packet(packet, spheres, first);
          std::vector<std::pair<std::uint32_t, std::uint32_t>> whole, stretched, buffer;
          query_sphere_packet_exact(bvh, bvh_bounds, packet,
                                    [&](std::uint32_t lane, std::uint32_t k) { whole.emplace_back(lane, k); });
          PacketWalkExact walk(bvh, bvh_bounds, packet);
          while (!walk.done()) {
            walk.run([&](std::uint32_t lane, std::uint32_t k) { buffer.emplace_back(lane, k); },
                     [&] { return capacity - static_cast<std::uint32_t>(buffer.size()); });
            REQUIRE(buffer.size() <= capacity);
            stretched.insert(stretched.end(), buffer.begin(), buffer.end());
            buffer.clear();
            ++stretches;
          }
          pairs += whole.size();
          mismatches += stretched != whole;
        }
      }
      CHECK(pairs > 0);
      CHECK(mismatches == 0);
    }
  }
  CHECK(stretches > packets);  // some walks were cut and resumed
}

TEST_CASE("Morton codes interleave x, y, z on cubic cells and clamp what lies outside", "[bvh]") {
  CHECK(spread_bits_3d(0b1011) == 0b001000001001u);
  CHECK(spread_bits_3d(0x3FF) == 0x09249249u);
  const Aabb box{{0, 0, 0}, {1023, 10, 1023}};  // flat: y shares x's and z's 1-unit cells
  CHECK(morton_code_3d(box, 1, 0, 0) == 0b100u);
  CHECK(morton_code_3d(box, 0, 1, 0) == 0b010u);
  CHECK(morton_code_3d(box, 0, 0, 1) == 0b001u);
  CHECK(morton_code_3d(box, 1023, 10, 1023) ==
        ((spread_bits_3d(1023) << 2) | (spread_bits_3d(10) << 1) | spread_bits_3d(1023)));
  CHECK(morton_code_3d(box, -5, -5, -5) == 0u);
  CHECK(morton_code_3d(box, std::nanf(""), 0, 0) == 0u);
  CHECK(morton_code_3d(box, 1e30f, 0, 0) == morton_code_3d(box, 1023, 0, 0));
  // The first split of Z-order is the top x bit: every point of the low half sorts first.
  CHECK(morton_code_3d(box, 511, 10, 1023) < morton_code_3d(box, 512, 0, 0));
}
