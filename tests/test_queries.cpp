// World queries (include/hail/world.h, "World queries"; kernel/world/world_queries.cpp): each
// query against a brute-force loop over every sphere, triangle and plane, on random scenes with
// terrain and planes, with and without filters; the batch against single casts and across thread
// counts; the lazily built sphere BVH rebuilt after changes; bad input refused.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "kernel/geometry/ray_sphere.h"
#include "kernel/geometry/swept_sphere.h"
#include "kernel/world/ray_batch_leaf_test.h"
#include "simd_paths.h"

using namespace hail;

namespace {

struct Scene {
  std::unique_ptr<World> world;
  std::shared_ptr<const Terrain> terrain;
};

Scene make_scene(int spheres, unsigned seed, int threads = 1) {
  WorldSettings settings;
  settings.threads = threads;
  Scene s{std::make_unique<World>(settings), nullptr};
  s.terrain = std::make_shared<const Terrain>(Heightmap::from_function(
      33, 33, {.cell_x = 2.0f, .cell_z = 2.0f},
      [](float x, float z) { return 2.0f * std::sin(0.3f * x) * std::cos(0.2f * z) + 0.05f * x; }));
  s.world->set_terrain(s.terrain);
  s.world->add_plane({.normal = {1, 0, 0}, .offset = -1.0f});    // wall: solid x < -1
  s.world->add_plane({.normal = {0, -1, 0}, .offset = -40.0f});  // ceiling: solid y > 40
  s.world->add_plane({.normal = {0, 1, 0}, .offset = -6.0f});    // floor under the terrain
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xz(0.0f, 64.0f), y(4.0f, 30.0f), r(0.1f, 1.0f);
  for (int k = 0; k < spheres; ++k) {
    SphereDesc d;
    d.position = {xz(rng), y(rng), xz(rng)};
    d.radius = r(rng);
    d.filter.category = 1u << (rng() % 4);
    s.world->add_sphere(d);
  }
  return s;
}

std::vector<Ray> random_rays(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xz(-4.0f, 68.0f), y(-2.0f, 36.0f), u(-1.0f, 1.0f), len(2.0f, 80.0f);
  std::vector<Ray> rays(count);
  for (int k = 0; k < count; ++k) {
    rays[k].origin = {xz(rng), y(rng), xz(rng)};
    rays[k].direction = {u(rng), u(rng), u(rng)};
    if (k % 3 == 0) rays[k].max_distance = len(rng);  // the rest infinite
  }
  return rays;
}

// The brute force: every sphere, triangle and plane, the same per-primitive formulas as the
// library (its unit direction is the direction divided by its float length).
struct UnitRay {
  float o[3], d[3], max;
};
UnitRay unit(const Ray& ray) {
  const Vec3& v = ray.direction;
  const float length = std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z());
  return {{ray.origin.x(), ray.origin.y(), ray.origin.z()},
          {v.x() / length, v.y() / length, v.z() / length},
          ray.max_distance};
}

bool passes(const World& w, std::size_t slot, const QueryFilter& f) {
  return (w.soa().collision_category[slot] & f.mask) != 0 && !(w.id_at(slot) == f.ignore);
}

float plane_distance(const UnitRay& r, const Plane& p, float grow) {
  const float gap = p.nx * r.o[0] + p.ny * r.o[1] + p.nz * r.o[2] - p.offset - grow;
  if (gap <= 0.0f) return 0.0f;
  const float closing = -(p.nx * r.d[0] + p.ny * r.d[1] + p.nz * r.d[2]);
  if (!(closing > 0.0f)) return -1.0f;
  return gap / closing;
}

QueryHit hit_of(QueryHitKind kind, SphereId id, std::uint32_t index, float distance) {
  QueryHit h;
  h.kind = kind, h.sphere = id, h.index = index, h.distance = distance;
  return h;
}

