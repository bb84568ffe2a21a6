// libFuzzer target: the JSON scene parser (scenes/scene_file.h) on arbitrary text, then a few steps
// of the World it built. A bad document must end in std::invalid_argument naming the field, never
// a crash, a hang or a sanitizer report; a document the parser accepts must step without one.
// Run through scripts/fuzz.sh (with tests/fuzz/scene.dict, so that numbers with exponents, huge
// magnitudes and the format's field names turn up often).
//
// Each input must stay fast (libFuzzer runs about a million of them), so the harness refuses,
// before parsing, documents that ask for much work: more than kMaxCount of anything (a
// generator's count, a terrain's vertices per side, solver iterations) and brackets nested deeper
// than kMaxNesting. The parser's own limits on huge counts and deep nesting are tested in
// tests/test_scene_file.cpp. Everything else, exponents and huge numbers included, reaches the
// parser. Only a world that is small and ordinary (below) is stepped.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include <nlohmann/json.hpp>

#include "hail/errors.h"
#include "scenes/scene_file.h"

namespace {

constexpr std::int64_t kMaxCount = 64;  ///< spheres per generator, terrain vertices per side, iterations
/// The parser refuses documents deeper than 64 (kMaxSceneNesting) without recursing; this bound
/// only keeps this harness's own recursive walks (asks_for_a_lot, ordinary_magnitudes) off deep
/// inputs, far above the parser's limit so that its refusal is fuzzed.
constexpr int kMaxNesting = 1000;
constexpr std::size_t kMaxStepSpheres = 64;
constexpr int kSteps = 3;
/// Stepped only when dt * time_scale is at most this: 10 substeps of the default 0.05 s. Longer
/// steps only cost time (up to max_substeps substeps; beyond, World::step refuses them).
constexpr double kMaxStepSeconds = 0.5;
/// Stepped only when every number in the document is at most this in magnitude. The World
/// refuses what it cannot step (a radius or plane offset past float range, a terrain or sphere
/// too far out to resolve: include/hail/world.h), so worlds with values far beyond any scene's are
/// stepped too; past 1e30 a value only repeats those refusals. Parsing sees all numbers.
constexpr double kMaxStepMagnitude = 1e30;

/// Deepest [ / { nesting outside strings: nlohmann's parser recurses once per level.
int nesting_depth(std::string_view text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

/// Keys whose integer value sets the work a document asks for.
bool is_work_key(const std::string& key) {
  return key == "count" || key == "size" || key == "collision_iterations" || key == "resting_iterations" ||
         key == "depenetration_iterations";
}

/// True when a number under a work key (or an element of its array) is an integer above
/// kMaxCount. Floats there are the parser's to refuse (integer fields take integers only).
bool asks_for_a_lot(const nlohmann::json& value, bool under_work_key) {
  if (value.is_number_integer()) {
    return under_work_key && (value.is_number_unsigned() ? value.get<std::uint64_t>() > kMaxCount
                                                         : value.get<std::int64_t>() > kMaxCount);
  }
  if (value.is_array()) {
    for (const auto& element : value) {
      if (asks_for_a_lot(element, under_work_key)) return true;
    }
  } else if (value.is_object()) {
    for (const auto& [key, element] : value.items()) {
      if (asks_for_a_lot(element, is_work_key(key))) return true;
    }
  }
  return false;
}

/// True when every number in the document is finite and within kMaxStepMagnitude (the seed and
/// shock_mass_ratio, whose documented "never" is 1e30, excepted).
bool ordinary_magnitudes(const nlohmann::json& value) {
  if (value.is_number()) return std::fabs(value.get<double>()) <= kMaxStepMagnitude;
  if (value.is_array()) {
    for (const auto& element : value) {
      if (!ordinary_magnitudes(element)) return false;
    }
  } else if (value.is_object()) {
    for (const auto& [key, element] : value.items()) {
      if (key != "seed" && key != "shock_mass_ratio" && !ordinary_magnitudes(element)) return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (nesting_depth(text) > kMaxNesting) return 0;
  // The same reading as parse_scene_text (comments allowed), only to look at the numbers first.
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
    if (asks_for_a_lot(doc, false)) return 0;
  } catch (const nlohmann::json::exception&) {  // bad JSON or a number beyond a double: the parser's error path, below
    doc = nlohmann::json();
  }
  // One thread: the fuzzer's coverage and the run must not depend on scheduling.
  hail::bench::SceneOverrides one_thread;
  one_thread.threads = 1;
  hail::bench::Scene scene;
  try {
    scene = hail::bench::parse_scene_text(text, "fuzz.json", one_thread, "/nonexistent");
  } catch (const std::invalid_argument&) {  // the parser's own refusal, naming the field
    return 0;
  } catch (const hail::FileError&) {  // a heightmap file named in the document
    return 0;
  }
  if (scene.world->sphere_count() > kMaxStepSpheres || !ordinary_magnitudes(doc)) return 0;
  const double seconds = static_cast<double>(scene.dt) * scene.world->settings().time_scale;
  if (!(seconds <= kMaxStepSeconds)) return 0;
  try {
    for (int i = 0; i < kSteps; ++i) scene.world->step(scene.dt);
  } catch (const hail::InvalidArgument&) {  // a dt the World refuses (it throws before changing anything)
  }
  return 0;
}
