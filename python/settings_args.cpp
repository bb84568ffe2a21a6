// WorldSettings from keyword arguments, driven by the settings table (include/hail/settings_table.h):
// a setting added to the table is a keyword of hail.World with no code here. Types are checked
// here (TypeError), enum names and integer ranges too (hail.InvalidArgument naming the value);
// the World's constructor checks every range as it does for C++ callers.

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <map>
#include <type_traits>

#include <hail/errors.h>
#include <hail/settings_table.h>

#include "bindings.h"
#include "scenes/setting_text.h"

namespace hail::python {
namespace {

std::string python_name(std::string_view table_name) {
  std::string name(table_name);
  for (char& c : name)
    if (c == '.') c = '_';
  return name;
}

/// The group of a nested setting ("soft_step" of "soft_step.substeps"), or "".
std::string group_of(std::string_view table_name) {
  const std::size_t dot = table_name.find('.');
  return dot == std::string_view::npos ? std::string() : std::string(table_name.substr(0, dot));
}

std::string repr_of(const py::handle& value) { return py::repr(value).cast<std::string>(); }
std::string type_name(const py::handle& value) { return py::str(py::type::of(value).attr("__name__")).cast<std::string>(); }

bool is_bool(const py::handle& v) {
  if (PyBool_Check(v.ptr())) return true;
  return py::isinstance(v, py::module_::import("numpy").attr("bool_"));
}
bool is_integer(const py::handle& v) { return !is_bool(v) && !PyFloat_Check(v.ptr()) && PyIndex_Check(v.ptr()); }
bool is_number(const py::handle& v) {
  return !is_bool(v) && (PyFloat_Check(v.ptr()) || PyIndex_Check(v.ptr()) ||
                         py::isinstance(v, py::module_::import("numpy").attr("floating")));
}

[[noreturn]] void wrong_type(const char* caller, const SettingSpec& spec, const char* wants, const py::handle& v) {
  throw py::type_error(std::string(caller) + ": setting " + python_name(spec.name) + " takes " + wants + ", got " +
                       repr_of(v) + " (" + type_name(v) + ")");
}

template <class T>
void assign(T& field, const SettingSpec& spec, const py::handle& v, const char* caller) {
  if constexpr (std::is_same_v<T, bool>) {
    if (!is_bool(v)) wrong_type(caller, spec, "True or False", v);
    field = v.cast<bool>();
  } else if constexpr (std::is_same_v<T, Vec3>) {
    const py::array_t<double> a = py::array_t<double>::ensure(v);
    if (!a || a.ndim() != 1 || a.size() != 3 || is_bool(v) || PyUnicode_Check(v.ptr()))
      wrong_type(caller, spec, "three numbers (x, y, z)", v);
    field = Vec3(static_cast<float>(a.at(0)), static_cast<float>(a.at(1)), static_cast<float>(a.at(2)));
  } else if constexpr (std::is_enum_v<T>) {
    if (!PyUnicode_Check(v.ptr())) wrong_type(caller, spec, (std::string("one of ") + spec.values).c_str(), v);
    const std::string name = v.cast<std::string>();
    const std::size_t index = setting_value_index(spec, name);
    if (index == setting_value_count(spec))
      throw InvalidArgument(std::string(caller) + ": setting " + python_name(spec.name) + " must be one of " +
                            spec.values + ", got " + repr_of(v));
    field = static_cast<T>(index);
  } else if constexpr (std::is_integral_v<T>) {
    if (!is_integer(v)) wrong_type(caller, spec, "an int", v);
    // Checked here, in Python's unbounded ints, before it could wrap in the field's type.
    const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(v.ptr()));
    const double d = PyLong_AsDouble(i.ptr());
    if (PyErr_Occurred()) PyErr_Clear();
    const bool fits = std::isfinite(d) && d >= spec.min && d <= spec.max && !(spec.min_open && d == spec.min) &&
                      !(spec.max_open && d == spec.max);
    if (!fits)
      throw InvalidArgument(std::string(caller) + ": setting " + python_name(spec.name) + " must be in " +
                            setting_range_text(spec) + " (include/hail/settings_table.h), got " + repr_of(v));
    field = static_cast<T>(i.cast<long long>());
  } else {
    static_assert(std::is_floating_point_v<T>);
    if (!is_number(v)) wrong_type(caller, spec, "a number", v);
    const double d = v.cast<double>();
    // A finite double beyond float range would reach the World's check as infinity.
    if (std::isfinite(d) && std::fabs(d) > FLT_MAX)
      throw InvalidArgument(std::string(caller) + ": setting " + python_name(spec.name) + " must be in " +
                            setting_range_text(spec) + " (include/hail/settings_table.h), got " + repr_of(v));
    field = static_cast<T>(d);
  }
}

template <class T>
py::object to_python(const T& field, const SettingSpec& spec) {
  if constexpr (std::is_same_v<T, Vec3>) {
    return py::make_tuple(field.x(), field.y(), field.z());
  } else if constexpr (std::is_enum_v<T>) {
    return py::str(std::string(setting_value_name(spec, static_cast<std::size_t>(field))));
  } else {
    return py::cast(field);
  }
}

template <class T>
const char* kind_of() {
  if constexpr (std::is_same_v<T, bool>) return "bool";
  else if constexpr (std::is_same_v<T, Vec3>) return "vec3";
  else if constexpr (std::is_enum_v<T>) return "enum";
  else if constexpr (std::is_integral_v<T>) return "int";
  else return "float";
}

/// Keyword arguments by Python name, with each group's dict spread out; TypeError for a name
/// that is no setting.
std::map<std::string, py::object> flatten(const py::kwargs& kwargs, const char* caller) {
  std::map<std::string, std::string> known;  // Python name -> table name
  std::map<std::string, bool> groups;
  WorldSettings probe;
  for_each_setting(probe, [&](const auto&, const SettingSpec& spec) {
    known[python_name(spec.name)] = spec.name;
    if (!group_of(spec.name).empty()) groups[group_of(spec.name)] = true;
  });
  std::map<std::string, py::object> given;
  auto put = [&](const std::string& name, py::object value) {
    if (!known.count(name)) {
      std::string names;
      for (const auto& [n, table] : known) names += (names.empty() ? "" : ", ") + n;
      throw py::type_error(std::string(caller) + " got an unexpected keyword argument '" + name +
                           "' (the settings: " + names + ")");
    }
    if (given.count(name))
      throw py::type_error(std::string(caller) + " got setting '" + name + "' twice (as a keyword and in its group's dict)");
    given[name] = std::move(value);
  };
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key).cast<std::string>();
    if (groups.count(name)) {
      if (!py::isinstance<py::dict>(value))
        throw py::type_error(std::string(caller) + ": " + name + " takes a dict of its settings, e.g. " + name +
                             "={...}, got " + repr_of(value));
      for (const auto& [inner, inner_value] : value.cast<py::dict>())
        put(name + "_" + py::str(inner).cast<std::string>(), py::reinterpret_borrow<py::object>(inner_value));
    } else {
      put(name, py::reinterpret_borrow<py::object>(value));
    }
  }
  return given;
}

}  // namespace

