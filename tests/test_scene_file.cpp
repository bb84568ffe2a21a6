// Scene files (scenes/scene_file.h): the shipped files are the built-in scenes exactly; bad files
// are refused with the file and the field named; the random generator is deterministic.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "catch.h"
#include "file_faults.h"
#include "hail/settings_table.h"
#include "scenes/large_scene_text.h"
#include "scenes/scene_file.h"
#include "scenes/scene_run.h"

namespace {

using hail::bench::parse_scene_text;
using hail::bench::Scene;
using hail::bench::SceneOverrides;
using hail::bench::scene_of_many_spheres;

const std::string kScenes = std::string(HAIL_SOURCE_DIR) + "/data/scenes/";

/// The message of the std::invalid_argument parsing `text` throws ("(no error)" if none).
std::string error_of(const std::string& text, const SceneOverrides& overrides = {}) {
  try {
    (void)parse_scene_text(text, "scene.json", overrides);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

/// `body` wrapped in the header every file needs.
std::string scene_text(const std::string& body) {
  return R"({"format": "hail-scene", "version": 1)" + std::string(body.empty() ? "" : ", ") + body + "}";
}

std::filesystem::path fresh_temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("hail-test-scene-file-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void require_same_world(Scene& from_file, Scene& built_in, int steps) {
  REQUIRE(from_file.world->sphere_count() == built_in.world->sphere_count());
  REQUIRE(from_file.ids.size() == from_file.world->sphere_count());
  REQUIRE(built_in.ids.size() == built_in.world->sphere_count());
  CHECK(from_file.dt == built_in.dt);
  CHECK(from_file.default_steps == built_in.default_steps);
  CHECK(from_file.has_terrain == built_in.has_terrain);
  CHECK(from_file.min_x == built_in.min_x);
  CHECK(from_file.max_x == built_in.max_x);
  CHECK(from_file.min_z == built_in.min_z);
  CHECK(from_file.max_z == built_in.max_z);
  CHECK(from_file.world->planes().size() == built_in.world->planes().size());
  CHECK(from_file.world->settings().gravity == built_in.world->settings().gravity);
  CHECK(from_file.world->state_hash() == built_in.world->state_hash());
  for (int k = 0; k < steps; ++k) {
    from_file.world->step(from_file.dt);
    built_in.world->step(built_in.dt);
  }
  CHECK(from_file.world->state_hash() == built_in.world->state_hash());
  for (std::size_t k = 0; k < from_file.ids.size(); k += 97)
    CHECK(from_file.world->position(from_file.ids[k]) == built_in.world->position(built_in.ids[k]));
}

}  // namespace

TEST_CASE("scene files: the shipped scenes build exactly the built-in scenes", "[scene_file][threads]") {
  hail::bench::SceneParams params;
  params.spheres = 4000;
  params.threads = 2;
  const SceneOverrides overrides{.threads = 2};
  for (const char* name : {"terrain-rain", "bowl-pile", "implosion", "terrain-rain-dem"}) {
    INFO(name);
    Scene from_file = hail::bench::load_scene_file(kScenes + name + ".json", overrides);
    Scene built_in = hail::bench::find_scene(name).build(params);
    CHECK(from_file.world->sphere_count() == 4000);
    require_same_world(from_file, built_in, 5);
  }
}

TEST_CASE("scene files: command-line values override the file's", "[scene_file]") {
  hail::bench::SceneParams params;
  params.spheres = 1000;
  params.threads = 1;
  params.dt = 1.0f / 120.0f;
  params.settings.reorder_interval = 4;
  params.settings.pair_search = hail::PairSearch::Grid;
  params.settings.warm_start_factor = 0.8f;
  params.settings.resting_iterations = 5;
  const SceneOverrides overrides{
      .spheres = 1000,
      .threads = 1,
      .steps = 77,
      .dt = 1.0f / 120.0f,
      .set = {"reorder_interval=4", "resting_iterations=5", "pair_search=grid", "warm_start_factor=0.8"}};
  Scene from_file = hail::bench::load_scene_file(kScenes + "terrain-rain.json", overrides);
  const hail::WorldSettings& s = from_file.world->settings();
  CHECK(s.threads == 1);
  CHECK(s.reorder_interval == 4);
  CHECK(s.pair_search == hail::PairSearch::Grid);
  CHECK(s.warm_start_factor == 0.8f);
  CHECK(s.resting_iterations == 5);
  CHECK(from_file.default_steps == 77);
  from_file.default_steps = 600;
  Scene built_in = hail::bench::build_terrain_rain(params);
  CHECK(from_file.world->sphere_count() == 1000);
  require_same_world(from_file, built_in, 5);
}

TEST_CASE("scene files: a file with every kind of entry parses to what it says", "[scene_file]") {
  const Scene scene = parse_scene_text(R"({
    // comments are allowed
    "format": "hail-scene", "version": 1,
    "description": "test scene",
    "gravity": [0, -5, 0], "dt": 0.01, "steps": 42, "threads": 1,
    "settings": {
      "time_scale": 0.5, "integrator": "uniform-acceleration", "collision_iterations": 3,
      "resting_iterations": 2, "depenetration_iterations": 1,
      "depenetration": {"fraction": 0.5, "slop_fraction": 0.02},
      "restitution_threshold": 0.1, "sphere_collisions": false, "pair_search": "sweep",
      "speculative_radii": 0.5, "reorder_interval": 0, "warm_start_factor": 0.25,
      "continuous_collision": false, "fast_travel_fraction": 0.5, "max_sweep_events": 4
    },
    "terrain": null,
    "planes": [{"normal": [0, 2, 0], "offset": -1, "restitution": 0.3, "friction": 0.7}, {"normal": [1, 0, 0]}],
    "material": {"radius": 0.25, "mass": 2, "restitution": 0.4, "friction": 0.6},
    "spheres": [
      {"list": [{"position": [1, 2, 3], "velocity": [4, 5, 6], "angular_velocity": [7, 8, 9]},
                {"position": [5, 5, 5], "radius": 1, "mass": 3, "restitution": 1, "friction": 0, "static": true}]},
      {"lattice": {"count": 8, "layout": "cube", "spacing": 1, "centre": [10, 10, 10], "velocity": [0, 1, 0]}},
      {"random": {"count": 5, "seed": 3, "box_min": [-1, -1, -1], "box_max": [1, 1, 1], "radius": [0.1, 0.2], "speed": 2}}
    ]
  })",
                                       "inline.json");
  const hail::World& world = *scene.world;
  CHECK(scene.description == "test scene");
  CHECK(scene.dt == 0.01f);
  CHECK(scene.default_steps == 42);
  CHECK_FALSE(scene.has_terrain);
  CHECK(world.terrain() == nullptr);
  const hail::WorldSettings& s = world.settings();
  CHECK(s.gravity == hail::Vec3(0, -5, 0));
  CHECK(s.threads == 1);
  CHECK(s.time_scale == 0.5f);
  CHECK(s.integrator == hail::Integrator::UniformAcceleration);
  CHECK(s.collision_iterations == 3);
  CHECK(s.resting_iterations == 2);
  CHECK(s.depenetration_iterations == 1);
  CHECK(s.depenetration.fraction == 0.5f);
  CHECK(s.depenetration.slop_fraction == 0.02f);
  CHECK(s.restitution_threshold == 0.1f);
  CHECK_FALSE(s.sphere_collisions);
  CHECK(s.pair_search == hail::PairSearch::SweepAndPrune);
  CHECK(s.speculative_radii == 0.5f);
  CHECK(s.reorder_interval == 0);
  CHECK(s.warm_start_factor == 0.25f);
  CHECK_FALSE(s.continuous_collision);
  CHECK(s.fast_travel_fraction == 0.5f);
  CHECK(s.max_sweep_events == 4);
  CHECK(s.rotation);  // not given: the default
  const Scene still = parse_scene_text(scene_text(R"("settings": {"rotation": false})"), "still.json");
  CHECK_FALSE(still.world->settings().rotation);

  REQUIRE(world.planes().size() == 2);
  CHECK(world.planes()[0].offset == -0.5f);  // n . x = offset with n as given: both are divided by |n|

