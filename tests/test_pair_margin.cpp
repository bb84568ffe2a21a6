// Each pair's own speculative margin (WorldSettings::pair_margin_travel): the pair search uses
// the step's margin, which the fastest sphere sets for everyone; pairs beyond their own
// margin, k (|va| + |vb|) dt, are dropped, and pairs within it are kept.

#include <algorithm>
#include <cmath>
#include <memory>

#include "catch.h"
#include "hail/world.h"

using namespace hail;

namespace {

constexpr float kDt = 1.0f / 60.0f;

/// No gravity; two spheres r = 0.5 on the x axis with `gap` between them, closing at `closing`
/// m/s (each moving closing / 2); a third, far away, moving at 20 m/s (not fast: 0.33 m a step) so that the step's
/// margin is at its cap (speculative_radii = 1: 0.5 m).
std::unique_ptr<World> pair_with_fast_bystander(float gap, float closing, float travel_factor) {
  WorldSettings settings;
  settings.threads = 1;
  settings.gravity = {0, 0, 0};
  settings.pair_margin_travel = travel_factor;
  settings.reorder_interval = 0;
  auto world = std::make_unique<World>(settings);
  world->add_sphere({.position = {0, 0, 0}, .velocity = {closing / 2, 0, 0}});
  world->add_sphere({.position = {1.0f + gap, 0, 0}, .velocity = {-closing / 2, 0, 0}});
  world->add_sphere({.position = {0, 100, 0}, .velocity = {0, 20, 0}});
  return world;
}

std::size_t sphere_contacts_after_one_step(float gap, float closing, float travel_factor) {
  const auto world = pair_with_fast_bystander(gap, closing, travel_factor);
  world->step(kDt);
  return world->last_contacts().size();
}

}  // namespace

TEST_CASE("A resting pair beyond its own margin gets no speculative contact", "[pairs][margin]") {
  // Gap 0.2 m: inside the step's 0.5 m margin, far beyond the pair's own (0 m/s: 0 m).
  CHECK(sphere_contacts_after_one_step(0.2f, 0.0f, 2.0f) == 0);
  // With per-pair margins off, every pair gets the step's margin, as before.
  CHECK(sphere_contacts_after_one_step(0.2f, 0.0f, 0.0f) == 1);
}

TEST_CASE("A closing pair within its own margin keeps its contact and does not overlap", "[pairs][margin]") {
  // 6 m/s closing: (3 + 3) * dt = 0.1 m of travel; k = 2 gives a 0.2 m margin.
  CHECK(sphere_contacts_after_one_step(0.15f, 6.0f, 2.0f) == 1);
  CHECK(sphere_contacts_after_one_step(0.25f, 6.0f, 2.0f) == 0);
  // The kept contact stops them at touching (e = 0.5 bounces them back): after a second of
  // steps they never overlapped by more than the 1% slop.
  const auto world_owner = pair_with_fast_bystander(0.05f, 6.0f, 2.0f);
  World& world = *world_owner;
  float deepest = 0.0f;
  for (int k = 0; k < 60; ++k) {
    world.step(kDt);
    const SphereState s = world.spheres();
    float dx = 0, dy = 0, dz = 0;
    bool found = false;
    for (std::size_t i = 0; i < world.sphere_count() && !found; ++i)
      for (std::size_t j = i + 1; j < world.sphere_count(); ++j)
        if (std::abs(s.py[i]) < 1.0f && std::abs(s.py[j]) < 1.0f) {
          dx = s.px[j] - s.px[i], dy = s.py[j] - s.py[i], dz = s.pz[j] - s.pz[i];
          found = true;
          break;
        }
    REQUIRE(found);
    deepest = std::max(deepest, 1.0f - std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  CHECK(deepest <= 0.01f * 0.5f + 1e-6f);
}