/// Every primitive's hit of a ball of radius `grow` along the ray (grow 0: the ray), unsorted.
std::vector<QueryHit> brute_hits(const World& w, const Ray& ray, const QueryFilter& f, float grow) {
  const UnitRay r = unit(ray);
  std::vector<QueryHit> hits;
  const SphereSoA& s = w.soa();
  for (std::size_t i = 0; i < w.sphere_count(); ++i) {
    if (!passes(w, i, f)) continue;
    const float t = ray_sphere(r.o, r.d, s.px[i], s.py[i], s.pz[i], s.radius[i] + grow);
    if (t >= 0.0f && t < r.max) hits.push_back(hit_of(QueryHitKind::Sphere, w.id_at(i), 0, t));
  }
  if (f.terrain && w.terrain()) {
    const Terrain& terrain = *w.terrain();
    for (std::uint32_t k = 0; k < terrain.triangle_count(); ++k) {
      const TerrainTriangle tri = terrain.triangle(k);
      float t = -1.0f;
      if (grow == 0.0f) {
        const float a[3] = {tri.a.x(), tri.a.y(), tri.a.z()}, b[3] = {tri.b.x(), tri.b.y(), tri.b.z()};
        const float c[3] = {tri.c.x(), tri.c.y(), tri.c.z()};
        t = ray_triangle(r.o, r.d, a, b, c);
      } else {
        const double o[3] = {r.o[0], r.o[1], r.o[2]}, v[3] = {r.d[0], r.d[1], r.d[2]};
        const double a[3] = {tri.a.x(), tri.a.y(), tri.a.z()}, b[3] = {tri.b.x(), tri.b.y(), tri.b.z()};
        const double c[3] = {tri.c.x(), tri.c.y(), tri.c.z()};
        const double n[3] = {tri.normal.x(), tri.normal.y(), tri.normal.z()};
        SweptHit h;
        if (swept_sphere_triangle(o, v, grow, a, b, c, n, 0, r.max, h)) t = static_cast<float>(h.t);
      }
      if (t >= 0.0f && t < r.max) hits.push_back(hit_of(QueryHitKind::Terrain, {}, k, t));
    }
  }
  if (f.planes)
    for (std::uint32_t k = 0; k < w.planes().size(); ++k) {
      const float t = plane_distance(r, w.planes()[k], grow);
      if (t >= 0.0f && t < r.max) hits.push_back(hit_of(QueryHitKind::Plane, {}, k, t));
    }
  std::sort(hits.begin(), hits.end(), hit_before);
  return hits;
}

std::optional<QueryHit> brute_closest(const World& w, const Ray& ray, const QueryFilter& f, float grow = 0.0f) {
  const auto hits = brute_hits(w, ray, f, grow);
  if (hits.empty()) return std::nullopt;
  return hits.front();
}

/// Same thing hit at the same distance, bit for bit.
bool same_hit(const QueryHit& a, const QueryHit& b) {
  return a.kind == b.kind && a.sphere == b.sphere && a.index == b.index &&
         std::memcmp(&a.distance, &b.distance, sizeof(float)) == 0;
}
bool same_hit(const std::optional<QueryHit>& a, const std::optional<QueryHit>& b) {
  return a.has_value() == b.has_value() && (!a || same_hit(*a, *b));
}
bool identical(const std::optional<QueryHit>& a, const std::optional<QueryHit>& b) {
  if (!same_hit(a, b)) return false;
  return !a || (std::memcmp(a->point.data(), b->point.data(), sizeof(float) * 3) == 0 &&
                std::memcmp(a->normal.data(), b->normal.data(), sizeof(float) * 3) == 0);
}

