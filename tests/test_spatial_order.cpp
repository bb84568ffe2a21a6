// The Morton re-sort of the sphere slots: a permutation sorted by code, handles still name
// their spheres after a world has re-sorted many times, and the step stays deterministic.

#include <algorithm>
#include <random>
#include <vector>

#include "catch.h"
#include "kernel/morton.h"
#include "kernel/spatial_order.h"
#include "kernel/world.h"

TEST_CASE("morton_slot_order is a permutation sorted by Morton code, ties by slot", "[soa][order]") {
  hail::SphereSoA s;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-50.0f, 50.0f);
  for (int k = 0; k < 3000; ++k) {
    const float x = k % 10 == 0 ? 0.0f : u(rng);  // some equal centres: ties
    s.add({x, k % 10 == 0 ? 0.0f : u(rng), k % 10 == 0 ? 0.0f : u(rng), 0, 0, 0, 0, 0, 0, 0.5f, 1, 1, 0.5f, 0.5f, 0});
  }
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> order;
  hail::morton_slot_order(s, keys, order);
  REQUIRE(order.size() == s.size());
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t k = 0; k < sorted.size(); ++k) REQUIRE(sorted[k] == k);
  hail::Aabb box = hail::empty_aabb();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const float p[3] = {s.px[i], s.py[i], s.pz[i]};
    hail::grow(box, p);
  }
  auto code = [&](std::uint32_t i) { return hail::morton_code_3d(box, s.px[i], s.py[i], s.pz[i]); };
  std::size_t out_of_order = 0;
  for (std::size_t k = 1; k < order.size(); ++k) {
    const auto a = code(order[k - 1]), b = code(order[k]);
    out_of_order += a > b || (a == b && order[k - 1] > order[k]);
  }
  CHECK(out_of_order == 0);
}

TEST_CASE("Handles keep naming their spheres across Morton re-sorts", "[soa][order]") {
  hail::WorldSettings settings;
  settings.threads = 1;
  settings.reorder_interval = 1;  // every step
  hail::World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-20.0f, 20.0f);
  std::vector<hail::SphereId> ids;
  std::vector<float> radius;
  for (int k = 0; k < 500; ++k) {
    radius.push_back(0.2f + 0.0005f * float(k));  // distinct: the radius identifies the sphere
    ids.push_back(world.add_sphere({.position = {u(rng), 1.0f + 0.5f * (u(rng) + 20.0f), u(rng)}, .radius = radius.back()}));
  }
  const float x_before = world.position(ids[123]).x();
  for (int step = 0; step < 30; ++step) world.step(1.0f / 60.0f);
  std::size_t wrong = 0;
  for (std::size_t k = 0; k < ids.size(); ++k)
    wrong += world.soa().radius[static_cast<std::size_t>(world.slot_of(ids[k]))] != radius[k];
  CHECK(wrong == 0);
  // Dropping from rest onto a plane: horizontal motion stays small, so the handle still finds
  // the sphere where it was put (a wrong mapping would jump by metres).
  CHECK(std::abs(world.position(ids[123]).x() - x_before) < 1.0f);
  // The slots really moved: slot order is no longer insertion order.
  std::size_t moved = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) moved += world.slot_of(ids[k]) != static_cast<std::int64_t>(k);
  CHECK(moved > 0);
}

TEST_CASE("A negative reorder interval is rejected", "[soa][order]") {
  hail::WorldSettings settings;
  settings.reorder_interval = -1;
  CHECK_THROWS_AS(hail::World(settings), hail::InvalidArgument);
}