  REQUIRE(world.sphere_count() == 2 + 8 + 5);
  REQUIRE(scene.ids.size() == 15);
  CHECK(world.position(scene.ids[0]) == hail::Vec3(1, 2, 3));
  CHECK(world.velocity(scene.ids[0]) == hail::Vec3(4, 5, 6));
  CHECK(world.angular_velocity(scene.ids[0]) == hail::Vec3(7, 8, 9));
  const hail::SphereSoA& soa = world.soa();
  const auto slot = [&](std::size_t k) { return static_cast<std::size_t>(world.slot_of(scene.ids[k])); };
  CHECK(soa.radius[slot(0)] == 0.25f);  // the shared material
  CHECK(soa.inv_mass[slot(0)] == 0.5f);
  CHECK(soa.radius[slot(1)] == 1.0f);                                   // its own values
  CHECK(soa.inv_mass[slot(1)] == 0.0f);                                 // static
  CHECK(world.position(scene.ids[2]) == hail::Vec3(9.5f, 9.5f, 9.5f));  // cube of side 2 around (10, 10, 10)
  CHECK(world.position(scene.ids[9]) == hail::Vec3(10.5f, 10.5f, 10.5f));
  CHECK(world.velocity(scene.ids[9]) == hail::Vec3(0, 1, 0));
  for (std::size_t k = 10; k < 15; ++k) {
    const hail::Vec3 p = world.position(scene.ids[k]);
    CHECK(p.cwiseAbs().maxCoeff() <= 1.0f);
    CHECK(soa.radius[slot(k)] >= 0.1f);
    CHECK(soa.radius[slot(k)] <= 0.2f);
    CHECK(world.velocity(scene.ids[k]).norm() == Approx(2.0f).epsilon(1e-5));
  }
}

TEST_CASE("scene files: terrain from a heightmap file, relative to the scene file", "[scene_file]") {
  const auto dir = fresh_temp_dir("raw");
  std::filesystem::create_directories(dir / "maps");
  {
    std::ofstream raw(dir / "maps" / "ramp.f32", std::ios::binary);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) {
        const float h = static_cast<float>(i);
        raw.write(reinterpret_cast<const char*>(&h), sizeof h);
      }
    std::ofstream(dir / "scene.json") << scene_text(R"("terrain": {"heightmap": "maps/ramp.f32", "format": "raw-f32",
        "size": [4, 3], "cell_size": [2, 0.5], "height_scale": 3, "height_offset": 1, "origin": [10, 0, 20]},
        "spheres": [{"list": [{"position": [12, 10, 20.5]}]}])");
  }
  const Scene scene = hail::bench::load_scene_file((dir / "scene.json").string());
  REQUIRE(scene.has_terrain);
  CHECK(scene.min_x == 10.0f);
  CHECK(scene.max_x == 16.0f);
  CHECK(scene.min_z == 20.0f);
  CHECK(scene.max_z == 21.0f);
  CHECK(scene.ground_height(12.0f, 20.5f) == Approx(1.0f + 3.0f * 1.0f));
  CHECK(scene.world->terrain()->heightmap().max_height() == 10.0f);

  // The same map, but the file is missing: the loader's message, under the field's name.
  std::ofstream(dir / "missing.json") << scene_text(R"("terrain": {"heightmap": "maps/none.pgm"})");
  try {
    (void)hail::bench::load_scene_file((dir / "missing.json").string());
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(message.find("missing.json: terrain.heightmap: hail: ") != std::string::npos);
    CHECK(message.find("none.pgm") != std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene files: the solver and the soft step's knobs", "[scene_file][soft]") {
  const Scene scene = parse_scene_text(scene_text(R"("settings": {"solver": "soft", "soft_step": {"substeps": 6,
      "contact_cycles": 0.2, "damping_ratio": 5, "relax_iterations": 2, "max_push_speed": 1.5,
      "depenetration_iterations_max": 9}})"),
                                       "scene.json", {});
  const hail::WorldSettings& s = scene.world->settings();
  CHECK(s.solver == hail::Solver::SoftStep);
  CHECK(s.soft_step.substeps == 6);
  CHECK(s.soft_step.contact_cycles == 0.2f);
  CHECK(s.soft_step.damping_ratio == 5.0f);
  CHECK(s.soft_step.relax_iterations == 2);
  CHECK(s.soft_step.max_push_speed == 1.5f);
  CHECK(s.soft_step.depenetration_iterations_max == 9);
  // --solver passes on the command line has the last word.
  const Scene overridden =
      parse_scene_text(scene_text(R"("settings": {"solver": "soft"})"), "scene.json", {.set = {"solver=passes"}});
  CHECK(overridden.world->settings().solver == hail::Solver::Passes);
  // --integrator too, over the file's.
  const Scene integrated = parse_scene_text(scene_text(R"("settings": {"integrator": "semi-implicit-euler"})"),
                                            "scene.json", {.set = {"integrator=uniform-acceleration"}});
  CHECK(integrated.world->settings().integrator == hail::Integrator::UniformAcceleration);
}

TEST_CASE("scene files: an old file's warm_start is read as warm_start_factor", "[scene_file]") {
  auto factor = [](const std::string& settings) {
    return parse_scene_text(scene_text(R"("settings": )" + settings), "old.json").world->settings().warm_start_factor;
  };
  CHECK(factor(R"({"warm_start": false})") == 0.0f);
  CHECK(factor(R"({"warm_start": false, "warm_start_factor": 0.25})") == 0.0f);  // off, whatever the factor
  CHECK(factor(R"({"warm_start": true})") == 1.0f);
  CHECK(factor(R"({"warm_start": true, "warm_start_factor": 0.25})") == 0.25f);
  CHECK(factor(R"({"warm_start_factor": 0})") == 0.0f);
  CHECK(factor("{}") == 1.0f);
}

