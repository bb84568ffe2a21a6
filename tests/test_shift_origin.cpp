// World::shift_origin (include/hail/world.h): spheres, planes and terrain move together, exactly for
// offsets that bring the world back towards the origin by whole metres; the motion goes on as
// it would have; bad offsets are refused with the world unchanged.

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "kernel/terrain/terrain_parts.h"
#include "world_refusal.h"

using hail::Heightmap;
using hail::HeightmapParams;
using hail::PlaneDesc;
using hail::SphereId;
using hail::Terrain;
using hail::Vec3;
using hail::World;
using hail::WorldSettings;
using namespace hail::testing;

namespace {

/// Gentle waves (terrain-rain's shape at a smaller scale), of the place relative to the origin.
std::shared_ptr<const Terrain> waves_at(float origin) {
  HeightmapParams p;
  p.origin_x = p.origin_z = origin;
  return std::make_shared<const Terrain>(Heightmap::from_function(64, 64, p, [=](float x, float z) {
    return 2.0f * std::sin(0.2f * (x - origin)) * std::cos(0.15f * (z - origin));
  }));
}

/// 36 spheres 4 m apart (they never meet) dropped onto the waves, with a wall (plane x = far + 60), all
/// `far` m out along x and z.
std::vector<SphereId> build(World& w, float far) {
  w.set_terrain(waves_at(far));
  w.add_plane({.normal = {-1.0f, 0.0f, 0.0f}, .offset = -(far + 60.0f)});
  std::vector<SphereId> ids;
  for (int k = 0; k < 36; ++k)
    ids.push_back(
        w.add_sphere({.position = {far + 10.25f + 4.0f * (k % 6), 4.5f + 0.25f * (k % 3), far + 10.5f + 4.0f * (k / 6)},
                      .velocity = {3.0f, 0.0f, 0.5f},
                      .radius = 0.5f}));
  return ids;
}

WorldSettings two_threads() {
  WorldSettings s;
  s.threads = 2;
  return s;
}

}  // namespace

TEST_CASE("shift_origin moves spheres, planes and terrain together, exactly by whole metres home",
          "[shift_origin][far_origin]") {
  constexpr float kFar = 4096.0f;
  World w(two_threads());
  const std::vector<SphereId> ids = build(w, kFar);
  for (int k = 0; k < 60; ++k) w.step(1.0f / 60.0f);
  std::vector<Vec3> before;
  for (SphereId id : ids) before.push_back(w.position(id));
  const std::vector<float> heights(w.terrain()->heightmap().heights().begin(),
                                   w.terrain()->heightmap().heights().end());
  const Terrain* shared = w.terrain();
  const std::uint32_t triangle_count = std::uint32_t(shared->triangles().size());
  const std::vector<std::uint32_t> bvh_order = shared->bvh().primitive_order;

  w.shift_origin({kFar, 0.0f, kFar});
  for (std::size_t k = 0; k < ids.size(); ++k) {
    CAPTURE(k);
    // p - 4096 is exact: p is a multiple of its spacing (2^-11 m at 4096 m) and lands nearer 0.
    CHECK(w.position(ids[k]) == before[k] - Vec3(kFar, 0.0f, kFar));
  }
  const Heightmap& moved = w.terrain()->heightmap();
  CHECK(w.terrain() != shared);  // a moved copy: the shared terrain is immutable
  CHECK(moved.x_of(0) == 0.0f);
  CHECK(moved.z_of(0) == 0.0f);
  CHECK(std::equal(heights.begin(), heights.end(), moved.heights().begin(), moved.heights().end()));
  CHECK(w.terrain()->triangles().size() == triangle_count);
  CHECK(w.planes()[0].offset == -60.0f);
  // The same triangles in the same BVH order: the warm-start impulses (keyed by triangle
  // index) still name them, so shift_origin kept them.
  CHECK(w.terrain()->bvh().primitive_order == bvh_order);

  // A y offset moves heights and positions too.
  const float y_before = w.position(ids[0]).y();
  const float h_before = w.terrain()->heightmap().h(3, 4);
  w.shift_origin({0.0f, -8.0f, 0.0f});
  CHECK(w.position(ids[0]).y() == y_before + 8.0f);
  CHECK(w.terrain()->heightmap().h(3, 4) == h_before + 8.0f);
  CHECK(w.planes()[0].offset == -60.0f);  // the wall's normal has no y
}

