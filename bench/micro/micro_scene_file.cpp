// Parsing a scene file's sphere list: the reader (parse_scene_text) against plain json::parse of
// the same text, at doubling list lengths. The reader must scale as json::parse does, linearly
// (benchmark's complexity fit says so): nlohmann's callback parser, which it used to use,
// looked through the whole parent array after every element, and 400,000 objects took 79 s.
#include <stdexcept>
#include <string>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "scenes/large_scene_text.h"
#include "scenes/scene_file.h"

namespace hail::micro {
namespace {

void scene_reader(benchmark::State& state) {
  const std::string text = bench::scene_of_many_spheres(static_cast<std::size_t>(state.range(0)));
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
  const std::string text = bench::scene_of_many_spheres(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(nlohmann::json::parse(text));
  state.SetComplexityN(state.range(0));
}
BENCHMARK(plain_json)->Name("scene_file/json_parse")->RangeMultiplier(2)->Range(25'000, 400'000)->Complexity();

}  // namespace
}  // namespace hail::micro