TEST_CASE("scene files: every kind of bad input names the file and the field", "[scene_file]") {
  struct Case {
    std::string text, expected;
  };
  const std::string list_head = R"("spheres": [{"list": [{"position": [0, 0, 0]}, )";
  const std::vector<Case> cases = {
      {scene_text(list_head + R"({"position": [0, 2, 0], "radius": -1}]}])"),
       "scene.json: spheres[0].list[1].radius: must be > 0, got -1"},
      {scene_text(R"("gravty": [0, -9.81, 0])"),
       "scene.json: unknown key \"gravty\" at top level (did you mean \"gravity\"?)"},
      {scene_text(R"("settings": {"warmstart": true})"),
       "scene.json: settings: unknown key \"warmstart\" (did you mean \"warm_start\"?)"},
      {scene_text(R"("spheres": [{"list": [{"positon": [0, 0, 0]}]}])"), "spheres[0].list[0]: unknown key \"positon\""},
      {scene_text(R"("spheres": [{"list": [{"radius": 1}]}])"),
       "scene.json: spheres[0].list[0]: missing required key \"position\""},
      {scene_text(R"("dt": "fast")"), "scene.json: dt: must be a number, got string \"fast\""},
      {scene_text(R"("dt": 0)"), "scene.json: dt: must be > 0, got 0"},
      {scene_text(R"("dt": 1e300)"), "scene.json: dt: must be a finite number within float range"},
      {scene_text(R"("steps": 10.5)"), "scene.json: steps: must be an integer, got 10.5"},
      {scene_text(R"("gravity": [0, -9.81])"), "scene.json: gravity: must be an array of 3 numbers"},
      {scene_text(R"("gravity": [0, "down", 0])"), "scene.json: gravity[1]: must be a number, got string \"down\""},
      {scene_text(R"("material": {"restitution": 1.5})"),
       "scene.json: material.restitution: must be in [0, 1], got 1.5"},
      {scene_text(R"("settings": {"pair_search": "fast"})"),
       "scene.json: settings.pair_search: must be one of \"auto\", \"brute\", \"grid\", \"sweep\", \"bvh\", got "
       "\"fast\""},
      {scene_text(R"("settings": {"integrator": "rk4"})"), "scene.json: settings.integrator: must be one of"},
      {scene_text(R"("settings": {"solver": "jacobi"})"), "scene.json: settings.solver: must be one of"},
      {scene_text(R"("settings": {"soft_step": {"substeps": 0}})"), "scene.json: settings.soft_step.substeps: must be"},
      {scene_text(R"("settings": {"soft_step": {"contact_cycles": 0.5}})"), "soft_step.contact_cycles"},
      {scene_text(R"("settings": {"soft_step": {"hertz": 30}})"), "settings.soft_step: unknown key \"hertz\""},
      {scene_text(R"("settings": {"warm_start": 1})"), "scene.json: settings.warm_start: must be true or false, got 1"},
      {scene_text(R"("settings": {"rotation": "off"})"),
       "scene.json: settings.rotation: must be true or false, got string \"off\""},
      {scene_text(
           R"("settings": {"rotation": false}, "spheres": [{"list": [{"position": [0, 0, 0], "angular_velocity": [0, 1, 0]}]}])"),
       "angular_velocity must be zero when WorldSettings::rotation is false"},
      {scene_text(R"("settings": {"collision_iterations": -1})"),
       "scene.json: settings.collision_iterations: must be >= 0, got -1"},
      {scene_text(R"("settings": {"fast_travel_fraction": 0})"),
       "scene.json: settings.fast_travel_fraction: must be in (0, 1], got 0"},
      {scene_text(R"("settings": {"max_sweep_events": 0})"),
       "scene.json: settings.max_sweep_events: must be >= 1, got 0"},
      {scene_text(R"("settings": {"depenetration": {"fraction": 2}})"),
       "scene.json: settings.depenetration.fraction: must be in [0, 1], got 2"},
      {scene_text(R"("spheres": [{"lattice": {"count": -5, "spacing": 1}}])"),
       "scene.json: spheres[0].lattice.count: must be >= 0, got -5"},
      {scene_text(R"("spheres": [{"lattice": {"spacing": 1}}])"),
       "scene.json: spheres[0].lattice: missing required key \"count\""},
      {scene_text(R"("spheres": [{"lattice": {"count": 4, "y_from": "terrain-min"}}])"),
       "scene.json: spheres[0].lattice.y_from: needs a terrain"},
      {scene_text(R"("spheres": [{"lattice": {"count": 4, "velocity": [1, 0, 0], "towards": {"speed": 1}}}])"),
       "scene.json: spheres[0].lattice: give \"velocity\" or \"towards\", not both"},
      {scene_text(R"("spheres": [{"random": {"count": 4, "box_min": [0, 0, 0], "box_max": [1, 1, 1]}}])"),
       "scene.json: spheres[0].random: missing required key \"seed\""},
      {scene_text(
           R"("spheres": [{"random": {"count": 4, "seed": 1, "box_min": [0, 0, 0], "box_max": [1, 1, 1], "radius": [1, 0.5]}}])"),
       "scene.json: spheres[0].random.radius: min must be <= max"},
      {scene_text(R"("spheres": [{"random": {"count": 4, "seed": 1, "box_min": [2, 0, 0], "box_max": [1, 1, 1]}}])"),
       "scene.json: spheres[0].random: box_min must be <= box_max"},
      {scene_text(R"("spheres": [{"list": [], "lattice": {"count": 1}}])"),
       "scene.json: spheres[0]: must have exactly one of \"list\", \"lattice\" or \"random\""},
      {scene_text(R"("spheres": {"list": []})"), "scene.json: spheres: must be an array of generators, got object"},
      {scene_text(R"("planes": [{"normal": [0, 0, 0]}])"), "scene.json: planes[0].normal: must not be zero"},
      {scene_text(R"("planes": [{"offset": 1}])"), "scene.json: planes[0]: missing required key \"normal\""},
      {scene_text(R"("terrain": {"function": "sine"})"),
       "scene.json: terrain.function: must be one of \"terrain-rain\", \"bowl\", \"flat\", got \"sine\""},
      {scene_text(R"("terrain": {"function": "flat", "heightmap": "a.pgm"})"),
       "scene.json: terrain: needs exactly one of \"function\" or \"heightmap\""},
      {scene_text(R"("terrain": {"function": "flat", "size": [1, 4]})"),
       "scene.json: terrain.size[0]: must be >= 2, got 1"},
      {scene_text(R"("terrain": {"function": "flat", "coefficient": 1})"),
       "scene.json: terrain.coefficient: applies to the \"bowl\" function only"},
      {scene_text(R"("terrain": {"heightmap": "a.dat"})"), "scene.json: terrain.heightmap: cannot tell the format"},
      {scene_text(R"("terrain": {"heightmap": "a.f32", "format": "raw-f32"})"),
       "scene.json: terrain: missing required key \"size\""},
      {R"({"version": 1})", "scene.json: missing \"format\": \"hail-scene\""},
      {R"({"format": "hail-scene"})", "scene.json: missing required key \"version\""},
      {R"({"format": "hail-scene", "version": 2, "new_key": 1})",
       "scene.json: version: this hail-bench reads version 1, got 2"},
      {R"([1, 2])", "scene.json: must be an object, got array"},
      {"{\"format\": \"hail-scene\",\n \"version\": 1,\n \"dt\": }",
       "scene.json: dt: [json.exception.parse_error.101] parse error at line 3, column 8"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(c.text);
    INFO("file: " << c.text << "\nmessage: " << message);
    CHECK(message.find(c.expected) != std::string::npos);
  }
}

TEST_CASE("scene files: --spheres needs exactly one lattice or random generator", "[scene_file]") {
  const std::string two = scene_text(R"("spheres": [{"lattice": {"count": 4}}, {"lattice": {"count": 4}}])");
  CHECK(error_of(two, {.spheres = 10}).find("scene.json: spheres: --spheres needs exactly one") != std::string::npos);
  CHECK(error_of(two) == "(no error)");
  const std::string one = scene_text(R"("spheres": [{"list": [{"position": [9, 9, 9]}]}, {"lattice": {"count": 4}}])");
  CHECK(parse_scene_text(one, "one.json", {.spheres = 10}).world->sphere_count() == 11);
}

TEST_CASE("scene files: missing file", "[scene_file]") {
  CHECK_THROWS_AS(hail::bench::load_scene_file("/nonexistent/scene.json"), std::invalid_argument);
  // A directory read as empty text: "parse error at line 1, column 1".
  const auto dir = fresh_temp_dir("directory");
  CHECK_THROWS_WITH(hail::bench::load_scene_file(dir.string()), dir.string() + ": is a directory, not a scene file");
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene files: the random generator is deterministic and documented", "[scene_file]") {
  const auto random_scene = [](int seed) {
    return scene_text(
        R"("gravity": [0, 0, 0], "spheres": [{"random": {"count": 300, "seed": )" + std::to_string(seed) +
        R"(, "box_min": [-10, 0, -10], "box_max": [10, 20, 10], "radius": [0.2, 0.6], "mass": [1, 3], "speed": [0, 4]}}])");
  };
  Scene a = parse_scene_text(random_scene(7), "a.json");
  Scene b = parse_scene_text(random_scene(7), "b.json");
  Scene c = parse_scene_text(random_scene(8), "c.json");
  CHECK(a.world->state_hash() == b.world->state_hash());
  CHECK(a.world->state_hash() != c.world->state_hash());
  for (int k = 0; k < 5; ++k) {
    a.world->step(a.dt);
    b.world->step(b.dt);
    c.world->step(c.dt);
  }
  CHECK(a.world->state_hash() == b.world->state_hash());
  CHECK(a.world->state_hash() != c.world->state_hash());

  // The first sphere follows the documented sequence: x, y, z, radius, mass, speed, then a
  // direction triple (retried until inside the unit ball).
  Scene d = parse_scene_text(random_scene(7), "d.json");
  std::mt19937_64 rng(7);
  const auto between = [&](float lo, float hi) { return lo + (hi - lo) * hail::bench::unit_float(rng); };
  // One draw per statement: as arguments of one call GCC draws z first (the reader did, until
  // this test spelt the documented order out).
  const float x = between(-10, 10);
  const float y = between(0, 20);
  const float z = between(-10, 10);
  const hail::Vec3 position(x, y, z);
  const float radius = between(0.2f, 0.6f);
  const float mass = between(1, 3);
  const float speed = between(0, 4);
  float dx, dy, dz, length2;
  do {
    dx = 2.0f * hail::bench::unit_float(rng) - 1.0f;
    dy = 2.0f * hail::bench::unit_float(rng) - 1.0f;
    dz = 2.0f * hail::bench::unit_float(rng) - 1.0f;
    length2 = dx * dx + dy * dy + dz * dz;
  } while (!(length2 > 1e-6f && length2 <= 1.0f));
  const float scale = speed / std::sqrt(length2);
  CHECK(d.world->position(d.ids[0]) == position);
  CHECK(d.world->velocity(d.ids[0]) == hail::Vec3(dx * scale, dy * scale, dz * scale));
  const auto slot = static_cast<std::size_t>(d.world->slot_of(d.ids[0]));
  CHECK(d.world->soa().radius[slot] == radius);
  CHECK(d.world->soa().inv_mass[slot] == 1.0f / mass);
  // std::mt19937_64 is fully specified by the standard (its 10,000th output), so the draws are
  // the same with every standard library.
  std::mt19937_64 standard(5489u);
  standard.discard(9999);
  CHECK(standard() == 9981545732273789042ull);
}

TEST_CASE("scene files: --dump-state writes spheres in the order they were added", "[scene_file]") {
  // Spheres listed against Morton order, re-sorted every step: slots and handles part ways.
  std::string list;
  for (int k = 0; k < 40; ++k)
    list += std::string(k ? ", " : "") + "{\"position\": [" + std::to_string(40 - k) + ", " + std::to_string(k % 3) +
            ", 0], \"velocity\": [0.5, 0, 0.25]}";
  Scene scene = parse_scene_text(
      scene_text(R"("settings": {"reorder_interval": 1}, "planes": [{"normal": [0, 1, 0], "offset": -1}],
                                                "spheres": [{"list": [)" +
                 list + "]}]"),
      "dump.json");
  for (int k = 0; k < 10; ++k) scene.world->step(scene.dt);
  REQUIRE(scene.world->slot_of(scene.ids[0]) != 0);

  const auto dir = fresh_temp_dir("dump");
  const std::string path = (dir / "state.csv").string();
  hail::bench::write_state_csv(scene, path);
  std::ifstream in(path);
  std::string line;
  REQUIRE(std::getline(in, line));
  CHECK(line == "id,x,y,z,vx,vy,vz,wx,wy,wz");
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    std::vector<float> v;
    std::stringstream fields(line);
    std::string field;
    std::getline(fields, field, ',');
    CHECK(std::stoul(field) == rows);
    while (std::getline(fields, field, ',')) v.push_back(std::strtof(field.c_str(), nullptr));
    REQUIRE(v.size() == 9);
    const hail::SphereId id = scene.ids[rows];
    CHECK(hail::Vec3(v[0], v[1], v[2]) == scene.world->position(id));  // %.9g reads back bit for bit
    CHECK(hail::Vec3(v[3], v[4], v[5]) == scene.world->velocity(id));
    CHECK(hail::Vec3(v[6], v[7], v[8]) == scene.world->angular_velocity(id));
    ++rows;
  }
  CHECK(rows == 40);
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene files: nesting deeper than 64 levels is refused before anything recurses", "[scene_file]") {
  auto nested = [](int levels) { return std::string(levels, '[') + std::string(levels, ']'); };
  // The top-level object is one level: "dt" may hold 63 more (refused by the schema only).
  CHECK(error_of(scene_text("\"dt\": " + nested(63))).find("scene.json: dt: must be a number, got array [[[[") !=
        std::string::npos);
  const std::string too_deep = error_of(scene_text("\"dt\": " + nested(64)));
  CHECK(too_deep.find("scene.json: dt[0][0]") == 0);
  CHECK(too_deep.find("arrays and objects nest deeper than 64 levels") != std::string::npos);
  // Used to crash (SIGSEGV) in the message helper's recursive dump, after nlohmann's parse.
  const std::string crash = error_of(scene_text("\"dt\": " + nested(60'000)));
  CHECK(crash.find("nest deeper than 64 levels") != std::string::npos);
  CHECK(crash.size() < 400);
  CHECK(error_of(
            scene_text("\"spheres\": [{\"list\": [{\"position\": [0, 0, 0], \"velocity\": " + nested(60'000) + "}]}]"))
            .find("scene.json: spheres[0].list[0].velocity[0]") == 0);
}

TEST_CASE("scene files: a deep or huge value in a parsed document is quoted by an excerpt", "[scene_file]") {
  // parse_scene_json takes any document: "got ..." must not walk all of it (a recursive dump
  // of 200,000 levels overflows the stack).
  nlohmann::json deep = nlohmann::json::array();
  for (int k = 0; k < 200'000; ++k) deep = nlohmann::json::array({std::move(deep)});
  nlohmann::json doc = {{"format", "hail-scene"}, {"version", 1}, {"dt", std::move(deep)}};
  try {
    (void)hail::bench::parse_scene_json(doc, "doc.json");
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message == "doc.json: dt: must be a number, got array " + std::string(45, '[') + "...");
  }
  doc["dt"] = std::string(10'000'000, 'x');
  CHECK_THROWS_WITH(hail::bench::parse_scene_json(doc, "doc.json"),
                    "doc.json: dt: must be a number, got string \"" + std::string(44, 'x') + "...");
}

TEST_CASE("scene files: numbers beyond a double, or beyond the field's range, name the field", "[scene_file]") {
  struct Case {
    std::string body, expected;
  };
  const std::vector<Case> cases = {
      {R"("dt": 1e999)", "scene.json: dt: must be a finite number (a double holds up to about 1.8e308)"},
      {R"("dt": -1e400)", "scene.json: dt: must be a finite number"},
      {R"("dt": 1e-400)", "scene.json: dt: must be > 0, got 0.0"},
      {R"("spheres": [{"lattice": {"count": 1e400}}])",
       "scene.json: spheres[0].lattice.count: must be a finite number"},
      {R"("spheres": [{"lattice": {"count": 2.5}}])",
       "scene.json: spheres[0].lattice.count: must be an integer, got 2.5"},
      {R"("spheres": [{"lattice": {"count": 1e-400}}])",
       "scene.json: spheres[0].lattice.count: must be an integer, got 0.0"},
      {R"("spheres": [{"lattice": {"count": -1}}])", "scene.json: spheres[0].lattice.count: must be >= 0, got -1"},
      {R"("spheres": [{"lattice": {"count": 18446744073709551615}}])",
       "scene.json: spheres[0].lattice.count: must be <= 100000000, got 18446744073709551615"},
      {R"("spheres": [{"lattice": {"count": 18446744073709551616}}])",
       "scene.json: spheres[0].lattice.count: must be an integer"},
      {R"("spheres": [{"lattice": {"count": -9223372036854775809}}])",
       "scene.json: spheres[0].lattice.count: must be an integer"},
      {R"("steps": 99999999999)", "scene.json: steps: must be <= 2147483647, got 99999999999"},
      {R"("gravity": [0, 1e39, 0])", "scene.json: gravity[1]: must be a finite number within float range"},
      {R"("spheres": [{"random": {"count": 1, "seed": -1, "box_min": [0, 0, 0], "box_max": [1, 1, 1]}}])",
       "scene.json: spheres[0].random.seed: must be an integer >= 0, got -1"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(scene_text(c.body));
    INFO("body: " << c.body << "\nmessage: " << message);
    CHECK(message.find(c.expected) == 0);
  }
  // Still std::invalid_argument, as docs/scene_format.md promises (nlohmann's out_of_range was not).
  CHECK_THROWS_AS(parse_scene_text(scene_text(R"("dt": 1e999)"), "scene.json"), std::invalid_argument);
}

TEST_CASE("scene files: a key given twice in one object is refused by name and path", "[scene_file]") {
  CHECK(error_of(scene_text(R"("dt": 0.01, "dt": 0.02)")) ==
        "scene.json: duplicate key \"dt\" at top level (a key may be given once)");
  CHECK(
      error_of(scene_text(
          R"("spheres": [{"list": [{"position": [0, 0, 0]}, {"position": [0, 2, 0], "radius": 1, "radius": 2}]}])")) ==
      "scene.json: spheres[0].list[1]: duplicate key \"radius\" (a key may be given once)");
  CHECK(error_of(scene_text(R"("settings": {"depenetration": {"fraction": 0.5, "fraction": 0.5}})")) ==
        "scene.json: settings.depenetration: duplicate key \"fraction\" (a key may be given once)");
  // The same key in different objects is fine.
  CHECK(error_of(scene_text(R"("spheres": [{"list": [{"position": [0, 0, 0]}, {"position": [0, 2, 0]}]}])")) ==
        "(no error)");
}

TEST_CASE("scene files: terrain fields that would overflow a float are named", "[scene_file]") {
  struct Case {
    std::string body, expected;
  };
  const std::vector<Case> cases = {
      // Used to end in "BVH primitive 2 has a non-finite or inverted box".
      {R"("terrain": {"function": "flat", "cell_size": 3e38})",
       "scene.json: terrain.cell_size: times the 255 cells along x is beyond float range"},
      {R"("terrain": {"function": "flat", "cell_size": [1, 3e38], "size": [4, 3]})",
       "scene.json: terrain.cell_size: times the 2 cells along z is beyond float range"},
      {R"("terrain": {"function": "flat", "cell_size": 1e36, "origin": [3e38, 0, 0]})",
       "scene.json: terrain.origin: plus the terrain's x extent is beyond float range"},
      {R"("terrain": {"function": "bowl", "coefficient": 1e38})",
       "scene.json: terrain.coefficient: hail: Heightmap::from_function"},
      {R"("terrain": {"heightmap": "none.pgm", "height_scale": 1e35})",
       "scene.json: terrain.height_scale: times the largest sample (65535), plus height_offset and origin.y, is beyond "
       "float range"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(scene_text(c.body));
    INFO("body: " << c.body << "\nmessage: " << message);
    CHECK(message.find(c.expected) == 0);
  }
  // A file's size is known once it is read: checked before the terrain is built.
  const auto dir = fresh_temp_dir("extent");
  {
    std::ofstream pgm(dir / "map.pgm");
    pgm << "P2 300 2 255\n";
    for (int k = 0; k < 600; ++k) pgm << "1 ";
  }
  try {
    (void)parse_scene_text(scene_text(R"("terrain": {"heightmap": "map.pgm", "cell_size": 3e36})"), "scene.json", {},
                           dir.string());
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find(
              "scene.json: terrain.cell_size: times the 299 cells along x is beyond float range") == 0);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene files: sphere counts and terrain sizes are checked against the memory limit first", "[scene_file]") {
  SceneOverrides limited;
  limited.memory_limit = {1e9, "1.00 GB (test)"};
  // Used to end in std::bad_alloc for 1e8 spheres: --spheres was checked, the file's counts not.
  const std::string many = error_of(scene_text(R"("spheres": [{"lattice": {"count": 100000000}}])"), limited);
  INFO(many);
  CHECK(many.find("scene.json: spheres: making 100000000 spheres needs about 210 GB (2100 bytes a sphere") == 0);
  CHECK(many.find("over the memory limit of 1.00 GB (test); --memory-limit GB sets it, 0 turns the check off") !=
        std::string::npos);
  // Every generator counts: two lattices each within the limit, together over it.
  const std::string two = error_of(
      scene_text(
          R"("spheres": [{"lattice": {"count": 300000}}, {"random": {"count": 300000, "seed": 1, "box_min": [0, 0, 0], "box_max": [1, 1, 1]}}])"),
      limited);
  CHECK(two.find("scene.json: spheres: making 600000 spheres needs about 1.26 GB") == 0);
  // --spheres replaces the count, and is checked the same way.
  SceneOverrides resized = limited;
  resized.spheres = 1'000'000;
  CHECK(error_of(scene_text(R"("spheres": [{"lattice": {"count": 4}}])"), resized).find("making 1000000 spheres") !=
        std::string::npos);
  // Used to allocate for 12 s and die: a 65,536 x 4,096 terrain.
  const std::string terrain =
      error_of(scene_text(R"("terrain": {"function": "flat", "size": [65536, 4096]})"), limited);
  CHECK(
      terrain.find(
          "scene.json: terrain.size: a 65536 x 4096 terrain needs about 161 GB (600 bytes a cell while it is built)") ==
      0);
  // Too many spheres are refused before the terrain is built (it alone would be refused too).
  CHECK(error_of(scene_text(R"("terrain": {"function": "flat", "size": [65536, 4096]},
                             "spheres": [{"lattice": {"count": 100000000}}])"),
                 limited)
            .find("scene.json: spheres: making 100000000 spheres") == 0);
  // The terrain counts against the spheres' share.
  const std::string both = error_of(scene_text(R"("terrain": {"function": "flat", "size": [1024, 1024]},
                                                  "spheres": [{"lattice": {"count": 300000}}])"),
                                    limited);
  CHECK(both.find("scene.json: spheres: making 300000 spheres needs about 1.26 GB (2100 bytes a sphere, the most "
                  "measured: docs/benchmarks.md, Memory; the terrain 628 MB)") == 0);
  // Within the limit: built.
  CHECK(error_of(scene_text(R"("spheres": [{"lattice": {"count": 1000}}])"), limited) == "(no error)");

  // A PGM's size is in the file: the loader refuses a header over what the limit allows.
  const auto dir = fresh_temp_dir("memory");
  {
    std::ofstream pgm(dir / "big.pgm", std::ios::binary);
    pgm << "P5 300 300 255\n" << std::string(300 * 300, '\1');
  }
  SceneOverrides small;
  small.memory_limit = {1e7, "10.0 MB (test)"};
  try {
    (void)parse_scene_text(scene_text(R"("terrain": {"heightmap": "big.pgm"})"), "scene.json", small, dir.string());
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(message.find("scene.json: terrain.heightmap: hail: ") == 0);
    CHECK(message.find("300 x 300 = 90000 vertices exceeds HeightmapParams::max_vertices = 16666") !=
          std::string::npos);
    CHECK(message.find("the memory limit of 10.0 MB (test) allows 16666 vertices; --memory-limit GB sets it") !=
          std::string::npos);
  }
  CHECK(parse_scene_text(scene_text(R"("terrain": {"heightmap": "big.pgm"})"), "scene.json", limited, dir.string())
            .has_terrain);
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene files: a dt the World would split into too many substeps is refused by name", "[scene_file]") {
  // World::step's contract (check_step): at most max_substeps (256) substeps of max_substep
  // (0.05 s) each. "dt": 100000 with 1,000 spheres used to make no visible progress for minutes.
  const std::string huge = error_of(scene_text(R"("dt": 100000)"));
  CHECK(huge.find("scene.json: dt: ") == 0);
  CHECK(huge.find("max_substeps") != std::string::npos);
  // The time scale counts: 1/60 s at time scale 1000 needs 334 substeps.
  CHECK(error_of(scene_text(R"("dt": 0.0166666675, "settings": {"time_scale": 1000})")).find("scene.json: dt: ") == 0);
  CHECK(error_of(scene_text(R"("dt": 0.0166666675, "settings": {"time_scale": 100})")) == "(no error)");
  // A --dt from the command line is judged the same way, and named as the flag.
  CHECK(error_of(scene_text(R"("settings": {"time_scale": 2})"), {.dt = 10.0f}).find("scene.json: --dt: ") == 0);
  CHECK(error_of(scene_text(""), {.dt = 10.0f}) == "(no error)");  // 200 substeps
  // A step too short to move anything (World::step's kMinStep): "dt": 1e-40, or a time scale
  // of 1e-37, turned every sphere NaN.
  for (const char* body : {R"("dt": 1e-40)", R"("dt": 0.0166666675, "settings": {"time_scale": 1e-37})"}) {
    INFO(body);
    const std::string tiny = error_of(scene_text(body));
    CHECK(tiny.find("scene.json: dt: ") == 0);
    CHECK(tiny.find("kMinStep") != std::string::npos);
  }
}

TEST_CASE("scene files: iteration counts take the World's one range", "[scene_file]") {
  // 2147483647 resting passes were accepted (8 spheres, 2 steps took over 20 s); the command
  // line capped --resting at 1000. Now both refuse past kMaxIterations.
  for (const char* setting : {R"("resting_iterations": 2147483647)", R"("depenetration_iterations": 1001)",
                              R"("collision_iterations": 5000)", R"("soft_step": {"substeps": 100000})"}) {
    INFO(setting);
    const std::string refused = error_of(scene_text(std::string(R"("settings": {)") + setting + "}"));
    CHECK(refused.find("scene.json") == 0);
    CHECK(refused.find("must be <= " + std::to_string(hail::kMaxIterations)) != std::string::npos);
  }
  CHECK(error_of(scene_text(R"("settings": {"resting_iterations": 1000})")) == "(no error)");
}

namespace {

/// The mass the format documents for a density: 4/3 pi r^3 density, in double, rounded once.
float mass_from(float density, float radius) {
  const double r = radius;
  return static_cast<float>(4.0 / 3.0 * 3.14159265358979323846 * double(density) * r * r * r);
}

/// World keeps 1 / mass, rounded: compare it with 1 / the mass expected.
float inverse_mass_of_sphere(const Scene& scene, std::size_t k) {
  const auto slot = static_cast<std::size_t>(scene.world->slot_of(scene.ids[k]));
  return scene.world->soa().inv_mass[slot];
}

float radius_of_sphere(const Scene& scene, std::size_t k) {
  return scene.world->soa().radius[static_cast<std::size_t>(scene.world->slot_of(scene.ids[k]))];
}

}  // namespace

TEST_CASE("scene files: a density instead of a mass makes each sphere's mass from its radius",
          "[scene_file][density]") {
  const Scene scene = parse_scene_text(scene_text(R"("material": {"radius": 0.5, "density": 1000},
      "spheres": [
        {"list": [{"position": [0, 0, 0]}, {"position": [3, 0, 0], "radius": 2}, {"position": [9, 0, 0], "mass": 7},
                  {"position": [15, 0, 0], "radius": 0.1, "density": 7800}]},
        {"lattice": {"count": 2, "spacing": 3, "centre": [0, 10, 0], "radius": 1}},
        {"lattice": {"count": 1, "centre": [0, 20, 0], "radius": 1, "mass": 2}},
        {"random": {"count": 20, "seed": 3, "box_min": [-50, 30, -50], "box_max": [50, 60, 50], "radius": [0.1, 1]}},
        {"random": {"count": 20, "seed": 4, "box_min": [-50, 70, -50], "box_max": [50, 90, 50], "radius": [0.1, 1],
                    "density": [500, 2000]}}])"),
                                       "density.json");
  REQUIRE(scene.ids.size() == 47);
  CHECK(inverse_mass_of_sphere(scene, 0) == 1.0f / mass_from(1000, 0.5f));  // the material's density and radius
  CHECK(1.0f / inverse_mass_of_sphere(scene, 0) == Approx(523.599));
  CHECK(inverse_mass_of_sphere(scene, 1) == 1.0f / mass_from(1000, 2));     // the material's density, its own radius
  CHECK(inverse_mass_of_sphere(scene, 2) == 1.0f / 7.0f);                   // a mass of its own instead
  CHECK(inverse_mass_of_sphere(scene, 3) == 1.0f / mass_from(7800, 0.1f));  // a density of its own
  CHECK(inverse_mass_of_sphere(scene, 4) == 1.0f / mass_from(1000, 1));
  CHECK(inverse_mass_of_sphere(scene, 5) == 1.0f / mass_from(1000, 1));
  CHECK(inverse_mass_of_sphere(scene, 6) == 1.0f / 2.0f);
  for (std::size_t k = 7; k < 27; ++k)
    CHECK(inverse_mass_of_sphere(scene, k) == 1.0f / mass_from(1000, radius_of_sphere(scene, k)));

  // A drawn density takes the mass's place in the sequence: x, y, z, radius, density, speed.
  std::mt19937_64 rng(4);
  const auto between = [&](float lo, float hi) { return lo + (hi - lo) * hail::bench::unit_float(rng); };
  (void)between(-50, 50), (void)between(70, 90), (void)between(-50, 50);
  const float radius = between(0.1f, 1);
  const float density = between(500, 2000);
  CHECK(radius_of_sphere(scene, 27) == radius);
  CHECK(inverse_mass_of_sphere(scene, 27) == 1.0f / mass_from(density, radius));
  int distinct_densities = 0;
  for (std::size_t k = 28; k < 47; ++k) {
    const float volume = 4.0f / 3.0f * 3.14159265f * std::pow(radius_of_sphere(scene, k), 3.0f);
    const float d = 1.0f / inverse_mass_of_sphere(scene, k) / volume;
    CHECK(d >= 499.0f);
    CHECK(d <= 2001.0f);
    distinct_densities += std::fabs(d - 1000.0f) > 10.0f;
  }
  CHECK(distinct_densities > 10);
}

TEST_CASE("scene files: mass and density together, or a density out of range, are refused by name",
          "[scene_file][density]") {
  const std::string list_head = R"("spheres": [{"list": [)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {scene_text(list_head + R"({"position": [0, 0, 0], "mass": 1, "density": 1000}]}])"),
       "scene.json: spheres[0].list[0]: give \"mass\" or \"density\" (mass = density * 4/3 pi radius^3), not both"},
      {scene_text(R"("material": {"mass": 1, "density": 1000})"), "scene.json: material: give \"mass\" or \"density\""},
      {scene_text(R"("spheres": [{"lattice": {"count": 2, "mass": 1, "density": 1}}])"),
       "scene.json: spheres[0].lattice: give \"mass\" or \"density\""},
      {scene_text(
           R"("spheres": [{"random": {"count": 2, "seed": 1, "box_min": [0, 0, 0], "box_max": [1, 1, 1], "mass": 1, "density": 1}}])"),
       "scene.json: spheres[0].random: give \"mass\" or \"density\""},
      {scene_text(list_head + R"({"position": [0, 0, 0], "density": 0}]}])"),
       "scene.json: spheres[0].list[0].density: must be > 0, got 0"},
      {scene_text(list_head + R"({"position": [0, 0, 0], "density": -5}]}])"),
       "scene.json: spheres[0].list[0].density: must be > 0, got -5"},
      {scene_text(list_head + R"({"position": [0, 0, 0], "density": "heavy"}]}])"),
       "scene.json: spheres[0].list[0].density: must be a number, got string \"heavy\""},
      {scene_text(list_head + R"({"position": [0, 0, 0], "density": 1e39}]}])"),
       "scene.json: spheres[0].list[0].density: must be a finite number within float range"},
      {scene_text(list_head + R"({"position": [0, 0, 0], "radius": 1000, "density": 1e6}]}])"),
       "scene.json: spheres[0].list[0].density: density 1e+06 kg/m^3 and radius 1000 m give a mass of 4.18879e+15 kg, "
       "more than "
       "the World's limit of 1e12 kg (kMaxSphereMass)"},
      {scene_text(list_head + R"({"position": [0, 0, 0], "radius": 1e-5, "density": 1e-3}]}])"),
       "give a mass of 4.18879e-18 kg, less than the World's limit of 1e-12 kg (kMinSphereMass)"},
      // Inherited from the material, the message names the sphere that makes it too heavy.
      {scene_text(
           R"("material": {"density": 1e6}, "spheres": [{"list": [{"position": [0, 0, 0]}, {"position": [9, 0, 0], "radius": 1000}]}])"),
       "scene.json: spheres[0].list[1]: density 1e+06 kg/m^3 and radius 1000 m give a mass of"},
      // A random generator's extremes bound every sphere it draws: refused before any is made.
      {scene_text(R"("spheres": [{"random": {"count": 2, "seed": 1, "box_min": [0, 0, 0], "box_max": [1, 1, 1],
                                              "radius": [1, 1000], "density": [1, 1e6]}}])"),
       "scene.json: spheres[0].random.density: density 1e+06 kg/m^3 and radius 1000 m give a mass of"},
      {scene_text(
           R"("spheres": [{"random": {"count": 2, "seed": 1, "box_min": [0, 0, 0], "box_max": [1, 1, 1], "density": [2, 1]}}])"),
       "scene.json: spheres[0].random.density: min must be <= max"},
      {scene_text(
           R"("spheres": [{"random": {"count": 2, "seed": 1, "box_min": [0, 0, 0], "box_max": [1, 1, 1], "radius_distribution": "log"}}])"),
       "scene.json: spheres[0].random.radius_distribution: must be one of \"uniform\", \"log-uniform\", got \"log\""},
      {scene_text(R"("spheres": [{"list": [{"position": [0, 0, 0], "radius_distribution": "uniform"}]}])"),
       "scene.json: spheres[0].list[0]: unknown key \"radius_distribution\""},
  };
  for (const auto& [text, expected] : cases) {
    const std::string message = error_of(text);
    INFO("file: " << text << "\nmessage: " << message);
    CHECK(message.find(expected) != std::string::npos);
  }
  // A static sphere has no mass: any density is accepted for it.
  CHECK(error_of(
            scene_text(list_head + R"({"position": [0, 0, 0], "radius": 1000, "density": 1e6, "static": true}]}])")) ==
        "(no error)");
}

TEST_CASE("scene files: log-uniform radii: every decade alike, drawn in the radius's place", "[scene_file][density]") {
  const Scene scene = parse_scene_text(scene_text(R"("spheres": [{"random": {"count": 2000, "seed": 11,
      "box_min": [-500, 0, -500], "box_max": [500, 500, 500], "radius": [0.05, 5], "radius_distribution": "log-uniform",
      "density": 1000}}])"),
                                       "log.json");
  REQUIRE(scene.ids.size() == 2000);
  std::size_t below_half = 0, below_tenth_of_max = 0;
  float smallest = 10, largest = 0;
  for (std::size_t k = 0; k < scene.ids.size(); ++k) {
    const float r = radius_of_sphere(scene, k);
    smallest = std::min(smallest, r), largest = std::max(largest, r);
    below_half += r < 0.5f;  // the geometric middle of [0.05, 5]: half of a log-uniform draw
    below_tenth_of_max += r < 0.05f * std::pow(10.0f, 1.5f);
    CHECK(inverse_mass_of_sphere(scene, k) == 1.0f / mass_from(1000, r));
  }
  CHECK(smallest >= 0.05f);
  CHECK(largest <= 5.0f);
  CHECK(smallest < 0.06f);
  CHECK(largest > 4.0f);
  // Uniform radii would put 9% below 0.5 m; log-uniform puts half there (and three quarters
  // below 10^1.5 min), within a few percent for 2,000 draws.
  CHECK(below_half > 900);
  CHECK(below_half < 1100);
  CHECK(below_tenth_of_max > 1400);
  CHECK(below_tenth_of_max < 1600);

  // The first sphere's radius is min (max/min)^u with u the fourth draw, in double, rounded once.
  std::mt19937_64 rng(11);
  for (int k = 0; k < 3; ++k) (void)hail::bench::unit_float(rng);
  const double u = hail::bench::unit_float(rng);
  CHECK(radius_of_sphere(scene, 0) == static_cast<float>(0.05f * std::exp(u * std::log(5.0 / double(0.05f)))));

  // One value: the draw is made (the sequence does not shift) and gives that value.
  const Scene one = parse_scene_text(scene_text(R"("spheres": [{"random": {"count": 3, "seed": 11, "box_min": [0, 0, 0],
      "box_max": [9, 9, 9], "radius": 0.3, "radius_distribution": "log-uniform"}}])"),
                                     "one.json");
  const Scene uniform =
      parse_scene_text(scene_text(R"("spheres": [{"random": {"count": 3, "seed": 11, "box_min": [0, 0, 0],
      "box_max": [9, 9, 9], "radius": 0.3}}])"),
                       "uniform.json");
  for (std::size_t k = 0; k < 3; ++k) {
    CHECK(radius_of_sphere(one, k) == 0.3f);
    CHECK(one.world->position(one.ids[k]) == uniform.world->position(uniform.ids[k]));
  }
}