std::vector<SphereId> brute_overlap_sphere(const World& w, const Vec3& c, float radius, const QueryFilter& f) {
  std::vector<SphereId> out;
  const SphereSoA& s = w.soa();
  for (std::size_t i = 0; i < w.sphere_count(); ++i) {
    const float dx = s.px[i] - c.x(), dy = s.py[i] - c.y(), dz = s.pz[i] - c.z(), reach = s.radius[i] + radius;
    if (passes(w, i, f) && dx * dx + dy * dy + dz * dz <= reach * reach) out.push_back(w.id_at(i));
  }
  std::sort(out.begin(), out.end(), [](SphereId a, SphereId b) { return a.index < b.index; });
  return out;
}

std::vector<SphereId> brute_overlap_box(const World& w, const Vec3& lo, const Vec3& hi, const QueryFilter& f) {
  std::vector<SphereId> out;
  const SphereSoA& s = w.soa();
  for (std::size_t i = 0; i < w.sphere_count(); ++i) {
    const float c[3] = {s.px[i], s.py[i], s.pz[i]};
    float d2 = 0.0f;
    for (int a = 0; a < 3; ++a) {
      const float out_by = c[a] < lo[a] ? lo[a] - c[a] : (c[a] > hi[a] ? c[a] - hi[a] : 0.0f);
      d2 += out_by * out_by;
    }
    if (passes(w, i, f) && d2 <= s.radius[i] * s.radius[i]) out.push_back(w.id_at(i));
  }
  std::sort(out.begin(), out.end(), [](SphereId a, SphereId b) { return a.index < b.index; });
  return out;
}

std::vector<QueryFilter> filters(const World& w) {
  QueryFilter teams;
  teams.mask = 0x5u;
  QueryFilter no_static;
  no_static.terrain = false, no_static.planes = false, no_static.mask = 0x2u;
  QueryFilter ignoring;
  ignoring.ignore = w.id_at(w.sphere_count() / 2);
  return {QueryFilter{}, teams, no_static, ignoring};
}

}  // namespace

TEST_CASE("raycast and raycast_all give the brute-force hits", "[queries]") {
  const Scene s = make_scene(3000, 7);
  const World& w = *s.world;
  const auto rays = random_rays(400, 11);
  int kinds_seen[3] = {0, 0, 0}, several = 0;
  for (const QueryFilter& f : filters(w))
    for (const Ray& ray : rays) {
      const auto expected = brute_hits(w, ray, f, 0.0f);
      const auto closest = w.raycast(ray, f);
      REQUIRE(same_hit(closest, expected.empty() ? std::nullopt : std::optional<QueryHit>(expected.front())));
      const auto all = w.raycast_all(ray, f);
      REQUIRE(all.size() == expected.size());
      for (std::size_t k = 0; k < all.size(); ++k) REQUIRE(same_hit(all[k], expected[k]));
      if (closest) {
        ++kinds_seen[static_cast<int>(closest->kind)];
        CHECK(std::abs(closest->normal.norm() - 1.0f) < 1e-4f);
        if (!f.terrain) CHECK(closest->kind == QueryHitKind::Sphere);
        if (closest->kind == QueryHitKind::Sphere) {
          CHECK((w.collision_filter(closest->sphere).category & f.mask) != 0);
          CHECK(!(closest->sphere == f.ignore));
        }
      }
      several += all.size() > 2;
    }
  // The scene exercises every kind of hit and rays through several things.
  CHECK(kinds_seen[0] > 100);
  CHECK(kinds_seen[1] > 20);
  CHECK(kinds_seen[2] > 20);
  CHECK(several > 100);
}

