#pragma once
// A setting of the settings table (include/hail/settings_table.h) set from text, as a command
// line gives it: `hail-bench run --set sleep_time=1.5 --set soft_step.substeps=8`. Every setting
// the table lists can be set this way, by its table name, without a flag of its own.

#include <string>
#include <string_view>
#include <vector>

#include "hail/world_settings.h"

namespace hail::bench {

/// Sets the setting `name` of `s` from `text`: a number for numbers, on|off|true|false for a
/// bool, one of the table's names for an enum ("soft", "grid"), "x,y,z" for a Vec3. Throws
/// std::invalid_argument naming the setting and what it takes for an unknown name or a text
/// that is not such a value; the range is the World's to check (World's constructor names it).
void set_setting(WorldSettings& s, std::string_view name, std::string_view text);

/// "NAME=VALUE" split at its first '=' and set_setting.
void set_setting(WorldSettings& s, std::string_view assignment);

/// set_setting for each assignment, in order (a later one wins).
void set_settings(WorldSettings& s, const std::vector<std::string>& assignments);

/// The setting `name` of `s` as set_setting reads it back exactly (floats with 9 digits);
/// std::invalid_argument for an unknown name.
[[nodiscard]] std::string setting_text(const WorldSettings& s, std::string_view name);

/// The names set_setting takes, comma-separated, for help texts and messages.
[[nodiscard]] std::string setting_names();

}  // namespace hail::bench
