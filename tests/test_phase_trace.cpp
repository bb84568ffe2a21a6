// The phase trace: one slice per phase per step per thread that worked on it, well formed,
// and recording it does not change the simulation.

#include <random>
#include <set>
#include <tuple>
#include <utility>

#include "catch.h"
#include "hail/world.h"

namespace {

void fill(hail::World& world) {
  world.add_plane({.normal = {0, 1, 0}, .offset = 0});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-8.0f, 8.0f);
  for (int k = 0; k < 2000; ++k) world.add_sphere({.position = {u(rng), 5.0f + u(rng), u(rng)}, .radius = 0.3f});
}

}  // namespace

TEST_CASE("The phase trace has a well-formed slice per phase, step and working thread", "[trace][threads]") {
  hail::WorldSettings settings;
  settings.threads = 2;
  hail::World traced(settings), plain(settings);
  fill(traced);
  fill(plain);
  traced.enable_trace(true);
  constexpr int kSteps = 5;
  for (int k = 0; k < kSteps; ++k) {
    traced.step(1.0f / 60.0f);
    plain.step(1.0f / 60.0f);
  }
  CHECK(traced.state_hash() == plain.state_hash());
  std::set<std::pair<std::uint64_t, hail::Phase>> seen;
  std::set<std::tuple<std::uint64_t, hail::Phase, int>> unique;
  bool well_formed = true;
  for (const hail::TraceSlice& s : traced.trace().slices()) {
    well_formed =
        well_formed && s.start_us <= s.end_us && s.thread >= 0 && s.thread < traced.thread_count() && s.step < kSteps;
    seen.insert({s.step, s.phase});
    unique.insert({s.step, s.phase, s.thread});
  }
  CHECK(well_formed);
  CHECK(unique.size() == traced.trace().slices().size());  // one slice per (step, phase, thread)
  for (std::uint64_t step = 0; step < kSteps; ++step)
    for (hail::Phase p : {hail::Phase::Predict, hail::Phase::DetectTerrain, hail::Phase::DetectPairs,
                          hail::Phase::Solve, hail::Phase::Integrate, hail::Phase::Depenetrate}) {
      INFO("step " << step << ", phase " << hail::phase_name(p));
      CHECK(seen.count({step, p}) == 1);
    }
  traced.enable_trace(false);
  traced.step(1.0f / 60.0f);
  CHECK(traced.trace().slices().empty());
}