TEST_CASE("sphere_cast gives the brute-force first hit", "[queries]") {
  const Scene s = make_scene(3000, 8);
  const World& w = *s.world;
  const auto rays = random_rays(300, 12);
  int terrain_hits = 0;
  for (const QueryFilter& f : filters(w))
    for (std::size_t k = 0; k < rays.size(); ++k) {
      const float radius = 0.05f + 0.5f * static_cast<float>(k % 5);
      const auto hit = w.sphere_cast(rays[k], radius, f);
      REQUIRE(same_hit(hit, brute_closest(w, rays[k], f, radius)));
      terrain_hits += hit && hit->kind == QueryHitKind::Terrain;
    }
  CHECK(terrain_hits > 10);
  // Radius 0 is a ray: bit for bit on spheres and planes (the same float formulas); the terrain's
  // swept test runs in double, so there only to rounding.
  const QueryFilter no_terrain{.terrain = false};
  for (std::size_t k = 0; k < 100; ++k) {
    CHECK(same_hit(w.sphere_cast(rays[k], 0.0f, no_terrain), w.raycast(rays[k], no_terrain)));
    const auto cast = w.sphere_cast(rays[k], 0.0f), ray = w.raycast(rays[k]);
    // A sweep meets a triangle only from the side its normal faces (kernel/geometry/swept_sphere.h);
    // a ray sees both faces: a ray from under the terrain is no comparison.
    if (ray && ray->kind == QueryHitKind::Terrain && ray->normal.y() < 0.0f) continue;
    REQUIRE(cast.has_value() == ray.has_value());
    if (cast) CHECK(std::abs(cast->distance - ray->distance) <= 1e-4f * (1.0f + ray->distance));
  }
}

TEST_CASE("overlap_sphere and overlap_box give the brute-force sets by handle", "[queries]") {
  const Scene s = make_scene(3000, 9);
  const World& w = *s.world;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> xz(-4.0f, 68.0f), y(0.0f, 34.0f), size(0.0f, 8.0f);
  std::size_t found = 0;
  for (const QueryFilter& f : filters(w))
    for (int k = 0; k < 200; ++k) {
      const Vec3 c(xz(rng), y(rng), xz(rng));
      const float radius = size(rng);
      const auto in_sphere = w.overlap_sphere(c, radius, f);
      REQUIRE(in_sphere == brute_overlap_sphere(w, c, radius, f));
      const Vec3 half(size(rng), size(rng), size(rng));
      const auto in_box = w.overlap_box(c - half, c + half, f);
      REQUIRE(in_box == brute_overlap_box(w, c - half, c + half, f));
      found += in_sphere.size() + in_box.size();
    }
  CHECK(found > 1000);
}

TEST_CASE("raycast_batch equals raycast ray by ray, bitwise on 1 and 2 threads", "[queries][threads]") {
  const Scene one = make_scene(3000, 10, 1);
  const Scene two = make_scene(3000, 10, 2);
  const auto rays = random_rays(5000, 13);
  QueryFilter f;
  f.mask = 0x7u;
  std::vector<std::optional<QueryHit>> hits1(rays.size()), hits2(rays.size());
  one.world->raycast_batch(rays, hits1, f);
  two.world->raycast_batch(rays, hits2, f);
  std::size_t hit_count = 0;
  for (std::size_t k = 0; k < rays.size(); ++k) {
    REQUIRE(identical(hits1[k], one.world->raycast(rays[k], f)));
    REQUIRE(identical(hits1[k], hits2[k]));
    hit_count += hits1[k].has_value();
  }
  CHECK(hit_count > rays.size() / 2);
  std::vector<std::optional<QueryHit>> short_of(rays.size() - 1);
  CHECK_THROWS_AS(one.world->raycast_batch(rays, short_of), InvalidArgument);
}

namespace {

/// Sets raycast_batch's leaf test for its lifetime, then restores the SIMD one.
struct ScopedLeafTest {
  explicit ScopedLeafTest(RayBatchLeafTest test) { set_ray_batch_leaf_test(test); }
  ~ScopedLeafTest() { set_ray_batch_leaf_test(RayBatchLeafTest::Simd); }
  ScopedLeafTest(const ScopedLeafTest&) = delete;
  ScopedLeafTest& operator=(const ScopedLeafTest&) = delete;
};

}  // namespace

