#include "scenes/setting_text.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <type_traits>

#include "hail/settings_table.h"

namespace hail::bench {
namespace {

[[noreturn]] void refuse(std::string_view name, std::string_view text, const std::string& takes) {
  throw std::invalid_argument("--set " + std::string(name) + "=" + std::string(text) + ": " + std::string(name) +
                              " takes " + takes);
}

/// The whole text as a double (strtod: "1e-3", "inf"), or nothing.
bool parse_double(std::string_view text, double& out) {
  const std::string copy(text);
  char* end = nullptr;
  out = std::strtod(copy.c_str(), &end);
  return !copy.empty() && end == copy.c_str() + copy.size();
}

template <class T>
void set_value(T& field, const SettingSpec& spec, std::string_view text) {
  if constexpr (std::is_same_v<T, bool>) {
    if (text == "on" || text == "true")
      field = true;
    else if (text == "off" || text == "false")
      field = false;
    else
      refuse(spec.name, text, "on, off, true or false");
  } else if constexpr (std::is_enum_v<T>) {
    const std::size_t index = setting_value_index(spec, text);
    if (index < setting_value_count(spec)) {
      field = static_cast<T>(index);
      return;
    }
    refuse(spec.name, text, std::string("one of ") + spec.values);
  } else if constexpr (std::is_same_v<T, Vec3>) {
    double v[3];
    std::string_view rest = text;
    for (int c = 0; c < 3; ++c) {
      const std::size_t comma = rest.find(',');
      if ((c < 2) == (comma == std::string_view::npos) || !parse_double(rest.substr(0, comma), v[c]))
        refuse(spec.name, text, "three numbers x,y,z");
      rest = c < 2 ? rest.substr(comma + 1) : rest;
    }
    field = Vec3(float(v[0]), float(v[1]), float(v[2]));
  } else if constexpr (std::is_integral_v<T>) {
    long long v = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (error != std::errc() || end != text.data() + text.size() || (v < 0 && std::is_unsigned_v<T>))
      refuse(spec.name, text, "a whole number");
    if (double(v) < spec.min - 1 || double(v) > spec.max + 1)  // keeps the cast below in range; World names the range
      refuse(spec.name, text,
             "a whole number in [" + std::to_string((long long)spec.min) + ", " + std::to_string((long long)spec.max) +
                 "]");
    field = static_cast<T>(v);
  } else {
    double v = 0.0;
    if (!parse_double(text, v)) refuse(spec.name, text, "a number");
    field = static_cast<T>(v);
  }
}

}  // namespace

void set_setting(WorldSettings& s, std::string_view name, std::string_view text) {
  bool found = false;
  for_each_setting(s, [&](auto& field, const SettingSpec& spec) {
    if (spec.name != name) return;
    found = true;
    set_value(field, spec, text);
  });
  if (!found)
    throw std::invalid_argument("--set " + std::string(name) + "=" + std::string(text) + ": no setting '" +
                                std::string(name) + "' (the settings: " + setting_names() + ")");
}

void set_setting(WorldSettings& s, std::string_view assignment) {
  const std::size_t equals = assignment.find('=');
  if (equals == std::string_view::npos || equals == 0)
    throw std::invalid_argument("--set " + std::string(assignment) + ": give NAME=VALUE, e.g. --set sleep_time=1.5");
  set_setting(s, assignment.substr(0, equals), assignment.substr(equals + 1));
}

void set_settings(WorldSettings& s, const std::vector<std::string>& assignments) {
  for (const std::string& a : assignments) set_setting(s, a);
}

std::string setting_text(const WorldSettings& s, std::string_view name) {
  std::string text;
  bool found = false;
  auto number = [](double v, const char* format) {
    char out[40];
    std::snprintf(out, sizeof out, format, v);
    return std::string(out);
  };
  for_each_setting(s, [&](const auto& field, const SettingSpec& spec) {
    if (spec.name != name) return;
    found = true;
    using T = std::remove_cvref_t<decltype(field)>;
    if constexpr (std::is_same_v<T, bool>) {
      text = field ? "on" : "off";
    } else if constexpr (std::is_enum_v<T>) {
      text = std::string(setting_value_name(spec, static_cast<std::size_t>(field)));
    } else if constexpr (std::is_same_v<T, Vec3>) {
      text = number(field.x(), "%.9g") + "," + number(field.y(), "%.9g") + "," + number(field.z(), "%.9g");
    } else if constexpr (std::is_integral_v<T>) {
      text = std::to_string(field);
    } else {
      text = number(field, "%.9g");
    }
  });
  if (!found) throw std::invalid_argument("no setting '" + std::string(name) + "'");
  return text;
}

std::string setting_names() {
  std::string names;
  const WorldSettings defaults;
  for_each_setting(defaults, [&](const auto&, const SettingSpec& spec) {
    names += (names.empty() ? "" : ", ") + std::string(spec.name);
  });
  return names;
}

}  // namespace hail::bench
