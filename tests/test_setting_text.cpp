// Settings set from text by their table name (scenes/setting_text.h: `hail-bench run --set
// NAME=VALUE`): every kind of setting reads, a wrong name or value is refused naming it, and a
// built-in scene and a scene file both take the assignments after their own settings.

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "catch.h"
#include "hail/settings_table.h"
#include "scenes/scene_file.h"
#include "scenes/scene_run.h"
#include "scenes/scenes.h"
#include "scenes/setting_text.h"

using namespace hail;
using hail::bench::set_setting;

namespace {

std::string refusal(const std::string& assignment) {
  WorldSettings s;
  try {
    set_setting(s, assignment);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("A setting is set from text by its table name, each kind", "[settings][scene_file]") {
  WorldSettings s;
  set_setting(s, "sleep_time=1.5");
  set_setting(s, "soft_step.substeps=8");
  set_setting(s, "solver=soft");
  set_setting(s, "pair_search=grid");
  set_setting(s, "rotation=off");
  set_setting(s, "gravity=0,-1.62,0");
  set_setting(s, "shock_mass_ratio=inf");
  set_setting(s, "solver_tile_spheres=0");
  CHECK(s.sleep_time == 1.5f);
  CHECK(s.soft_step.substeps == 8);
  CHECK(s.solver == Solver::SoftStep);
  CHECK(s.pair_search == PairSearch::Grid);
  CHECK_FALSE(s.rotation);
  CHECK(s.gravity == Vec3(0.0f, -1.62f, 0.0f));
  CHECK(std::isinf(s.shock_mass_ratio));
  CHECK(s.solver_tile_spheres == 0);
  // Every name of the table is known (an empty value is refused as a value, not as a name).
  std::size_t names = 0;
  const WorldSettings defaults;
  for_each_setting(defaults, [&](const auto&, const SettingSpec& spec) {
    ++names;
    const std::string refused = refusal(std::string(spec.name) + "=");
    CHECK(refused.find("takes") != std::string::npos);
  });
  CHECK(names > 30);
}

TEST_CASE("A wrong setting name or value is refused, naming it", "[settings][scene_file]") {
  CHECK_THAT(refusal("nosuch=1"), Catch::Contains("no setting 'nosuch'") && Catch::Contains("sleep_time"));
  CHECK_THAT(refusal("sleep_time"), Catch::Contains("give NAME=VALUE"));
  CHECK_THAT(refusal("=3"), Catch::Contains("give NAME=VALUE"));
  CHECK_THAT(refusal("rotation=maybe"), Catch::Contains("rotation takes on, off, true or false"));
  CHECK_THAT(refusal("solver=jacobi"), Catch::Contains("solver takes one of passes|soft"));
  CHECK_THAT(refusal("resting_iterations=2.5"), Catch::Contains("a whole number"));
  CHECK_THAT(refusal("resting_iterations=99999999999"), Catch::Contains("a whole number in [0, 1000]"));
  CHECK_THAT(refusal("solver_tile_spheres=-1"), Catch::Contains("a whole number"));
  CHECK_THAT(refusal("gravity=0,1"), Catch::Contains("three numbers"));
  CHECK_THAT(refusal("time_scale=fast"), Catch::Contains("a number"));
}

TEST_CASE("Built-in scenes and scene files take --set after their own settings", "[settings][scene_file]") {
  bench::SceneParams params;
  params.spheres = 50;
  params.threads = 1;
  params.settings.resting_iterations = 3;
  params.set = {"resting_iterations=5", "sleep_time=2", "resting_iterations=6"};  // the last wins
  bench::Scene built = bench::find_scene("terrain-rain").build(params);
  CHECK(built.world->settings().resting_iterations == 6);
  CHECK(built.world->settings().sleep_time == 2.0f);

  const std::string text = R"({"format": "hail-scene", "version": 1, "settings": {"sleep_time": 4, "solver": "soft"}})";
  bench::SceneOverrides overrides;
  overrides.set = {"sleep_time=0.25"};
  bench::Scene from_file = bench::parse_scene_text(text, "scene.json", overrides);
  CHECK(from_file.world->settings().sleep_time == 0.25f);
  CHECK(from_file.world->settings().solver == Solver::SoftStep);  // the file's, untouched
  overrides.set = {"sleep_time=fast"};
  CHECK_THROWS_WITH(bench::parse_scene_text(text, "scene.json", overrides),
                    Catch::Contains("scene.json") && Catch::Contains("sleep_time takes a number"));
}

TEST_CASE("Every setting's text reads back exactly", "[settings][scene_file]") {
  // setting_text is how hail-bench run hands its flags to a scene file: it must lose nothing.
  WorldSettings odd;
  odd.gravity = Vec3(0.1f, -9.80665f, 1.0f / 3.0f);
  odd.sleep_time = 0.123456789f;
  odd.warm_start_factor = 1.0f / 7.0f;
  odd.solver = Solver::SoftStep;
  odd.pair_search = PairSearch::SweepAndPrune;
  odd.rotation = false;
  odd.solver_tile_spheres = 4096;
  for (const WorldSettings& original : {WorldSettings{}, odd}) {
    for_each_setting(original, [&](const auto& value, const SettingSpec& spec) {
      INFO(spec.name << " = " << bench::setting_text(original, spec.name));
      WorldSettings copy;
      set_setting(copy, spec.name, bench::setting_text(original, spec.name));
      for_each_setting(copy, [&](const auto& read, const SettingSpec& read_spec) {
        if constexpr (std::is_same_v<std::remove_cvref_t<decltype(read)>, std::remove_cvref_t<decltype(value)>>)
          if (read_spec.name == std::string(spec.name)) CHECK(read == value);
      });
    });
  }
}
