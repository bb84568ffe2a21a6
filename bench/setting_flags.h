#pragma once
// hail-bench's setting flags, made from the settings table (include/hail/settings_table.h): a
// setting whose SettingSpec names a `flag` gets --FLAG VALUE, which takes the text --set
// NAME=VALUE takes (scenes/setting_text.h) and is checked by World::validate's rules before
// anything runs. Adding a flag means naming it in the table; no command declares one by hand.

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "hail/world_settings.h"

namespace CLI {
class App;
}

namespace hail::bench {

/// Adds the flag of every setting that has one, writing its value into `settings`; with `only`
/// (table names, or a group's prefix: "soft_step."), the flags of those settings alone.
void add_setting_flags(CLI::App& app, WorldSettings& settings, std::initializer_list<std::string_view> only = {});

/// Every setting flag, with its dashes ("--resting", ...), in the table's order.
[[nodiscard]] std::vector<std::string> setting_flags();

/// The setting flags given on `app`'s command line as assignments by table name
/// ("resting_iterations=12"), their values read back from `settings`, in the table's order: what
/// a scene file takes over its own values (scenes/scene_file.h's SceneOverrides::set).
[[nodiscard]] std::vector<std::string> given_setting_flags(const CLI::App& app, const WorldSettings& settings);

}  // namespace hail::bench
