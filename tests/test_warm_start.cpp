// Warm starting: contacts find their last-step impulses again (also after the Morton re-sort
// moved the spheres' slots), and a tall stack holds its weight far better with it than without.

#include <algorithm>
#include <cmath>

#include "catch.h"
#include "hail/world.h"
#include "kernel/solver/contact_cache.h"

using namespace hail;

namespace {

SphereRecord at(float x) { return {x, 0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 1, 10, 0.5f, 0.5f, 0}; }

Contact pair(std::uint32_t a, std::uint32_t b, float impulse) {
  Contact c;
  c.a = a, c.b = b, c.nx = 1, c.ny = 0, c.nz = 0, c.normal_impulse = impulse, c.tx = 0, c.ty = impulse, c.tz = 0;
  return c;
}

/// Deepest overlap with the floor (y = 0) after `steps` of a column of `count` spheres.
float column_sinking(float warm_start_factor, int count, int steps) {
  WorldSettings settings;
  settings.threads = 1;
  settings.warm_start_factor = warm_start_factor;
  World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.0f, .friction = 0.5f});
  for (int k = 0; k < count; ++k)
    world.add_sphere({.position = {0, 0.5f + 1.0f * float(k), 0}, .radius = 0.5f, .restitution = 0.0f});
  for (int k = 0; k < steps; ++k) world.step(1.0f / 60.0f);
  const SphereState s = world.spheres();
  float deepest = 0.0f;
  for (std::size_t i = 0; i < world.sphere_count(); ++i) deepest = std::max(deepest, s.radius[i] - s.py[i]);
  return deepest;
}

}  // namespace

TEST_CASE("The contact cache finds last step's impulses by sphere and feature, across a re-sort", "[warmstart]") {
  SphereSoA s;
  for (int k = 0; k < 4; ++k) s.add(at(float(k)));
  // Static contacts (sphere 0 on features 7 and 9, sphere 2 on feature 7), then pairs.
  std::vector<Contact> last;
  Contact ground;
  ground.a = 0, ground.b = kStaticBody, ground.feature = 7, ground.ny = 1, ground.nx = 0, ground.normal_impulse = 1.5f;
  last.push_back(ground);
  ground.feature = 9, ground.normal_impulse = 2.5f;
  last.push_back(ground);
  ground.a = 2, ground.feature = 7, ground.normal_impulse = 3.5f;
  last.push_back(ground);
  last.push_back(pair(0, 1, 4.0f));
  last.push_back(pair(1, 3, 5.0f));
  ContactImpulseCache cache;
  cache.store(last, 3, s);

  // Reverse the slots: every sphere moves, pairs may change which sphere comes first.
  const std::uint32_t reversed[4] = {3, 2, 1, 0};
  s.permute(reversed);                  // old slot 0 is now slot 3, 1 -> 2, 2 -> 1, 3 -> 0
  ContactImpulseCache unmoved = cache;  // not told of the permutation: every slot has another sphere
  cache.remap_slots(reversed);
  std::vector<Contact> now;
  Contact g;
  g.a = 3, g.b = kStaticBody, g.feature = 9, g.nx = 0, g.ny = 1, g.nz = 0;  // old sphere 0, feature 9
  now.push_back(g);
  g.a = 1, g.feature = 8;  // old sphere 2 on a feature it did not touch: no match
  now.push_back(g);
  now.push_back(pair(0, 2, 0.0f));                     // old spheres 3 and 1: stored as (1, 3)
  now.push_back(pair(2, 3, 0.0f));                     // old spheres 1 and 0: stored as (0, 1)
  now.push_back(pair(0, 1, 0.0f));                     // old spheres 3 and 2: never touched
  for (Contact& c : now) c.normal_impulse = -1.0f;     // must be overwritten either way
  CHECK(unmoved.load(now, 2, 0, now.size(), s) == 0);  // nothing taken for the wrong sphere
  CHECK(std::all_of(now.begin(), now.end(), [](const Contact& c) { return c.normal_impulse == 0.0f; }));
  const std::size_t matched = cache.load(now, 2, 0, now.size(), s);
  CHECK(matched == 3);
  CHECK(now[0].normal_impulse == 2.5f);
  CHECK(now[1].normal_impulse == 0.0f);
  CHECK(now[2].normal_impulse == 5.0f);
  CHECK(now[2].ty == 5.0f);  // the tangential part survives (normal is +x, impulse along +y)
  CHECK(now[3].normal_impulse == 4.0f);
  CHECK(now[4].normal_impulse == 0.0f);
  // A factor scales what is carried over; clearing forgets it all.
  cache.load(now, 2, 2, 3, s, 0.5f);
  CHECK(now[2].normal_impulse == 2.5f);
  cache.clear();
  CHECK(cache.load(now, 2, 0, now.size(), s) == 0);
}

