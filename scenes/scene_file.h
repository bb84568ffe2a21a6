#pragma once
// Scene files: a scene described in JSON (docs/scene_format.md) and read into the same Scene the
// built-in builders make, so `hail-bench run --scene FILE.json` reports the same timing and
// error figures. Every problem is a std::invalid_argument naming the file and the field
// ("scene.json: spheres[2].list[5].radius: must be > 0, got -1"); unknown keys are errors, so
// a typo cannot silently leave a default in place.

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/memory_use.h"
#include "scenes/scenes.h"

namespace hail::bench {

/// The `"version"` this reader understands (`"format": "hail-scene"`).
inline constexpr int kSceneFormatVersion = 1;

/// Values given on the command line, which replace the file's. Unset: the file's value stands.
struct SceneOverrides {
  std::optional<std::size_t> spheres = std::nullopt;  ///< count of the file's only lattice or random generator
  std::optional<int> threads = std::nullopt;
  std::optional<int> steps = std::nullopt;
  std::optional<float> dt = std::nullopt;
  /// Settings by their table name, "NAME=VALUE" (scenes/setting_text.h: hail-bench run's setting
  /// flags and --set), applied in order after the file's own settings.
  std::vector<std::string> set{};
  /// `--memory-limit`: a file whose text, parsed document, spheres or terrain would need more
  /// (kBytesPerSphereGuide a sphere, kTerrainBytesPerCellGuide a terrain cell) is refused before
  /// they are allocated.
  MemoryLimit memory_limit = {};
};

/// Reads and builds the scene in `path`; a heightmap path inside is relative to the file's
/// folder. The description is the file's; dt and default_steps are set; ids holds every sphere.
/// Only a regular file (after symbolic links) is read: a directory, FIFO, device or socket is
/// refused by its kind without being opened, and a file larger than the memory limit before it
/// is read. Reads the size the file had when it was looked at, and refuses a file that changed.
Scene load_scene_file(const std::string& path, const SceneOverrides& overrides = {});

/// The same from JSON text (`//` and `/* */` comments allowed); `source_name` starts every
/// error message and `base_dir` resolves a relative heightmap path. Parses in time linear in the
/// text. Refuses, naming the path, nesting deeper than kMaxSceneNesting, a key given twice in
/// one object, numbers beyond a double, and text or a parsed document over the memory limit
/// (overrides.memory_limit, checked as the parse goes).
Scene parse_scene_text(std::string_view text, const std::string& source_name, const SceneOverrides& overrides = {},
                       const std::string& base_dir = ".");

/// Arrays and objects nested deeper than this are refused while parsing: the schema needs 4
/// levels, and a value nested tens of thousands deep would overflow the stack of any code that
/// walks it recursively.
inline constexpr int kMaxSceneNesting = 64;

/// The same from a parsed document (duplicate keys are gone by then: only the text is checked).
Scene parse_scene_json(const nlohmann::json& doc, const std::string& source_name, const SceneOverrides& overrides = {},
                       const std::string& base_dir = ".");

/// The random generator's uniform draw in [0, 1): the top 24 bits of one std::mt19937_64 output
/// times 2^-24, exact in a float and the same with every standard library.
[[nodiscard]] inline float unit_float(std::mt19937_64& rng) { return static_cast<float>(rng() >> 40) * 0x1p-24f; }

}  // namespace hail::bench
