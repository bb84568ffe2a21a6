// The Morton re-sort of the sphere slots: a permutation sorted by code, handles still name
// their spheres after a world has re-sorted many times, and the step stays deterministic.

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "catch.h"
#include "hail/world.h"
#include "kernel/broadphase/spatial_order.h"
#include "kernel/geometry/morton.h"

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

TEST_CASE("The re-sort's parts run over blocks in any order give morton_slot_order's order", "[soa][order]") {
  // The World's re-sort (kernel/world/step_pipeline.cpp) runs finite_centre_bounds and morton_keys over
  // blocks in parallel and sorts the keys with tbb::parallel_sort: the box must be the union of
  // the blocks' boxes (non-finite centres left out), and the keys the serial ones.
  hail::SphereSoA s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-30.0f, 30.0f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < 1000; ++k) {
    float x = u(rng);
    if (k == 17) x = nan;
    if (k == 400) x = inf;
    if (k == 401) x = -inf;
    s.add({x, u(rng), 0.5f * u(rng), 0, 0, 0, 0, 0, 0, 0.5f, 1, 1, 0.5f, 0.5f, 0});
  }
  std::vector<std::uint64_t> serial_keys;
  std::vector<std::uint32_t> serial_order;
  hail::morton_slot_order(s, serial_keys, serial_order);
  constexpr std::size_t kBlock = 37;
  hail::Aabb box = hail::empty_aabb();
  for (std::size_t first = (s.size() - 1) / kBlock * kBlock;; first -= kBlock) {  // last block first
    hail::grow(box, hail::finite_centre_bounds(s, first, std::min(s.size(), first + kBlock)));
    if (first == 0) break;
  }
  const hail::Aabb whole = hail::finite_centre_bounds(s, 0, s.size());
  for (int a = 0; a < 3; ++a) {
    CHECK(box.min[a] == whole.min[a]);
    CHECK(box.max[a] == whole.max[a]);
    CHECK(std::isfinite(box.min[a]));
    CHECK(std::isfinite(box.max[a]));
  }
  std::vector<std::uint64_t> keys(s.size());
  for (std::size_t first = 0; first < s.size(); first += kBlock)
    hail::morton_keys(s, box, first, std::min(s.size(), first + kBlock), keys.data());
  std::sort(keys.begin(), keys.end());
  REQUIRE(keys.size() == serial_order.size());
  std::size_t different = 0;
  for (std::size_t k = 0; k < keys.size(); ++k) different += static_cast<std::uint32_t>(keys[k]) != serial_order[k];
  CHECK(different == 0);
}

TEST_CASE("A world of several re-sort blocks re-sorts to the same state on 1, 2 and 3 threads",
          "[soa][order][determinism][threads]") {
  // More spheres than one block of the parallel re-sort (16,384), re-sorted every step.
  auto run = [](int threads) {
    hail::WorldSettings settings;
    settings.threads = threads;
    settings.reorder_interval = 1;
    hail::World world(settings);
    world.add_plane({.normal = {0, 1, 0}, .offset = 0});
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-60.0f, 60.0f), h(0.5f, 6.0f);
    for (int k = 0; k < 20000; ++k) world.add_sphere({.position = {u(rng), h(rng), u(rng)}, .radius = 0.3f});
    std::vector<hail::SphereId> first_ids;
    for (std::size_t slot = 0; slot < 8; ++slot) first_ids.push_back(world.soa().id_at(slot));
    for (int step = 0; step < 6; ++step) world.step(1.0f / 60.0f);
    std::size_t moved = 0;
    for (std::size_t slot = 0; slot < first_ids.size(); ++slot)
      moved += world.slot_of(first_ids[slot]) != static_cast<std::int64_t>(slot);
    CHECK(moved > 0);  // the slots really were re-sorted
    return world.state_hash();
  };
  const std::uint64_t one = run(1);
  CHECK(run(2) == one);
  CHECK(run(3) == one);
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
    ids.push_back(
        world.add_sphere({.position = {u(rng), 1.0f + 0.5f * (u(rng) + 20.0f), u(rng)}, .radius = radius.back()}));
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