TEST_CASE("scene files: wide-mix-rain: radii over two decades at one density, over terrain-rain's terrain",
          "[scene_file][density]") {
  const Scene scene = hail::bench::load_scene_file(kScenes + "wide-mix-rain.json", {.spheres = 500});
  REQUIRE(scene.ids.size() == 500);
  CHECK(scene.has_terrain);
  float smallest = 10, largest = 0;
  for (std::size_t k = 0; k < scene.ids.size(); ++k) {
    const float r = radius_of_sphere(scene, k);
    smallest = std::min(smallest, r), largest = std::max(largest, r);
    CHECK(inverse_mass_of_sphere(scene, k) == 1.0f / mass_from(1000, r));
  }
  CHECK(smallest < 0.07f);
  CHECK(largest > 3.5f);
}

TEST_CASE("scene files: a function terrain keeps its shape when its origin moves", "[scene_file][far_origin]") {
  // The function is of the place relative to the terrain's origin, so a terrain moved out to
  // 1e4 or 1e5 m has bit for bit the heights it has at the origin (and its vertices the moved
  // places). Evaluated at world x, z it showed another stretch of terrain-rain's waves and, at
  // 1e5 m where floats are 7.8 mm apart, a ragged bowl.
  for (const char* function : {R"("terrain-rain")", R"("bowl", "coefficient": 0.002)"}) {
    auto heights_at = [&](const std::string& origin) {
      const Scene scene =
          parse_scene_text(scene_text(std::string(R"("terrain": {"function": )") + function +
                                      R"(, "size": [64, 48], "cell_size": [1, 0.5], "origin": )" + origin + "}"),
                           "scene.json");
      const hail::Heightmap& h = scene.world->terrain()->heightmap();
      return std::vector<float>(h.heights().begin(), h.heights().end());
    };
    const std::vector<float> home = heights_at("[0, 0, 0]");
    for (const char* far : {"[10000, 0, 10000]", "[100000, 0, -100000]"}) {
      CAPTURE(function, far);
      CHECK(heights_at(far) == home);
    }
    CHECK(heights_at("[0, 2, 0]")[7] == home[7] + 2.0f);
  }
  const Scene far = parse_scene_text(
      scene_text(R"("terrain": {"function": "terrain-rain", "size": [64, 48], "origin": [100000, 0, -100000]})"),
      "scene.json");
  CHECK(far.min_x == 100000.0f);
  CHECK(far.max_z == -100000.0f + 47.0f);
  CHECK(far.ground_height(100000.0f + 5.0f, -100000.0f + 7.0f) ==
        Approx(hail::bench::terrain_rain_height(5.0f, 7.0f)).margin(1e-5));
}