TEST_CASE("raycast_batch with SIMD leaves equals raycast and the brute force on every SIMD path, ties included",
          "[queries][simd]") {
  Scene s = make_scene(2001, 21, 2);  // 2001: the last leaf is short (the lanes' scalar tail)
  World& w = *s.world;
  // Ties: nine equal spheres (three leaves' worth) on one spot and two pairs elsewhere; a ray
  // into them meets all at one distance, and the lowest handle index must win.
  std::vector<Vec3> tie_spots = {{20.5f, 18.0f, 20.5f}, {40.25f, 10.0f, 12.0f}, {8.0f, 25.0f, 50.0f}};
  std::vector<SphereId> tied;
  for (std::size_t spot = 0; spot < tie_spots.size(); ++spot)
    for (int k = 0; k < (spot == 0 ? 9 : 2); ++k) {
      SphereDesc d;
      d.position = tie_spots[spot];
      d.radius = 0.75f;
      d.filter.category = 1u << (k % 2);
      tied.push_back(w.add_sphere(d));
    }
  auto rays = random_rays(3000, 22);
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const Vec3& spot : tie_spots)
    for (int k = 0; k < 40; ++k) {
      const Vec3 from = spot + Vec3(u(rng), u(rng), u(rng)) * 6.0f;
      rays.push_back({from, spot - from, std::numeric_limits<float>::infinity()});
      rays.push_back({spot + Vec3(u(rng), u(rng), u(rng)) * 0.5f, {u(rng), u(rng), 1.0f}});  // from inside
    }
  for (std::size_t k = 0; k < 200; ++k) {  // from inside the random spheres, and rays that miss
    const Vec3 centre = w.position(w.id_at(k));
    rays.push_back({centre, {u(rng), u(rng), u(rng) + 2.0f}});
    rays.push_back({{-30.0f, 50.0f + static_cast<float>(k), -30.0f}, {-1.0f, u(rng), -1.0f}});
  }
  std::vector<QueryFilter> fs = filters(w);
  QueryFilter spheres_only{.terrain = false, .planes = false};
  QueryFilter ignore_tie_winner = spheres_only;
  ignore_tie_winner.ignore = tied[0];
  QueryFilter odd_category = spheres_only;  // drops the winning half of each tie
  odd_category.mask = 0x2u;
  fs.insert(fs.end(), {spheres_only, ignore_tie_winner, odd_category});

  std::vector<std::optional<QueryHit>> scalar(rays.size()), simd(rays.size());
  std::size_t misses = 0, inside = 0, ties = 0, brute_checked = 0;
  for (const QueryFilter& f : fs) {
    {
      ScopedLeafTest scalar_leaves(RayBatchLeafTest::Scalar);
      w.raycast_batch(rays, scalar, f);
    }
    for (std::size_t k = 0; k < rays.size(); ++k) {
      REQUIRE(identical(scalar[k], w.raycast(rays[k], f)));
      misses += !scalar[k], inside += scalar[k] && scalar[k]->distance == 0.0f;
      if (scalar[k] && std::find(tied.begin(), tied.end(), scalar[k]->sphere) != tied.end()) ++ties;
      // The brute force on every seventh ray (it tests every primitive) and on the tie rays.
      if (k % 7 == 0 || k >= 3000) {
        REQUIRE(same_hit(scalar[k], brute_closest(w, rays[k], f)));
        ++brute_checked;
      }
    }
    for (SimdPath path : testing::supported_paths()) {
      testing::ScopedSimdPath on(path);
      INFO("SIMD path " << simd_path_name(path));
      w.raycast_batch(rays, simd, f);
      for (std::size_t k = 0; k < rays.size(); ++k) REQUIRE(identical(simd[k], scalar[k]));
    }
  }
  CHECK(misses > 500);
  CHECK(inside > 300);
  CHECK(ties > 200);
  CHECK(brute_checked > 5000);
}