TEST_CASE("shift_origin: stepping after the shift follows the unshifted world", "[shift_origin][far_origin]") {
  // Two copies of a world 4096 m out; one is brought home after 30 steps, both take 90 more.
  // The shift itself is exact (above), so the worlds part only because the far one rounds its
  // positions to 2^-12 m (half its spacing) every step and the near one much finer. Measured
  // (2-core AVX2): the gap grows by 2e-4 m a step while the spheres fall (0.013 m after 60
  // steps), then landings and bounces a step apart amplify it, to 0.070 m after 90. The bound,
  // 0.15 m, is twice that and 30% of a radius; terrain moved by a wrong amount puts the waves
  // (2 m high, 31 m long) under the spheres elsewhere, a wrongly moved wall or sphere offsets
  // them by the error itself.
  constexpr float kFar = 4096.0f;
  World far(two_threads()), home(two_threads());
  const std::vector<SphereId> far_ids = build(far, kFar), home_ids = build(home, kFar);
  for (int k = 0; k < 30; ++k) far.step(1.0f / 60.0f), home.step(1.0f / 60.0f);
  home.shift_origin({kFar, 0.0f, kFar});
  float worst = 0.0f;
  for (int k = 0; k < 90; ++k) {
    far.step(1.0f / 60.0f), home.step(1.0f / 60.0f);
    for (std::size_t i = 0; i < far_ids.size(); ++i)
      worst = std::max(
          worst,
          (home.position(home_ids[i]) + Vec3(kFar, 0.0f, kFar) - far.position(far_ids[i])).cwiseAbs().maxCoeff());
  }
  INFO("largest difference " << worst << " m");
  CHECK(worst <= 0.15f);
  // The spheres did move: rolled over the waves and some against the wall.
  CHECK(home.position(home_ids[0]).x() > 10.25f + 3.0f);
}

TEST_CASE("shift_origin refuses bad offsets and leaves the world unchanged", "[shift_origin][invalid][far_origin]") {
  World w(two_threads());
  build(w, 0.0f);
  const Terrain* terrain = w.terrain();
  auto unchanged = [&] {
    CHECK(w.terrain() == terrain);
    CHECK(w.planes()[0].offset == -60.0f);
  };
  expect_rejected(w, [&] { w.shift_origin({kNaN, 0.0f, 0.0f}); }, {"shift_origin", "finite", "nan"});
  unchanged();
  expect_rejected(w, [&] { w.shift_origin({0.0f, 0.0f, -kInf}); }, {"shift_origin", "finite"});
  unchanged();
  // 1e7 m out, floats are 1 m apart: more than the 1 m cells / kTerrainCellResolution that
  // set_terrain allows.
  // Its spheres would land where add_sphere refuses them first.
  expect_rejected(w, [&] { w.shift_origin({-1e7f, 0.0f, 0.0f}); }, {"shift_origin", "add_sphere"});
  unchanged();
  World bare(two_threads());  // the terrain alone
  bare.set_terrain(waves_at(0.0f));
  expect_rejected(bare, [&] { bare.shift_origin({-1e7f, 0.0f, 0.0f}); }, {"terrain reaches", "kTerrainCellResolution"});
  // A sphere carried where add_sphere would refuse to place it (kSphereRadiusResolution): a
  // shift of 1e30 collapsed every sphere onto one float, and one of 1e6 put 0.5 m spheres where
  // floats are 0.0625 m apart. A shift past float range is refused the same way.
  World big(two_threads());
  big.add_sphere({.position = {0.0f, 0.0f, 0.0f}});
  big.add_sphere({.position = {3.0f, 0.0f, 0.0f}});
  for (float out : {1e30f, 1e6f, -3e38f})
    expect_rejected(big, [&] { big.shift_origin({out, 0.0f, 0.0f}); }, {"shift_origin", "sphere 0", "add_sphere"});
  big.shift_origin({-1e5f, 0.0f, 0.0f});  // 1e5 m out: floats 7.8 mm apart, under 0.5 m / 64
  CHECK(big.position(big.id_at(0)).x() == 1e5f);
  CHECK(big.position(big.id_at(1)).x() == 100003.0f);
  // A plane offset that would.
  World walls(two_threads());
  walls.add_plane({.normal = {1.0f, 0.0f, 0.0f}, .offset = 3e38f});
  expect_rejected(walls, [&] { walls.shift_origin({-3e38f, 0.0f, 0.0f}); }, {"shift_origin", "plane 0"});
  CHECK(walls.planes()[0].offset == 3e38f);
}

TEST_CASE("shift_origin may bring a sphere that flew past the placement rule nearer, never farther",
          "[shift_origin][invalid][far_origin]") {
  // A step does not stop a sphere flying out; such a sphere must not block shifting home.
  World w(two_threads());
  const SphereId flyer = w.add_sphere({.position = {1e5f, 0.0f, 0.0f}, .velocity = {1e6f, 0.0f, 0.0f}});
  w.step(0.5f);  // ~5e5 m out with 0.5 m radius: floats there are 0.03 m apart, past r / 64
  const float x = w.position(flyer).x();
  REQUIRE(x > 4e5f);
  expect_rejected(w, [&] { w.shift_origin({-1e5f, 0.0f, 0.0f}); }, {"shift_origin", "add_sphere"});
  w.shift_origin({1e5f, 0.0f, 0.0f});  // nearer: allowed though still past the rule
  CHECK(w.position(flyer).x() == x - 1e5f);
}