namespace {

/// load_scene_file(path)'s error message, from another thread: "(timed out)" when it has not
/// ended within `limit`. A regression that blocks (opening a FIFO) or reads without end
/// (/dev/zero) then fails the test instead of hanging it; the thread is left behind.
std::string load_error_within(const std::string& path, std::chrono::seconds limit) {
  return hail::testing::thrown_within<std::invalid_argument>(limit,
                                                             [path] { (void)hail::bench::load_scene_file(path); })
      .value_or("(timed out)");
}

}  // namespace

TEST_CASE("scene files: a long list of objects is read whole before its refusal", "[scene_file]") {
  // A list of 200,000 objects parses to the end, to the unknown key after it. How long that
  // takes, against plain json::parse, is measured in hail-micro (scene_file/reader: linear,
  // where nlohmann's callback parser took 79 s for 400,000), never asserted here.
  const std::string text = scene_of_many_spheres(200'000);
  const auto document = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  REQUIRE(document["spheres"][0]["list"].size() == 200'000);
  CHECK(error_of(text) ==
        "scene.json: unknown key \"refused_after_the_parse\" at top level (known: format, version, "
        "description, gravity, dt, steps, threads, settings, terrain, planes, meshes, material, spheres)");
}

TEST_CASE("scene files: only a regular file is read, and no more than its size", "[scene_file]") {
  using std::chrono::seconds;
  // /dev/zero was read until memory ran out.
  CHECK(load_error_within("/dev/zero", seconds(10)) ==
        "/dev/zero: is a character device, not a scene file (write the scene to a file)");
  const auto dir = fresh_temp_dir("not-regular");
#if defined(__linux__)
  // Opening a FIFO waits for a writer, which may never come: `--scene <(generate)` is refused.
  const std::string fifo = (dir / "scene.json").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string fifo_error = load_error_within(fifo, seconds(10));
  CHECK(fifo_error == fifo + ": is a pipe (FIFO), not a scene file (write the scene to a file)");
  if (fifo_error == "(timed out)") {  // let the blocked open go on, so that the thread can end
    const int writer = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (writer >= 0) ::close(writer);
  }
#endif
  const std::string folder = (dir / "folder.json").string();
  std::filesystem::create_directory(folder);
  CHECK(load_error_within(folder, seconds(10)) == folder + ": is a directory, not a scene file");
  // A symbolic link to a regular file is that file.
  const auto target = dir / "real.json";
  std::ofstream(target) << scene_text(R"("spheres": [{"list": [{"position": [0, 0, 0]}]}])");
  std::filesystem::create_symlink(target, dir / "link.json");
  CHECK(hail::bench::load_scene_file((dir / "link.json").string()).world->sphere_count() == 1);
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene files: the text and its parsed document are checked against the memory limit", "[scene_file]") {
  SceneOverrides limited;
  limited.memory_limit = {1e6, "1.00 MB (test)"};
  // 20,000 spheres are 0.5 MB of text but about 7 MB once parsed: refused where the parse
  // crosses the limit, before the rest of the document is built.
  const std::string document = error_of(scene_of_many_spheres(20'000), limited);
  INFO(document);
  CHECK(document.find("scene.json: spheres[0].list[") == 0);
  CHECK(document.find(": the parsed document needs about 1.00 MB (") != std::string::npos);
  CHECK(document.find("JSON values so far") != std::string::npos);
  CHECK(document.find("over the memory limit of 1.00 MB (test); --memory-limit GB sets it, 0 turns the check off") !=
        std::string::npos);
  // The text alone over the limit: refused before the parse.
  SceneOverrides tiny;
  tiny.memory_limit = {1000, "1.00 kB (test)"};
  const std::string text = error_of(scene_of_many_spheres(100), tiny);
  INFO(text);
  CHECK(text.find("scene.json: the text needs about 2.") == 0);
  CHECK(text.find("over the memory limit of 1.00 kB (test); --memory-limit GB sets it") != std::string::npos);
  // A file is refused by its size, before it is read.
  const auto dir = fresh_temp_dir("memory-text");
  const std::string path = (dir / "big.json").string();
  std::ofstream(path) << scene_of_many_spheres(100);
  try {
    (void)hail::bench::load_scene_file(path, tiny);
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find(path + ": the text needs about 2.") == 0);
  }
  // Within the limit, or with the check off: built.
  CHECK(error_of(scene_text(R"("spheres": [{"list": [{"position": [0, 0, 0]}]}])"), limited) == "(no error)");
  CHECK(error_of(scene_of_many_spheres(20'000)).find("refused_after_the_parse") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene files: values the World refuses are named by file and field", "[scene_file]") {
  // These came from World::set_terrain, World::add_plane and World::add_sphere without the file
  // or the field (planes with std::to_string's 39 digits and "0.000010").
  const std::string cell = error_of(scene_text(R"("terrain": {"function": "flat", "cell_size": [1, 1e-30]})"));
  INFO(cell);
  CHECK(cell.find("scene.json: terrain.cell_size: hail: terrain reaches 255 m from the origin") == 0);
  CHECK(cell.find("more than its cell size 1e-30 m") != std::string::npos);
  const std::string raised =
      error_of(scene_text(R"("terrain": {"function": "terrain-rain", "cell_size": 1e-30, "origin": [0, 1, 0]})"));
  INFO(raised);
  CHECK(raised.find("scene.json: terrain.cell_size: hail: terrain reaches 1 m from the origin") == 0);
  // Without a cell_size, the origin (too far out for the default 1 m cells).
  CHECK(error_of(scene_text(R"("terrain": {"function": "flat", "origin": [1e7, 0, 0]})"))
            .find("scene.json: terrain.origin: hail: terrain reaches 1.00003e+07 m from the origin") == 0);

  const std::string plane = error_of(scene_text(R"("planes": [{"normal": [0, 1e-5, 0], "offset": 1e38}])"));
  INFO(plane);
  CHECK(plane.find("scene.json: planes[0].offset: hail: plane offset / |normal| must be finite") == 0);
  CHECK(plane.find("(offset 1e+38 m, |normal| 1e-05)") != std::string::npos);
  const std::string second =
      error_of(scene_text(R"("planes": [{"normal": [0, 1, 0]}, {"normal": [1e-5, 0, 0], "offset": -1e38}])"));
  CHECK(second.find("scene.json: planes[1].offset: ") == 0);

  // A sphere by the generator that made it: a list's element by its path.
  const std::string heavy = error_of(scene_text(
      R"("spheres": [{"lattice": {"count": 2}}, {"list": [{"position": [5, 0, 0]}, {"position": [9, 0, 0], "mass": 1e13}]}])"));
  INFO(heavy);
  CHECK(heavy.find("scene.json: spheres[1].list[1]: hail: ") == 0);
  CHECK(heavy.find("mass") != std::string::npos);
  const std::string fast = error_of(scene_text(
      R"("spheres": [{"list": [{"position": [5, 0, 0]}]}, {"random": {"count": 3, "seed": 1, "box_min": [0, 0, 0], "box_max": [1, 1, 1], "speed": 2e6}}])"));
  INFO(fast);
  CHECK(fast.find("scene.json: spheres[1].random: sphere 0 of this generator: hail: ") == 0);
}

TEST_CASE("scene files: every setting of the settings table is a key, read with its range", "[scene_file][settings]") {
  // The "settings" object is read from include/hail/settings_table.h: each setting (but gravity
  // and threads, top-level keys) given its default reads back as that default, and each value
  // past a number's range is refused naming the key.
  const hail::WorldSettings defaults;
  std::size_t keys = 0;
  hail::for_each_setting(defaults, [&](const auto& value, const hail::SettingSpec& spec) {
    using T = std::remove_cvref_t<decltype(value)>;
    const std::string name = spec.name;
    if constexpr (std::is_same_v<T, hail::Vec3>) return;  // gravity, a top-level key
    if (name == "threads") return;                        // a top-level key
    INFO(name);
    std::string json_value;
    if constexpr (std::is_same_v<T, bool>) {
      json_value = value ? "false" : "true";  // the other one: a real read
    } else if constexpr (std::is_enum_v<T>) {
      const std::string values = spec.values;
      json_value = "\"" + values.substr(values.rfind('|') + 1) + "\"";  // the last name
    } else if constexpr (std::is_arithmetic_v<T>) {
      char text[32];
      std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
      json_value = text;
    }
    const std::size_t dot = name.find('.');
    const std::string body = dot == std::string::npos ? "\"" + name + "\": " + json_value
                                                      : "\"" + name.substr(0, dot) + "\": {\"" + name.substr(dot + 1) +
                                                            "\": " + json_value + "}";
    const std::string text = scene_text(R"("settings": {)" + body + "}");
    CHECK(error_of(text) == "(no error)");
    const Scene scene = parse_scene_text(text, "scene.json");
    hail::for_each_setting(scene.world->settings(), [&](const auto& read, const hail::SettingSpec& read_spec) {
      using R = std::remove_cvref_t<decltype(read)>;
      if constexpr (std::is_same_v<R, T>)
        if (read_spec.name == name) {
          if constexpr (std::is_same_v<T, bool>)
            CHECK(read != value);
          else if constexpr (std::is_enum_v<T>)
            CHECK(static_cast<std::size_t>(read) + 1 == hail::setting_value_count(spec));
          else
            CHECK(read == value);
        }
    });
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      if (spec.min > -1e30) {  // just below the bottom, or at an open one
        char below[48];
        std::snprintf(below, sizeof below, "%.9g",
                      spec.min_open ? spec.min : spec.min - (std::is_integral_v<T> ? 1.0 : 1e-3));
        const std::string past = dot == std::string::npos ? "\"" + name + "\": " + below
                                                          : "\"" + name.substr(0, dot) + "\": {\"" +
                                                                name.substr(dot + 1) + "\": " + below + "}";
        CHECK(error_of(scene_text(R"("settings": {)" + past + "}")).find("settings." + name + ": must be") !=
              std::string::npos);
      }
    }
    ++keys;
  });
  CHECK(keys >= 34);
}

TEST_CASE("scene files: meshes load from their files, placed, and fail by field", "[scene]") {
  const Scene funnel = hail::bench::load_scene_file(kScenes + "funnel.json", {.spheres = 200});
  REQUIRE(funnel.world->mesh_count() == 2);
  for (int k = 0; k < 120; ++k) funnel.world->step(funnel.dt);
  for (const hail::SphereId id : funnel.ids) CHECK(funnel.world->position(id).y() > 0.0f);  // none through the floor

  const std::string meshes_dir = std::string(HAIL_SOURCE_DIR) + "/data/meshes/";
  const Scene placed = hail::bench::parse_scene_text(
      R"({"format": "hail-scene", "version": 1, "gravity": [0, -10, 0],
          "meshes": [{"file": "floor.obj", "position": [0, 2, 0], "rotation": {"axis": [0, 1, 0], "degrees": 30}}],
          "spheres": [{"list": [{"position": [0.5, 3, 0.5], "radius": 0.5}]}]})",
      "scene.json", {}, meshes_dir);
  for (int k = 0; k < 120; ++k) placed.world->step(1.0f / 60);
  CHECK(placed.world->position(placed.ids[0]).y() == Approx(2.5f).margin(0.005f));

  CHECK_THAT(error_of(R"({"format": "hail-scene", "version": 1, "meshes": [{"file": "no-such.obj"}]})"),
             Catch::Matchers::StartsWith("scene.json: meshes[0].file:") && Catch::Matchers::Contains("no-such.obj"));
  CHECK_THAT(error_of(R"({"format": "hail-scene", "version": 1, "meshes": [{"position": [0, 0, 0]}]})"),
             Catch::Matchers::Contains("meshes[0]") && Catch::Matchers::Contains("\"file\""));
  CHECK_THAT(error_of(R"({"format": "hail-scene", "version": 1, "meshes": [{"file": "a.obj", "scale": -1}]})"),
             Catch::Matchers::Contains("meshes[0].scale"));
}
