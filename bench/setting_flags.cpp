#include "setting_flags.h"

#include <algorithm>
#include <stdexcept>
#include <type_traits>

#include "cli.h"
#include "hail/settings_table.h"
#include "hail/world.h"
#include "scenes/setting_text.h"

namespace hail::bench {
namespace {

/// "--set NAME=TEXT: NAME takes ..." and "hail: WorldSettings::NAME must be ..." without their
/// prefixes: CLI11 puts the flag in front of what a check returns.
std::string reason_alone(std::string_view what) {
  if (what.starts_with("--set ")) what.remove_prefix(std::min(what.size(), what.find(": ") + 2));
  if (what.starts_with("hail: ")) what.remove_prefix(6);
  if (what.starts_with("WorldSettings::")) what.remove_prefix(15);
  return std::string(what);
}

/// A CLI11 check of the setting `name`'s text: set_setting reads it, World::validate checks it
/// on the default settings (so that --resting 5000 is refused before a scene is built).
CLI::Validator setting_check(const char* name) {
  return CLI::Validator(
      [name](std::string& text) {
        WorldSettings scratch;
        try {
          set_setting(scratch, name, text);
          World::validate(scratch);
        } catch (const std::exception& e) {
          return reason_alone(e.what());
        }
        return std::string();
      },
      "");
}

template <class T>
std::string value_kind(const SettingSpec& spec) {
  if constexpr (std::is_same_v<T, bool>) return "on|off";
  if constexpr (std::is_enum_v<T>) return spec.values;
  if constexpr (std::is_integral_v<T>) return "N";
  return "X";
}

/// Whether `name` is one of `only` (all if empty); "soft_step." lists every setting of that group.
bool listed(std::initializer_list<std::string_view> only, std::string_view name) {
  return only.size() == 0 || std::any_of(only.begin(), only.end(), [&](std::string_view entry) {
           return entry == name || (entry.ends_with('.') && name.starts_with(entry));
         });
}

}  // namespace

void add_setting_flags(CLI::App& app, WorldSettings& settings, std::initializer_list<std::string_view> only) {
  for_each_setting(settings, [&](auto& field, const SettingSpec& spec) {
    using T = std::remove_cvref_t<decltype(field)>;
    if (!spec.flag || !listed(only, spec.name)) return;
    std::string help = spec.doc;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) help += "; " + setting_range_text(spec);
    help += " (WorldSettings::" + std::string(spec.name) + ")";
    app.add_option_function<std::string>(
           std::string("--") + spec.flag,
           [&settings, name = spec.name](const std::string& text) { set_setting(settings, name, text); }, help)
        ->check(setting_check(spec.name))
        ->type_name(value_kind<T>(spec))
        ->default_str(setting_text(settings, spec.name));  // shown by --help
  });
}

std::vector<std::string> setting_flags() {
  std::vector<std::string> flags;
  const WorldSettings defaults;
  for_each_setting(defaults, [&](const auto&, const SettingSpec& spec) {
    if (spec.flag) flags.push_back(std::string("--") + spec.flag);
  });
  return flags;
}

std::vector<std::string> given_setting_flags(const CLI::App& app, const WorldSettings& settings) {
  std::vector<std::string> assignments;
  for_each_setting(settings, [&](const auto&, const SettingSpec& spec) {
    if (spec.flag && app.count(std::string("--") + spec.flag) > 0)
      assignments.push_back(std::string(spec.name) + "=" + setting_text(settings, spec.name));
  });
  return assignments;
}

}  // namespace hail::bench
