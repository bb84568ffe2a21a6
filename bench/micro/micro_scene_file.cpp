// Parsing a scene file's sphere list: the reader (parse_scene_text) against plain json::parse of
// the same text, at doubling list lengths. The reader must scale as json::parse does, linearly
// (benchmark's complexity fit says so): nlohmann's callback parser, which it used to use,
// looked through the whole parent array after every element, and 400,000 objects took 79 s.
#include <stdexcept>
#include <string>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "scenes/scene_file.h"

namespace hail::micro {
namespace {

/// A scene whose one list holds `count` spheres, refused after the parse (an unknown top-level
/// key), so that only the parse is timed, not building the spheres.
std::string scene_of_many_spheres(std::size_t count) {
  std::string text = R"({"format": "hail-scene", "version": 1, "spheres": [{"list": [)";
  text.reserve(text.size() + 26 * count + 40);
  for (std::size_t k = 0; k < count; ++k)
    text += k == 0 ? R"({"position": [1, 2, 3]})" : R"(, {"position": [1, 2, 3]})";
  return text + R"(]}], "refused_after_the_parse": 1})";
}

void scene_reader(benchmark::State& state) {
  const std::string text = scene_of_many_spheres(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    try {
      (void)bench::parse_scene_text(text, "scene.json");
    } catch (const std::invalid_argument&) {
      // the unknown key, after the whole document was parsed
    }
  }
  state.SetComplexityN(state.range(0));
}
BENCHMARK(scene_reader)->Name("scene_file/reader")->RangeMultiplier(2)->Range(25'000, 400'000)->Complexity();

void plain_json(benchmark::State& state) {
  const std::string text = scene_of_many_spheres(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(nlohmann::json::parse(text));
  state.SetComplexityN(state.range(0));
}
BENCHMARK(plain_json)->Name("scene_file/json_parse")->RangeMultiplier(2)->Range(25'000, 400'000)->Complexity();

}  // namespace
}  // namespace hail::micro