TEST_CASE("the query BVH is built once per change and follows moves, radii, filters and removals", "[queries]") {
  World w;
  const SphereId a = w.add_sphere({.position = {0, 0, 0}, .radius = 1.0f});
  const SphereId b = w.add_sphere({.position = {0, 0, 10}, .radius = 1.0f});
  const Ray along_z{{0, 0, -5}, {0, 0, 1}};
  CHECK(w.query_cache_builds() == 0);  // nothing built before a query
  REQUIRE(w.raycast(along_z));
  CHECK(w.raycast(along_z)->sphere == a);
  CHECK(w.raycast(along_z)->distance == 4.0f);
  CHECK(w.query_cache_builds() == 1);  // reused by the later queries
  w.set_position(a, {5, 0, 0});        // out of the way: b is hit now
  CHECK(w.raycast(along_z)->sphere == b);
  CHECK(w.query_cache_builds() == 2);
  w.set_radius(a, 6.0f);  // reaches the ray again
  CHECK(w.raycast(along_z)->sphere == a);
  w.set_collision_filter(a, {.category = 0x2u, .mask = kAllCategories});
  CHECK(w.raycast(along_z, {.mask = 0x1u})->sphere == b);
  CHECK(w.overlap_sphere({5, 0, 0}, 0.5f) == std::vector<SphereId>{a});
  w.remove_sphere(a);
  CHECK(w.overlap_sphere({5, 0, 0}, 0.5f).empty());
  const SphereId c = w.add_sphere({.position = {0, 0, 3}, .radius = 0.5f});
  CHECK(w.raycast(along_z)->sphere == c);
  // Gravity moves everything: hits follow. Two steps: under the uniform integrator one step
  // drops c only g dt^2 / 2 (1.4 mm), which left the hit's distance 7.5 to float rounding.
  w.step(1.0f / 60.0f);
  w.step(1.0f / 60.0f);
  const auto after_step = w.raycast(along_z);
  REQUIRE(after_step);
  CHECK(after_step->distance > 7.5f);  // c's surface is no longer at distance 7.5
  CHECK(w.query_cache_builds() == 7);
  w.shift_origin({0, 0, 1});
  CHECK(w.raycast(along_z)->distance == after_step->distance - 1.0f);
}

TEST_CASE("queries: hits from inside, planes, filters for static geometry", "[queries]") {
  World w;
  w.add_plane({.normal = {0, 1, 0}, .offset = 0.0f});
  const SphereId a = w.add_sphere({.position = {0, 5, 0}, .radius = 1.0f});
  const auto inside = w.raycast({{0, 5, 0}, {1, 0, 0}});
  REQUIRE(inside);
  CHECK(inside->sphere == a);
  CHECK(inside->distance == 0.0f);
  CHECK(inside->normal == Vec3(-1, 0, 0));
  const auto down = w.raycast({{3, 5, 0}, {0, -2, 0}});
  REQUIRE(down);
  CHECK(down->kind == QueryHitKind::Plane);
  CHECK(down->distance == 5.0f);  // metres, whatever |direction|
  CHECK(down->point == Vec3(3, 0, 0));
  CHECK(!w.raycast({{3, 5, 0}, {0, -1, 0}}, {.planes = false}));
  CHECK(!w.raycast({{3, 5, 0}, {0, -1, 0}, 4.0f}));  // [0, max): short of the plane
  const auto all = w.raycast_all({{0, 10, 0}, {0, -1, 0}});
  REQUIRE(all.size() == 2);
  CHECK(all[0].sphere == a);
  CHECK(all[0].distance == 4.0f);
  CHECK(all[1].kind == QueryHitKind::Plane);
  const auto cast = w.sphere_cast({{3, 5, 0}, {0, -1, 0}}, 0.5f);
  REQUIRE(cast);
  CHECK(cast->distance == 4.5f);
  CHECK(cast->point == Vec3(3, 0, 0));
  const auto ignored = w.raycast({{0, 10, 0}, {0, -1, 0}}, {.ignore = a});
  REQUIRE(ignored);
  CHECK(ignored->kind == QueryHitKind::Plane);
}

