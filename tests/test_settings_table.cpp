// The settings table (include/hail/settings_table.h): every WorldSettings field is in it once,
// World::validate refuses each number just past its range and takes it at its ends, and the
// table in docs/embedding.md is the one the table writes (`hail-tests "[.write-settings-doc]"`
// rewrites it after a change).

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>

#include "catch.h"
#include "hail/settings_table.h"
#include "hail/world.h"

using namespace hail;

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, v == std::floor(v) && std::fabs(v) < 1e15 ? "%.0f" : "%g", v);
  return text;
}

/// A table cell: "|" (enum values, |g|) escaped, as markdown tables need.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

// Strings start as std::string, not "literal" + string: GCC 12 warns, wrongly, on the latter here.
template <class T>
std::string default_text(const T& value, const SettingSpec& spec) {
  if constexpr (std::is_same_v<T, bool>)
    return value ? "on" : "off";
  else if constexpr (std::is_same_v<T, Vec3>)
    return std::string("(") + number(value.x()) + ", " + number(value.y()) + ", " + number(value.z()) + ")";
  else if constexpr (std::is_enum_v<T>)
    return std::string("`") + std::string(setting_value_name(spec, static_cast<std::size_t>(value))) + "`";
  else
    return number(static_cast<double>(value));
}

std::string range_text(const SettingSpec& spec, bool is_number) {
  if (spec.values) return std::string("`") + spec.values + "`";
  if (!is_number) return spec.name == std::string("gravity") ? "finite" : "on / off";
  return setting_range_text(spec) + (spec.infinity ? " or inf" : "");
}

/// The markdown table docs/embedding.md holds between its two marker lines.
std::string settings_markdown() {
  std::string table = "| setting | default | range | hail-bench flag | what it does |\n|---|---|---|---|---|\n";
  const WorldSettings defaults;
  for_each_setting(defaults, [&](const auto& value, const SettingSpec& spec) {
    using T = std::remove_cvref_t<decltype(value)>;
    const bool is_number = !std::is_same_v<T, bool> && !std::is_same_v<T, Vec3> && !std::is_enum_v<T>;
    table += "| `" + std::string(spec.name) + "` | " + cell(default_text(value, spec)) + " | " +
             cell(range_text(spec, is_number)) + " | " +
             (spec.flag ? "`--" + std::string(spec.flag) + "`" : std::string()) + " | " + cell(spec.doc) + (spec.snapshot ? "" : " (not in snapshots)") +
             " |\n";
  });
  return table;
}

const std::filesystem::path kEmbedding = std::filesystem::path(HAIL_SOURCE_DIR) / "docs/embedding.md";
constexpr const char* kBegin = "<!-- settings table: begin (written by hail-tests \"[.write-settings-doc]\") -->\n";
constexpr const char* kEnd = "<!-- settings table: end -->\n";

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The WorldSettings with setting number `index` (in table order) given `value`.
template <class V>
WorldSettings with_setting(WorldSettings s, std::size_t index, V value) {
  std::size_t k = 0;
  for_each_setting(s, [&](auto& field, const SettingSpec&) {
    using T = std::remove_cvref_t<decltype(field)>;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
      if (k == index) field = static_cast<T>(value);
    ++k;
  });
  return s;
}

bool accepted(const WorldSettings& s) {
  try {
    World w(s);
  } catch (const InvalidArgument&) {
    return false;
  }
  return true;
}

}  // namespace

TEST_CASE("The settings table lists every setting once, with a doc line and a sane range", "[settings]") {
  std::set<std::string> names;
  std::size_t count = 0, in_snapshot = 0;
  const WorldSettings defaults;
  for_each_setting(defaults, [&](const auto&, const SettingSpec& spec) {
    ++count;
    in_snapshot += spec.snapshot ? 1 : 0;
    CHECK(names.insert(spec.name).second);
    CHECK(std::string(spec.doc).size() > 10);
    CHECK(spec.min <= spec.max);
  });
  CHECK(count == names.size());
  CHECK(in_snapshot + 1 == count);  // all but threads
  CHECK(accepted(defaults));        // the defaults lie in their ranges
}

TEST_CASE("World refuses every number just past its range, naming it, and takes its ends", "[settings][invalid]") {
  // Zero gravity: the longest step may then be as long as the ranges allow.
  WorldSettings base;
  base.gravity = Vec3::Zero();
  base.threads = 1;
  std::size_t index = 0, checked = 0;
  for_each_setting(base, [&](const auto& value, const SettingSpec& spec) {
    using T = std::remove_cvref_t<decltype(value)>;
    const std::size_t k = index++;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      INFO(spec.name);
      const bool is_float = std::is_floating_point_v<T>;
      auto refused_naming = [&](double v) {
        INFO("value " << v);
        try {
          World w(with_setting(base, k, v));
          FAIL("accepted");
        } catch (const InvalidArgument& e) {
          CHECK(std::string(e.what()).find(spec.name) != std::string::npos);
        }
      };
      // Just below the bottom (or at an open one), just above the top (or at an open one).
      if (spec.min_open)
        refused_naming(spec.min);
      else if (spec.min > double(std::numeric_limits<T>::lowest()))
        refused_naming(is_float ? std::nextafter(float(spec.min), -1e30f) : spec.min - 1);
      if (spec.max_open)
        refused_naming(spec.max);
      else if (spec.max < double(std::numeric_limits<T>::max()) && !spec.infinity)
        refused_naming(is_float ? std::nextafter(float(spec.max), 3e38f) : spec.max + 1);
      if (is_float) {
        refused_naming(std::numeric_limits<double>::quiet_NaN());
        if (!spec.infinity) refused_naming(std::numeric_limits<double>::infinity());
      }
      // The ends themselves (closed ones), but the thread count (an arena of 4,096 slots).
      if (spec.name != std::string("threads")) {
        if (!spec.min_open) CHECK(accepted(with_setting(base, k, spec.min)));
        if (!spec.max_open && !(spec.name == std::string("solver_tile_spheres") && spec.max == 0))
          CHECK(accepted(with_setting(base, k, spec.max)));
      }
      ++checked;
    }
  });
  CHECK(checked > 25);
}

TEST_CASE("docs/embedding.md's settings table is the one the table writes", "[settings][docs]") {
  const std::string text = read_text(kEmbedding);
  const std::size_t begin = text.find(kBegin), end = text.find(kEnd);
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  const std::string in_page = text.substr(begin + std::string(kBegin).size(), end - begin - std::string(kBegin).size());
  INFO("after a change to include/hail/settings_table.h: hail-tests \"[.write-settings-doc]\" rewrites it");
  CHECK(in_page == settings_markdown());
}

TEST_CASE("Write docs/embedding.md's settings table", "[.write-settings-doc]") {
  std::string text = read_text(kEmbedding);
  const std::size_t begin = text.find(kBegin), end = text.find(kEnd);
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  text.replace(begin + std::string(kBegin).size(), end - begin - std::string(kBegin).size(), settings_markdown());
  std::ofstream(kEmbedding, std::ios::binary | std::ios::trunc) << text;
}