TEST_CASE("A warm-start factor of 0 is warm starting off: no impulse is looked up or remembered", "[warmstart]") {
  for (const float factor : {0.0f, 0.5f}) {
    World world(WorldSettings{.threads = 1, .warm_start_factor = factor});
    world.add_plane({.normal = {0, 1, 0}, .offset = 0});
    for (int k = 0; k < 4; ++k) world.add_sphere({.position = {0, 0.5f + 1.0f * float(k), 0}, .radius = 0.5f});
    std::size_t warm_started = 0;
    for (int k = 0; k < 30; ++k) {
      world.step(1.0f / 60.0f);
      warm_started += world.last_step_stats().warm_started;
    }
    INFO("factor " << factor);
    CHECK((warm_started > 0) == (factor > 0.0f));
  }
}

TEST_CASE("A tall column sinks far less into the floor with warm starting", "[warmstart]") {
  const float without = column_sinking(0.0f, 12, 240);  // factor 0: warm starting off
  const float with = column_sinking(1.0f, 12, 240);
  INFO("deepest floor overlap without " << without << " m, with " << with << " m");
  CHECK(with < 0.02f);           // under 4% of the radius
  CHECK(with < 0.5f * without);  // and at most half of what it is without
}

TEST_CASE("The contact cache finds a contact anywhere in its sphere's range, stored block by block in any order",
          "[warmstart]") {
  SphereSoA s;
  for (int k = 0; k < 6; ++k) s.add(at(float(k)));
  // Detection order: static contacts of spheres 0 and 4 (three features each), then the pairs
  // of rows 0, 1 and 4.
  std::vector<Contact> last;
  for (std::uint32_t a : {0u, 4u})
    for (std::uint32_t f = 0; f < 3; ++f) {
      Contact g;
      g.a = a, g.b = kStaticBody, g.feature = 10 * a + f, g.nx = 0, g.ny = 1, g.nz = 0;
      g.normal_impulse = float(10 * a + f + 1);
      last.push_back(g);
    }
  const std::size_t static_count = last.size();
  for (auto [a, b] : {std::pair{0u, 1u}, {0u, 2u}, {0u, 5u}, {1u, 2u}, {4u, 5u}})
    last.push_back(pair(a, b, float(100 + 10 * a + b)));

  // As the step stores it: the layout in two blocks of slots [0, 3) and [3, 6) of each kind,
  // then the impulses in another order (the solver's colour order).
  ContactImpulseCache blocks;
  blocks.begin_layout(s);
  blocks.layout_static(last, 0, 3, 0, 3, s);
  blocks.layout_static(last, 3, static_count, 3, 6, s);
  blocks.layout_pairs(last, static_count, static_count + 4, 0, 3);
  blocks.layout_pairs(last, static_count + 4, last.size(), 3, 6);
  blocks.begin_store(last.size(), nullptr);
  for (std::size_t k = last.size(); k-- > 0;) blocks.store_entry(k, last[k], k < static_count, s);
  ContactImpulseCache whole;
  whole.store(last, static_count, s);

  // This step: sphere 0's features in another order with a new one first, sphere 4 lost one;
  // row 0 gained a pair in front and lost one; row 1 and 4 as they were.
  std::vector<Contact> now;
  for (auto [a, f] : {std::pair{0u, 7u}, {0u, 2u}, {0u, 0u}, {0u, 1u}, {4u, 41u}, {4u, 40u}}) {
    Contact g;
    g.a = a, g.b = kStaticBody, g.feature = f, g.nx = 0, g.ny = 1, g.nz = 0;
    now.push_back(g);
  }
  const std::size_t now_static = now.size();
  for (auto [a, b] : {std::pair{0u, 3u}, {0u, 1u}, {0u, 5u}, {1u, 2u}, {4u, 5u}}) now.push_back(pair(a, b, -1.0f));
  std::vector<Contact> again = now;
  CHECK(blocks.load(now, now_static, 0, now.size(), s) == 9);
  CHECK(whole.load(again, now_static, 0, again.size(), s) == 9);
  const float expected[] = {0, 3, 1, 2, 42, 41, 0, 101, 105, 112, 145};
  for (std::size_t k = 0; k < now.size(); ++k) {
    INFO("contact " << k);
    CHECK(now[k].normal_impulse == expected[k]);
    CHECK(again[k].normal_impulse == expected[k]);
  }
}
