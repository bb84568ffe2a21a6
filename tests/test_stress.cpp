// The stability battery (scenes/stress_cases.h): each case checks its invariants after every
// step, and every case passes with both solvers (WorldSettings::solver). A case the kernel stops passing would be tagged [!shouldfail]
// (with the reason in the commit), so that it still runs and the suite says so the day it
// passes again; `hail-bench stress` prints the worst values of every case.

#include <string>

#include "catch.h"
#include "scenes/stress_cases.h"

namespace {

hail::bench::StressResult run_case(const std::string& name, hail::Solver solver) {
  for (const hail::bench::StressCase& c : hail::bench::stress_cases(solver))
    if (c.name == name) return c.run();
  FAIL("no stress case named " << name);
  return {};
}

void require_passed(const hail::bench::StressResult& r) {
  INFO(r.invariants);
  for (const std::string& f : r.failures) INFO(f);
  CHECK(r.worst.steps > 0);
  CHECK(r.failures.empty());
}

/// Runs the case with each solver (WorldSettings::solver): both must pass it. The soft step's
/// last failure, radius-1e-4-and-1e4, passes since its depenetration goes on while overlaps are
/// deep (SoftStepParams::depenetration_iterations_max).
void run_stress_case(const std::string& name) {
  {
    INFO("solver: passes");
    require_passed(run_case(name, hail::Solver::Passes));
  }
  INFO("solver: soft step");
  require_passed(run_case(name, hail::Solver::SoftStep));
}

}  // namespace

TEST_CASE("Stress: a 1e4 kg sphere rests on 1 kg spheres", "[stress]") { run_stress_case("mass-ratio-1e4-on-1"); }
TEST_CASE("Stress: a 1 : 100 : 10,000 kg stack stands", "[stress]") { run_stress_case("stack-1-100-1e4"); }
TEST_CASE("Stress: a 1e-3 kg sphere hit by a 1e3 kg one", "[stress]") { run_stress_case("light-hit-by-heavy"); }
TEST_CASE("Stress: radius 0.01 among radius 10", "[stress]") { run_stress_case("radius-0.01-among-10"); }
TEST_CASE("Stress: 1e4 m/s into terrain", "[stress]") { run_stress_case("speed-1e4-into-terrain"); }
TEST_CASE("Stress: 1e4 m/s into a pile", "[stress]") { run_stress_case("speed-1e4-into-pile"); }
TEST_CASE("Stress: dt from 1e-5 to 1/20", "[stress]") { run_stress_case("dt-1e-5-to-1/20"); }
TEST_CASE("Stress: coincident centres, spheres on edges and vertices", "[stress]") {
  run_stress_case("coincident-and-on-edges");
}
TEST_CASE("Stress: vertical cliff and one-vertex spikes", "[stress]") { run_stress_case("cliff-and-spikes"); }
TEST_CASE("Stress: terrain-rain at the origin (the baseline of the far cases)", "[stress]") {
  run_stress_case("rain-at-origin");
}
TEST_CASE("Stress: heights of 1e4 m", "[stress]") { run_stress_case("heights-1e4"); }
TEST_CASE("Stress: 1e4 m from the origin", "[stress]") { run_stress_case("far-1e4"); }
TEST_CASE("Stress: 1e5 m from the origin", "[stress]") { run_stress_case("far-1e5"); }
TEST_CASE("Stress: restitution 0/1, friction 0/10, time scale 0/100", "[stress]") {
  run_stress_case("materials-and-time-scale");
}
TEST_CASE("Stress: 1.25e5 m from the origin (within kSphereRadiusResolution)", "[stress]") {
  run_stress_case("far-1.25e5");
}
TEST_CASE("Stress: time scale 300 and 750 stable, 1e4 refused", "[stress]") {
  run_stress_case("time-scale-300-and-750");
}
TEST_CASE("Stress: radius 1e-4 and 1e4 spheres", "[stress]") { run_stress_case("radius-1e-4-and-1e4"); }
TEST_CASE("Stress: small spheres under big ones stay above the ground", "[stress]") {
  run_stress_case("small-under-big-rain");
}
TEST_CASE("Stress: 1,000 spheres at one point", "[stress]") { run_stress_case("coincident-1000"); }
TEST_CASE("Stress: spheres starting inside the terrain", "[stress]") { run_stress_case("start-inside-terrain"); }
TEST_CASE("Stress: spheres in a box of planes", "[stress]") { run_stress_case("plane-box"); }
TEST_CASE("Stress: spheres added and removed between steps", "[stress]") { run_stress_case("add-and-remove"); }
TEST_CASE("Stress: 500 spheres created at one point on the ground", "[stress]") {
  run_stress_case("coincident-500-on-ground");
}
TEST_CASE("Stress: 1,024 spheres 1e4 m out, then shifted home (World::shift_origin)", "[stress][far_origin]") {
  run_stress_case("far-1e4-rain-shifted-home");
}
TEST_CASE("Stress: rain on steep real DEMs and generated cliffs, spikes, folds", "[stress][steep]") {
  run_stress_case("steep-terrain-rain");
}
TEST_CASE("Stress: rain of radii 0.05-5 m at one density (mass ratio 1e6)", "[stress]") {
  run_stress_case("wide-mix-rain");
}
TEST_CASE("Stress: bowl-pile with 10,000 spheres settles in 20 s", "[stress][.slow]") {
  run_stress_case("bowl-pile-10k-20s");
}
TEST_CASE("Stress: bowl-pile 10k with rolling resistance is asleep within 15 s", "[stress][.slow]") {
  run_stress_case("bowl-pile-10k-rolling-asleep");
}
TEST_CASE("Stress: spheres fired at 20-60 m/s at 1 mm mesh walls", "[stress][mesh]") {
  run_stress_case("meshes-thin-walls-60-m-s");
}
TEST_CASE("Stress: mixed radii rain through a mesh funnel", "[stress][mesh]") { run_stress_case("meshes-funnel-rain"); }