WorldSettings settings_from_kwargs(const py::kwargs& kwargs, const char* caller) {
  std::map<std::string, py::object> given = flatten(kwargs, caller);
  WorldSettings s;
  for_each_setting(s, [&](auto& field, const SettingSpec& spec) {
    const auto it = given.find(python_name(spec.name));
    if (it != given.end()) assign(field, spec, it->second, caller);
  });
  return s;
}

std::vector<std::string> setting_assignments(const py::kwargs& kwargs, const char* caller) {
  const std::map<std::string, py::object> given = flatten(kwargs, caller);
  const WorldSettings s = settings_from_kwargs(kwargs, caller);
  std::vector<std::string> out;
  for_each_setting(s, [&](const auto&, const SettingSpec& spec) {
    if (given.count(python_name(spec.name)))
      out.push_back(std::string(spec.name) + "=" + bench::setting_text(s, spec.name));
  });
  return out;
}

py::dict settings_to_dict(const WorldSettings& s) {
  py::dict d;
  for_each_setting(s, [&](const auto& field, const SettingSpec& spec) {
    d[py::str(python_name(spec.name))] = to_python(field, spec);
  });
  return d;
}

std::string settings_doc() {
  std::string doc;
  const WorldSettings defaults;
  for_each_setting(defaults, [&](const auto& field, const SettingSpec& spec) {
    using T = std::decay_t<decltype(field)>;
    std::string line = "    " + python_name(spec.name) + " (" + kind_of<T>() + ", default ";
    auto short_number = [](double v) {
      char text[32];
      std::snprintf(text, sizeof text, "%.6g", v);
      return std::string(text);
    };
    if constexpr (std::is_same_v<T, Vec3>) {
      line += "(" + short_number(field.x()) + ", " + short_number(field.y()) + ", " + short_number(field.z()) + ")";
    } else if constexpr (std::is_floating_point_v<T>) {
      line += short_number(field);
    } else if constexpr (std::is_same_v<T, bool>) {
      line += field ? "True" : "False";
    } else if constexpr (std::is_enum_v<T>) {
      line += "'" + std::string(setting_value_name(spec, static_cast<std::size_t>(field))) + "'";
    } else {
      line += bench::setting_text(defaults, spec.name);
    }
    if constexpr (std::is_enum_v<T>) {
      line += "; one of " + std::string(spec.values);
    } else if constexpr (!std::is_same_v<T, bool> && !std::is_same_v<T, Vec3>) {
      line += "; in " + setting_range_text(spec);
    }
    doc += line + "): " + spec.doc + "\n";
  });
  return doc;
}

void bind_settings(py::module_& m) {
  m.def(
      "settings_table",
      [] {
        py::list rows;
        const WorldSettings defaults;
        for_each_setting(defaults, [&](const auto& field, const SettingSpec& spec) {
          using T = std::decay_t<decltype(field)>;
          py::dict row;
          row["name"] = python_name(spec.name);
          row["table_name"] = spec.name;
          row["kind"] = kind_of<T>();
          row["default"] = to_python(field, spec);
          if constexpr (std::is_enum_v<T>) {
            py::list values;
            for (std::size_t k = 0; k < setting_value_count(spec); ++k)
              values.append(std::string(setting_value_name(spec, k)));
            row["values"] = values;
          } else if constexpr (!std::is_same_v<T, bool> && !std::is_same_v<T, Vec3>) {
            row["min"] = spec.min;
            row["max"] = spec.max >= settings_detail::kFloatMax ? INFINITY : spec.max;
            row["range"] = setting_range_text(spec) + (spec.infinity ? " or inf" : "");
          }
          row["snapshot"] = spec.snapshot;
          row["doc"] = spec.doc;
          rows.append(row);
        });
        return rows;
      },
      "Every setting of hail.World, in the settings table's order (include/hail/settings_table.h):\n"
      "a dict each with name (the keyword), table_name (the scene file's and C++ name), kind\n"
      "(bool, int, float, enum, vec3), default, values (enums), min, max and range (numbers),\n"
      "snapshot (saved in snapshots) and doc.");
}

}  // namespace hail::python