TEST_CASE("queries refuse bad input and name the value", "[queries]") {
  World w;
  w.add_sphere({});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto refused = [](auto&& call, const char* word) {
    try {
      call();
    } catch (const InvalidArgument& e) {
      return std::string(e.what()).find(word) != std::string::npos;
    }
    return false;
  };
  CHECK(refused([&] { (void)w.raycast({{nan, 0, 0}, {0, 1, 0}}); }, "origin"));
  CHECK(refused([&] { (void)w.raycast({{0, 0, 0}, {0, 0, 0}}); }, "direction"));
  CHECK(refused([&] { (void)w.raycast_all({{0, 0, 0}, {nan, 1, 0}}); }, "direction"));
  CHECK(refused([&] { (void)w.raycast({{0, 0, 0}, {0, 1, 0}, -1.0f}); }, "max_distance"));
  CHECK(refused([&] { (void)w.raycast({{0, 0, 0}, {0, 1, 0}, nan}); }, "max_distance"));
  CHECK(refused([&] { (void)w.sphere_cast({{0, 0, 0}, {0, 1, 0}}, -0.5f); }, "radius"));
  CHECK(refused([&] { (void)w.overlap_sphere({0, 0, 0}, nan); }, "radius"));
  CHECK(refused([&] { (void)w.overlap_sphere({0, nan, 0}, 1.0f); }, "centre"));
  CHECK(refused([&] { (void)w.overlap_box({1, 0, 0}, {0, 1, 1}); }, "min"));
  const std::vector<Ray> rays{{{0, 0, 0}, {0, 1, 0}}, {{0, 0, 0}, {0, 0, 0}}};
  std::vector<std::optional<QueryHit>> hits(2);
  CHECK(refused([&] { w.raycast_batch(rays, hits); }, "ray 1"));
}

TEST_CASE("queries from two threads at once build the stale BVH once and agree", "[queries][threads]") {
  const Scene s = make_scene(2000, 14);
  World& w = *s.world;
  const auto rays = random_rays(500, 15);
  std::vector<std::optional<QueryHit>> expected(rays.size());
  w.raycast_batch(rays, expected);
  const std::uint64_t builds = w.query_cache_builds();
  w.set_position(w.id_at(0), w.position(w.id_at(0)));  // stale again: both threads find it so
  std::vector<std::optional<QueryHit>> first(rays.size()), second(rays.size());
  std::thread other([&] {
    for (std::size_t k = 0; k < rays.size(); ++k) second[k] = w.raycast(rays[k]);
  });
  for (std::size_t k = 0; k < rays.size(); ++k) first[k] = w.raycast(rays[k]);
  other.join();
  CHECK(w.query_cache_builds() == builds + 1);
  for (std::size_t k = 0; k < rays.size(); ++k) {
    REQUIRE(identical(first[k], expected[k]));
    REQUIRE(identical(second[k], expected[k]));
  }
}

TEST_CASE("A ray direction of any non-zero finite length works, however long or short", "[queries]") {
  // Directions of 1e-40 or 3e38 were refused as "not zero": their squared length leaves float range.
  World w;
  w.add_sphere({.position = {0, 5, 0}});
  const std::optional<QueryHit> unit = w.raycast({{0, 0, 0}, {0, 1, 0}});
  REQUIRE(unit);
  for (float length : {1e-40f, 1e-30f, 1e30f, 3e38f}) {
    INFO(length);
    const std::optional<QueryHit> hit = w.raycast({{0, 0, 0}, {0, length, 0}});
    REQUIRE(hit);
    CHECK(hit->distance == unit->distance);
    CHECK(hit->sphere == unit->sphere);
    const std::optional<QueryHit> cast = w.sphere_cast({{0, 0, 0}, {0, length, 0}}, 0.25f);
    REQUIRE(cast);
    CHECK(cast->distance == Approx(4.25f));
  }
}
