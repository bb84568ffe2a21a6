#include "scenes/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <list>
#include <optional>
#include <set>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <vector>

#include "hail/errors.h"
#include "hail/heightmap.h"
#include "hail/settings_table.h"
#include "hail/triangle_mesh.h"
#include "scenes/setting_text.h"

namespace hail::bench {
namespace {

using json = nlohmann::json;

constexpr std::int64_t kMaxSpheres = 100'000'000;  // as hail-bench run --spheres

/// Where in which file a value sits: "spheres[2].list[5].radius" in "scene.json".
struct Where {
  const std::string& source;
  std::string path;

  [[nodiscard]] Where key(std::string_view name) const {
    return {source, path.empty() ? std::string(name) : path + "." + std::string(name)};
  }
  [[nodiscard]] Where index(std::size_t k) const { return {source, path + "[" + std::to_string(k) + "]"}; }
  [[noreturn]] void fail(const std::string& message) const {
    throw std::invalid_argument(source + ": " + (path.empty() ? "" : path + ": ") + message);
  }
};

/// A number in messages as printf's %g gives it: 1e-30 and 1e+38, where std::to_string gives
/// 0.000000 and 39 digits.
std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// Appends `j` as compact JSON to `out`, stopping once `out` holds `limit` characters. Unlike
/// json::dump it never walks more of the value than it prints, so a value nested 60,000 deep or
/// megabytes long costs a few dozen steps (and a recursion no deeper than `limit`).
void append_excerpt(const json& j, std::string& out, std::size_t limit) {
  if (out.size() >= limit) return;
  if (!j.is_structured()) {
    out += j.dump();
    return;
  }
  out += j.is_array() ? '[' : '{';
  bool first = true;
  for (auto it = j.begin(); it != j.end() && out.size() < limit; ++it, first = false) {
    if (!first) out += ',';
    if (j.is_object()) out += json(it.key()).dump() + ':';
    append_excerpt(*it, out, limit);
  }
  out += j.is_array() ? ']' : '}';
}

/// The value as the file wrote it, for "got ..." (strings and containers with their type),
/// cut to 48 characters.
std::string got(const json& j) {
  std::string text;
  append_excerpt(j, text, 49);
  if (text.size() > 48) text = text.substr(0, 45) + "...";
  if (j.is_number() || j.is_boolean() || j.is_null()) return text;
  return std::string(j.type_name()) + " " + text;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

float to_float(const json& j, const Where& at) {
  if (!j.is_number()) at.fail("must be a number, got " + got(j));
  const float value = static_cast<float>(j.get<double>());
  if (!std::isfinite(value)) at.fail("must be a finite number within float range, got " + got(j));
  return value;
}

std::int64_t to_integer(const json& j, const Where& at, std::int64_t min, std::int64_t max) {
  if (!j.is_number_integer()) at.fail("must be an integer, got " + got(j));
  if (j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(max))
    at.fail("must be <= " + std::to_string(max) + ", got " + got(j));
  const std::int64_t value = j.get<std::int64_t>();
  if (value < min) at.fail("must be >= " + std::to_string(min) + ", got " + got(j));
  if (value > max) at.fail("must be <= " + std::to_string(max) + ", got " + got(j));
  return value;
}

Vec3 to_vec3(const json& j, const Where& at) {
  if (!j.is_array() || j.size() != 3) at.fail("must be an array of 3 numbers [x, y, z], got " + got(j));
  return {to_float(j[0], at.index(0)), to_float(j[1], at.index(1)), to_float(j[2], at.index(2))};
}

/// One JSON object of the schema: its keys are declared up front, so an unknown one is an
/// error naming it (with the nearest known key when one is close).
class Object {
 public:
  Object(const json& j, Where at, std::initializer_list<std::string_view> known)
      : Object(j, std::move(at), std::vector<std::string_view>(known)) {}
  /// `known` must outlive the Object (it keeps the views).
  Object(const json& j, Where at, std::vector<std::string_view> known)
      : j_(j), at_(std::move(at)), known_(std::move(known)) {
    if (!j.is_object()) at_.fail("must be an object, got " + got(j));
  }

  /// Throws for the first key that is not a known one.
  void reject_unknown_keys() const {
    for (const auto& [key, value] : j_.items()) {
      if (std::find(known_.begin(), known_.end(), key) != known_.end()) continue;
      std::string_view nearest;
      std::size_t best = 3;  // suggest only within two edits
      for (std::string_view k : known_)
        if (const std::size_t d = edit_distance(key, k); d < best) best = d, nearest = k;
      std::string known_list;
      for (std::string_view k : known_) known_list += std::string(known_list.empty() ? "" : ", ") + std::string(k);
      const std::string hint =
          nearest.empty() ? " (known: " + known_list + ")" : " (did you mean \"" + std::string(nearest) + "\"?)";
      const std::string message = "unknown key \"" + key + "\"";
      if (at_.path.empty()) at_.fail(message + " at top level" + hint);
      at_.fail(message + hint);
    }
  }

  [[nodiscard]] const Where& where() const { return at_; }
  [[nodiscard]] Where at(std::string_view key) const { return at_.key(key); }
  [[nodiscard]] bool has(std::string_view key) const { return j_.contains(key); }
  [[nodiscard]] const json& operator[](std::string_view key) const { return j_.at(key); }

  const json& required(std::string_view key) const {
    if (!has(key)) at_.fail("missing required key \"" + std::string(key) + "\"");
    return j_.at(key);
  }
  /// `key` must not be given in this kind of object (`why` says which kind).
  void forbid(std::string_view key, const std::string& why) const {
    if (has(key)) at(key).fail(why);
  }

  [[nodiscard]] std::optional<float> opt_number(std::string_view key) const {
    if (!has(key)) return std::nullopt;
    return to_float(j_.at(key), at(key));
  }
  [[nodiscard]] float number(std::string_view key, float fallback) const { return opt_number(key).value_or(fallback); }
  [[nodiscard]] std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t min,
                                     std::int64_t max) const {
    return has(key) ? to_integer(j_.at(key), at(key), min, max) : fallback;
  }
  [[nodiscard]] bool boolean(std::string_view key, bool fallback) const {
    if (!has(key)) return fallback;
    const json& v = j_.at(key);
    if (!v.is_boolean()) at(key).fail("must be true or false, got " + got(v));
    return v.get<bool>();
  }
  [[nodiscard]] std::optional<std::string> opt_string(std::string_view key) const {
    if (!has(key)) return std::nullopt;
    const json& v = j_.at(key);
    if (!v.is_string()) at(key).fail("must be a string, got " + got(v));
    return v.get<std::string>();
  }
  [[nodiscard]] Vec3 vec3(std::string_view key, const Vec3& fallback) const {
    return has(key) ? to_vec3(j_.at(key), at(key)) : fallback;
  }
  /// One of `names` (the string given), mapped to the value beside it.
  template <class T>
  [[nodiscard]] std::optional<T> choice(std::string_view key,
                                        std::initializer_list<std::pair<std::string_view, T>> names) const {
    const std::optional<std::string> name = opt_string(key);
    if (!name) return std::nullopt;
    std::string list;
    for (const auto& [n, value] : names) {
      if (*name == n) return value;
      list += std::string(list.empty() ? "" : ", ") + "\"" + std::string(n) + "\"";
    }
    at(key).fail("must be one of " + list + ", got \"" + *name + "\"");
  }

 private:
  const json& j_;
  Where at_;
  std::vector<std::string_view> known_;
};

// ---- checks shared by every kind of object --------------------------------------------------

float positive(const Object& o, std::string_view key, float fallback) {
  const float v = o.number(key, fallback);
  if (!(v > 0.0f)) o.at(key).fail("must be > 0, got " + got(o[key]));
  return v;
}

float non_negative(const Object& o, std::string_view key, float fallback) {
  const float v = o.number(key, fallback);
  if (!(v >= 0.0f)) o.at(key).fail("must be >= 0, got " + got(o[key]));
  return v;
}

float unit_interval(const Object& o, std::string_view key, float fallback) {
  const float v = o.number(key, fallback);
  if (!(v >= 0.0f && v <= 1.0f)) o.at(key).fail("must be in [0, 1], got " + got(o[key]));
  return v;
}

/// A number, or [min, max] with 0 < min <= max (`allow_zero`: 0 <= min).
std::pair<float, float> range(const Object& o, std::string_view key, float fallback, bool allow_zero) {
  if (!o.has(key)) return {fallback, fallback};
  const json& j = o[key];
  const Where at = o.at(key);
  std::pair<float, float> r;
  if (j.is_array()) {
    if (j.size() != 2) at.fail("must be a number or [min, max], got " + got(j));
    r = {to_float(j[0], at.index(0)), to_float(j[1], at.index(1))};
  } else {
    if (!j.is_number()) at.fail("must be a number or [min, max], got " + got(j));
    r.first = r.second = to_float(j, at);
  }
  const bool min_ok = allow_zero ? r.first >= 0.0f : r.first > 0.0f;
  if (!min_ok) at.fail(std::string("must be ") + (allow_zero ? ">= 0" : "> 0") + ", got " + got(j));
  if (r.first > r.second) at.fail("min must be <= max, got " + got(j));
  return r;
}

/// radius / mass or density / restitution / friction / static, defaulting from `base`.
struct Material {
  float radius = 0.5f, mass = 1.0f, restitution = 0.5f, friction = 0.5f;
  /// kg/m^3: when set, each sphere's mass is mass_of(density, its radius) and `mass` is unused.
  std::optional<float> density = std::nullopt;
  bool is_static = false;
};

/// kg of a solid sphere: density (kg/m^3) times 4/3 pi r^3, in double and rounded once to float
/// (beyond float range it is infinite, which check_mass refuses).
float mass_of(float density, float radius) {
  constexpr double kFourThirdsPi = 4.0 / 3.0 * 3.14159265358979323846;
  const double r = radius;
  return static_cast<float>(kFourThirdsPi * double(density) * r * r * r);
}

/// A mass made from a density must lie where World::add_sphere accepts it; refused here so that
/// the message names the density and radius that gave it.
void check_mass(float mass, float density, float radius, const Where& at) {
  if (mass >= kMinSphereMass && mass <= kMaxSphereMass) return;
  char text[256];
  std::snprintf(text, sizeof text, "density %g kg/m^3 and radius %g m give a mass of %g kg, %s", double(density),
                double(radius), double(mass),
                mass > kMaxSphereMass ? "more than the World's limit of 1e12 kg (kMaxSphereMass)"
                                      : "less than the World's limit of 1e-12 kg (kMinSphereMass)");
  at.fail(text);
}

/// "mass" and "density" say the same thing two ways: one object may give one of them.
void forbid_mass_and_density(const Object& o) {
  if (o.has("mass") && o.has("density"))
    o.where().fail("give \"mass\" or \"density\" (mass = density * 4/3 pi radius^3), not both");
}

/// `ranges_elsewhere`: radius and mass (or density) are [min, max] ranges the caller reads.
Material read_material(const Object& o, const Material& base, bool ranges_elsewhere = false) {
  Material m = base;
  forbid_mass_and_density(o);
  m.is_static = o.boolean("static", base.is_static);
  if (!ranges_elsewhere) {
    m.radius = positive(o, "radius", base.radius);
    if (o.has("mass")) {
      m.mass = positive(o, "mass", base.mass);
      m.density.reset();
    } else if (o.has("density")) {
      m.density = positive(o, "density", 0.0f);
    }
    if (m.density) {
      m.mass = mass_of(*m.density, m.radius);
      // A static sphere has no mass (World ignores it): any density will do.
      if (!m.is_static) check_mass(m.mass, *m.density, m.radius, o.has("density") ? o.at("density") : o.where());
    }
  }
  m.restitution = unit_interval(o, "restitution", base.restitution);
  m.friction = non_negative(o, "friction", base.friction);
  return m;
}

SphereDesc sphere(const Vec3& position, const Vec3& velocity, const Vec3& angular_velocity, const Material& m) {
  return {.position = position,
          .velocity = velocity,
          .angular_velocity = angular_velocity,
          .radius = m.radius,
          .mass = m.mass,
          .restitution = m.restitution,
          .friction = m.friction,
          .is_static = m.is_static};
}

// ---- settings --------------------------------------------------------------------------------

/// The keys of the "settings" object (`group` empty) or of one of its groups ("soft_step"):
/// the settings table's names (include/hail/settings_table.h) below it, each once, and the
/// groups' own names at the top.
std::vector<std::string> setting_keys(std::string_view group) {
  std::vector<std::string> keys;
  const WorldSettings defaults;
  for_each_setting(defaults, [&](const auto&, const SettingSpec& spec) {
    if (spec.scene_top_level) return;
    const std::string_view name = spec.name;
    const std::size_t dot = name.find('.');
    const std::string_view head = name.substr(0, dot), tail = dot == name.npos ? "" : name.substr(dot + 1);
    const std::string key(group.empty() ? head : (head == group ? tail : std::string_view()));
    if (!key.empty() && std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  });
  return keys;
}

/// One setting's value from `o[key]`, by its type and the table's range, into `field`.
template <class T>
void read_setting(const Object& o, std::string_view key, T& field, const SettingSpec& spec) {
  if (!o.has(key)) return;
  if constexpr (std::is_same_v<T, bool>) {
    field = o.boolean(key, field);
  } else if constexpr (std::is_enum_v<T>) {
    const std::optional<std::string> name = o.opt_string(key);
    const std::size_t index = setting_value_index(spec, *name);
    if (index < setting_value_count(spec)) {
      field = static_cast<T>(index);
      return;
    }
    std::string list;
    for (std::size_t k = 0; k < setting_value_count(spec); ++k)
      list += std::string(list.empty() ? "" : ", ") + "\"" + std::string(setting_value_name(spec, k)) + "\"";
    o.at(key).fail("must be one of " + list + ", got \"" + *name + "\"");
  } else if constexpr (std::is_same_v<T, Vec3>) {
    field = o.vec3(key, field);  // no table key holds one (gravity is a top-level key)
  } else if constexpr (std::is_integral_v<T>) {
    const auto min = static_cast<std::int64_t>(spec.min) + (spec.min_open ? 1 : 0);
    const auto max = static_cast<std::int64_t>(spec.max) - (spec.max_open ? 1 : 0);
    field = static_cast<T>(o.integer(key, static_cast<std::int64_t>(field), min, max));
  } else {
    const float v = o.number(key, field);  // finite, within float range
    const bool above = spec.min_open ? v > spec.min : v >= spec.min;
    const bool below = spec.max_open ? v < spec.max : v <= spec.max;
    if (!(above && below)) o.at(key).fail("must be in " + setting_range_text(spec) + ", got " + got(o[key]));
    field = v;
  }
}

/// A key older scene files have that is no longer a setting: "warm_start": false is read as
/// "warm_start_factor": 0 (warm starting off), and true leaves the factor as it is.
constexpr std::string_view kWarmStartAlias = "warm_start";

/// The "settings" object: every key the settings table names, with its range (the World's own),
/// so that a setting added to the table is a scene-file key at once; and kWarmStartAlias.
void read_settings(const json& j, const Where& at, WorldSettings& s) {
  std::vector<std::string> keys = setting_keys("");
  keys.emplace_back(kWarmStartAlias);
  const Object o(j, at, std::vector<std::string_view>(keys.begin(), keys.end()));
  o.reject_unknown_keys();
  std::list<std::vector<std::string>> group_keys;  // the groups' Objects keep views of these
  std::vector<std::pair<std::string, Object>> groups;
  for (const std::string& key : keys) {
    const std::vector<std::string>& inner = group_keys.emplace_back(setting_keys(key));
    if (inner.empty() || !o.has(key)) continue;
    groups.emplace_back(key, Object(o[key], o.at(key), std::vector<std::string_view>(inner.begin(), inner.end())));
    groups.back().second.reject_unknown_keys();
  }
  for_each_setting(s, [&](auto& field, const SettingSpec& spec) {
    if (spec.scene_top_level) return;  // read with the scene's own keys
    const std::string_view name = spec.name;
    const std::size_t dot = name.find('.');
    if (dot == name.npos) return read_setting(o, name, field, spec);
    for (const auto& [group, object] : groups)
      if (group == name.substr(0, dot)) read_setting(object, name.substr(dot + 1), field, spec);
  });
  if (!o.boolean(kWarmStartAlias, true)) s.warm_start_factor = 0.0f;
}

// ---- terrain ---------------------------------------------------------------------------------

/// What a terrain of cols x rows vertices takes at its peak while it is built.
double terrain_bytes(std::uint64_t cols, std::uint64_t rows) {
  return kTerrainBytesPerCellGuide * double(cols - 1) * double(rows - 1);
}

/// Refuses a grid whose far corner or span is not a finite float: infinite vertex coordinates
/// give triangles without a box, which the BVH refuses without naming the field.
void check_terrain_extent(const Object& o, const HeightmapParams& p, std::uint32_t cols, std::uint32_t rows) {
  const struct {
    float origin, cell;
    std::uint32_t vertices;
    const char* axis;
  } axes[] = {{p.origin_x, p.cell_x, cols, "x"}, {p.origin_z, p.cell_z, rows, "z"}};
  for (const auto& a : axes) {
    const float span = a.cell * static_cast<float>(a.vertices - 1);
    if (!std::isfinite(span))
      o.at("cell_size")
          .fail(std::string("times the ") + std::to_string(a.vertices - 1) + " cells along " + a.axis +
                " is beyond float range (cell_size * cells must stay below 3.4e38), got " + got(o["cell_size"]));
    if (!std::isfinite(a.origin + span))
      o.at("origin").fail(std::string("plus the terrain's ") + a.axis + " extent is beyond float range, got " +
                          got(o["origin"]));
  }
}

void read_terrain(const Object& o, const std::string& base_dir, const MemoryLimit& limit, Scene& scene,
                  float& restitution, float& friction, std::shared_ptr<const Terrain>& terrain) {
  o.reject_unknown_keys();
  restitution = unit_interval(o, "restitution", 0.5f);
  friction = non_negative(o, "friction", 0.5f);
  const bool is_function = o.has("function"), is_file = o.has("heightmap");
  if (is_function == is_file) o.where().fail("needs exactly one of \"function\" or \"heightmap\"");

  HeightmapParams params;
  if (o.has("cell_size")) {
    const json& c = o["cell_size"];
    const Where at = o.at("cell_size");
    if (c.is_array()) {
      if (c.size() != 2) at.fail("must be a number or [x, z], got " + got(c));
      params.cell_x = to_float(c[0], at.index(0));
      params.cell_z = to_float(c[1], at.index(1));
    } else {
      params.cell_x = params.cell_z = to_float(c, at);
    }
    if (!(params.cell_x > 0.0f && params.cell_z > 0.0f)) at.fail("must be > 0, got " + got(c));
  }
  const Vec3 origin = o.vec3("origin", Vec3::Zero());
  params.origin_x = origin.x();
  params.origin_y = origin.y();
  params.origin_z = origin.z();

  std::uint32_t cols = 0, rows = 0;
  if (o.has("size")) {
    const json& s = o["size"];
    const Where at = o.at("size");
    if (!s.is_array() || s.size() != 2) at.fail("must be [columns, rows], got " + got(s));
    cols = static_cast<std::uint32_t>(to_integer(s[0], at.index(0), 2, kMaxHeightmapSide));
    rows = static_cast<std::uint32_t>(to_integer(s[1], at.index(1), 2, kMaxHeightmapSide));
    if (std::uint64_t(cols) * rows > kMaxHeightmapVertices)
      at.fail("has " + std::to_string(std::uint64_t(cols) * rows) + " vertices, more than the " +
              std::to_string(kMaxHeightmapVertices) + " allowed");
  }
  if (is_function && !o.has("size")) cols = rows = 256;
  // The grid's size is known here for functions and raw files: refuse it before allocating.
  const std::string per_cell = std::to_string(static_cast<int>(kTerrainBytesPerCellGuide)) + " bytes a cell";
  if (cols > 0) {
    check_terrain_extent(o, params, cols, rows);
    if (const double bytes = terrain_bytes(cols, rows); limit.bytes > 0.0 && bytes > limit.bytes)
      (o.has("size") ? o.at("size") : o.where())
          .fail("a " + std::to_string(cols) + " x " + std::to_string(rows) + " terrain " +
                over_memory_limit(bytes, per_cell + " while it is built", limit));
  } else if (limit.bytes > 0.0) {
    // PGM and PNG give their size in the file: the loader refuses a header over the limit.
    params.max_vertices = static_cast<std::uint64_t>(
        std::clamp(limit.bytes / kTerrainBytesPerCellGuide, 4.0, double(kMaxHeightmapVertices)));
  }

  std::optional<Heightmap> heightmap;
  if (is_function) {
    for (const char* key : {"format", "height_scale", "height_offset"})
      o.forbid(key, "applies to a \"heightmap\" terrain only");
    enum class Shape { Rain, Bowl, Flat };
    const Shape shape =
        *o.choice<Shape>("function", {{"terrain-rain", Shape::Rain}, {"bowl", Shape::Bowl}, {"flat", Shape::Flat}});
    if (shape != Shape::Bowl) o.forbid("coefficient", "applies to the \"bowl\" function only");
    const float k = o.number("coefficient", 0.002f);
    // The function is evaluated at each vertex's place relative to the terrain's origin (vertex
    // (0, 0)) and the map then moved to the origin, so that moving `origin` moves the same
    // shape. Evaluated at world x, z, terrain-rain's waves showed another part of the field and,
    // 1e5 m out, x and z came in 7.8 mm steps, so the sines and the bowl's (x - cx)^2 went
    // ragged (tests/test_scene_file.cpp, "a function terrain keeps its shape when moved").
    HeightmapParams local = params;
    local.origin_x = local.origin_z = 0.0f;
    const Vec3 to_origin(params.origin_x, 0.0f, params.origin_z);
    try {
      if (shape == Shape::Rain) {
        heightmap = Heightmap::from_function(cols, rows, local, terrain_rain_height);
      } else if (shape == Shape::Bowl) {
        // h = k ((x - cx)^2 + (z - cz)^2), centred on the map: bowl-pile's bowl for the defaults.
        const float cx = 0.5f * static_cast<float>(cols - 1) * params.cell_x;
        const float cz = 0.5f * static_cast<float>(rows - 1) * params.cell_z;
        heightmap = Heightmap::from_function(
            cols, rows, local, [=](float x, float z) { return k * ((x - cx) * (x - cx) + (z - cz) * (z - cz)); });
      } else {
        heightmap = Heightmap::from_function(cols, rows, params, [](float, float) { return 0.0f; });
      }
    } catch (const InvalidArgument& e) {  // e.g. heights beyond float range
      if (shape == Shape::Bowl)
        o.at("coefficient")
            .fail(std::string(e.what()) +
                  " (coefficient times the squared distance to the map's centre must stay below 3.4e38)");
      o.where().fail(e.what());
    }
    if (shape != Shape::Flat) {
      try {
        heightmap = heightmap->moved(to_origin);
      } catch (const InvalidArgument& e) {  // an origin or height no longer a finite float
        o.at("origin").fail(e.what());
      }
    }
  } else {
    o.forbid("coefficient", "applies to the \"bowl\" function only");
    const std::string file = *o.opt_string("heightmap");
    params.height_scale = o.number("height_scale", 1.0f);
    params.height_offset = o.number("height_offset", 0.0f);
    std::filesystem::path path(file);
    if (path.is_relative()) path = std::filesystem::path(base_dir) / path;
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    enum class Format { Pgm, Png, RawF32, RawU16Le, RawU16Be };
    std::optional<Format> format = o.choice<Format>("format", {{"pgm", Format::Pgm},
                                                               {"png", Format::Png},
                                                               {"raw-f32", Format::RawF32},
                                                               {"raw-u16le", Format::RawU16Le},
                                                               {"raw-u16be", Format::RawU16Be}});
    if (!format) {
      if (extension == ".pgm")
        format = Format::Pgm;
      else if (extension == ".png")
        format = Format::Png;
      else
        o.at("heightmap")
            .fail("cannot tell the format from \"" + extension +
                  "\": add \"format\" (pgm, png, raw-f32, raw-u16le, raw-u16be)");
    }
    const bool raw = *format != Format::Pgm && *format != Format::Png;
    if (raw && !o.has("size")) o.where().fail("missing required key \"size\" ([columns, rows]) for a raw heightmap");
    if (!raw) o.forbid("size", "applies to raw heightmaps only (PGM and PNG files give their own size)");
    // Integer samples are at most 65535: a scale that overflows even so is the field's fault.
    const double highest = std::abs(double(params.height_scale)) * 65535.0 + std::abs(double(params.height_offset)) +
                           std::abs(double(params.origin_y));
    if (*format != Format::RawF32 && !(highest <= double(std::numeric_limits<float>::max())))
      o.at("height_scale")
          .fail("times the largest sample (65535), plus height_offset and origin.y, is beyond float range, got " +
                got(o["height_scale"]));
    try {
      switch (*format) {
        case Format::Pgm:
          heightmap = Heightmap::load_pgm(path.string(), params);
          break;
        case Format::Png:
          heightmap = Heightmap::load_png(path.string(), params);
          break;
        case Format::RawF32:
          heightmap = Heightmap::load_raw_f32(path.string(), cols, rows, params);
          break;
        case Format::RawU16Le:
          heightmap = Heightmap::load_raw_u16(path.string(), cols, rows, params, true);
          break;
        case Format::RawU16Be:
          heightmap = Heightmap::load_raw_u16(path.string(), cols, rows, params, false);
          break;
      }
    } catch (const SizeLimitError& e) {  // the header's size is over what the memory limit allows
      o.at("heightmap")
          .fail(std::string(e.what()) + "; a terrain takes about " + per_cell +
                " while it is built, so the memory limit of " + limit.description + " allows " +
                std::to_string(params.max_vertices) + " vertices; --memory-limit GB sets it, 0 turns the check off");
    } catch (const std::exception& e) {  // FileError or InvalidArgument from the loader
      o.at("heightmap").fail(e.what());
    }
    check_terrain_extent(o, params, heightmap->cols(), heightmap->rows());
  }
  if (!std::isfinite(heightmap->max_height() - heightmap->min_height()))
    (is_function ? o.where() : o.at("height_scale"))
        .fail("the heights span " + number_text(heightmap->min_height()) + " .. " +
              number_text(heightmap->max_height()) + " m, more than a float holds");

  scene.has_terrain = true;
  scene.min_x = heightmap->x_of(0);
  scene.max_x = heightmap->max_x();
  scene.min_z = heightmap->z_of(0);
  scene.max_z = heightmap->max_z();
  try {
    terrain = std::make_shared<const Terrain>(std::move(*heightmap));
  } catch (const InvalidArgument& e) {  // the BVH's refusal: the checks above should leave none
    o.where().fail(e.what());
  }
  scene.ground_height = [t = terrain](float x, float z) { return t->heightmap().surface_height(x, z); };
}

// ---- sphere generators -----------------------------------------------------------------------

/// What a generator may refer to outside itself.
struct GeneratorContext {
  Material material;                          ///< the top-level "material"
  const Terrain* terrain;                     ///< for "y_from"
  std::optional<std::size_t> count_override;  ///< --spheres, for the one lattice / random generator
};

std::size_t read_count(const Object& o, const GeneratorContext& g) {
  const auto count = static_cast<std::size_t>(to_integer(o.required("count"), o.at("count"), 0, kMaxSpheres));
  return g.count_override.value_or(count);
}

/// "velocity" or "towards" {"point", "speed"}: the velocity of a sphere at `position`.
struct VelocityRule {
  Vec3 velocity = Vec3::Zero();
  bool towards = false;
  Vec3 point = Vec3::Zero();
  float speed = 0.0f;

  [[nodiscard]] Vec3 at(const Vec3& position) const {
    if (!towards) return velocity;
    const Vec3 offset = position - point;
    const float distance = offset.norm();
    return distance > 0.0f ? Vec3(-speed * offset / distance) : Vec3(Vec3::Zero());
  }
};

VelocityRule read_velocity_rule(const Object& o) {
  VelocityRule rule;
  rule.velocity = o.vec3("velocity", Vec3::Zero());
  if (o.has("towards")) {
    if (o.has("velocity")) o.where().fail("give \"velocity\" or \"towards\", not both");
    const Object t(o["towards"], o.at("towards"), {"point", "speed"});
    t.reject_unknown_keys();
    rule.towards = true;
    rule.point = t.vec3("point", Vec3::Zero());
    rule.speed = non_negative(t, "speed", 0.0f);
  }
  return rule;
}

void read_list(const json& list, const Where& at, const GeneratorContext& g, std::vector<SphereDesc>& out) {
  if (!list.is_array()) at.fail("must be an array of spheres, got " + got(list));
  for (std::size_t k = 0; k < list.size(); ++k) {
    const Object o(
        list[k], at.index(k),
        {"position", "velocity", "angular_velocity", "radius", "mass", "density", "restitution", "friction", "static"});
    o.reject_unknown_keys();
    const Material m = read_material(o, g.material);
    out.push_back(sphere(to_vec3(o.required("position"), o.at("position")), o.vec3("velocity", Vec3::Zero()),
                         o.vec3("angular_velocity", Vec3::Zero()), m));
  }
}

void read_lattice(const Object& o, const GeneratorContext& g, std::vector<SphereDesc>& out) {
  o.reject_unknown_keys();
  const std::size_t n = read_count(o, g);
  const Material m = read_material(o, g.material);
  enum class Layout { Layers, Cube };
  const Layout layout =
      o.choice<Layout>("layout", {{"layers", Layout::Layers}, {"cube", Layout::Cube}}).value_or(Layout::Layers);
  const float spacing = positive(o, "spacing", 2.0f * m.radius);
  Vec3 centre = o.vec3("centre", Vec3::Zero());
  enum class From { TerrainMin, TerrainMax };
  if (const auto from =
          o.choice<From>("y_from", {{"terrain-min", From::TerrainMin}, {"terrain-max", From::TerrainMax}})) {
    if (!g.terrain) o.at("y_from").fail("needs a terrain");
    const Heightmap& h = g.terrain->heightmap();
    centre.y() = (*from == From::TerrainMin ? h.min_height() : h.max_height()) + centre.y();
  }
  if (o.has("layer_side") && o.has("max_layer_side"))
    o.where().fail("give \"layer_side\" or \"max_layer_side\", not both");
  const auto side_limit = static_cast<std::size_t>(o.integer("max_layer_side", kMaxSpheres, 1, kMaxSpheres));
  const double root = layout == Layout::Layers ? std::ceil(std::sqrt(double(n))) : std::ceil(std::cbrt(double(n)));
  const std::size_t s = o.has("layer_side")
                            ? static_cast<std::size_t>(o.integer("layer_side", 1, 1, kMaxSpheres))
                            : std::max<std::size_t>(1, std::min(side_limit, static_cast<std::size_t>(root)));
  const VelocityRule velocity = read_velocity_rule(o);
  const Vec3 angular_velocity = o.vec3("angular_velocity", Vec3::Zero());

  out.reserve(out.size() + n);
  for (std::size_t k = 0; k < n; ++k) {
    Vec3 position;
    if (layout == Layout::Layers) {
      // terrain-rain's layering (docs/scenes.md): s/2 is a real division.
      const float half = static_cast<float>(s) / 2.0f;
      position = {centre.x() + (static_cast<float>(k % s) - half) * spacing,
                  centre.y() + static_cast<float>(k / (s * s)) * spacing,
                  centre.z() + (static_cast<float>((k / s) % s) - half) * spacing};
    } else {
      // implosion's cube: x fastest, then y, then z, centred on `centre`.
      const float c = 0.5f * static_cast<float>(s - 1);
      position = centre + spacing * Vec3(static_cast<float>(k % s) - c, static_cast<float>((k / s) % s) - c,
                                         static_cast<float>(k / (s * s)) - c);
    }
    out.push_back(sphere(position, velocity.at(position), angular_velocity, m));
  }
}

void read_random(const Object& o, const GeneratorContext& g, std::vector<SphereDesc>& out) {
  o.reject_unknown_keys();
  const std::size_t n = read_count(o, g);
  const json& seed_json = o.required("seed");
  if (!seed_json.is_number_integer() || (!seed_json.is_number_unsigned() && seed_json.get<std::int64_t>() < 0))
    o.at("seed").fail("must be an integer >= 0, got " + got(seed_json));
  const std::uint64_t seed = seed_json.get<std::uint64_t>();
  const Vec3 lo = to_vec3(o.required("box_min"), o.at("box_min"));
  const Vec3 hi = to_vec3(o.required("box_max"), o.at("box_max"));
  for (int a = 0; a < 3; ++a)
    if (!(lo[a] <= hi[a]))
      o.where().fail("box_min must be <= box_max on every axis, got " + got(o["box_min"]) + " and " +
                     got(o["box_max"]));
  const Material m = read_material(o, g.material, true);
  const auto radius = range(o, "radius", g.material.radius, false);
  enum class Spread { Uniform, LogUniform };
  const Spread radius_spread =
      o.choice<Spread>("radius_distribution", {{"uniform", Spread::Uniform}, {"log-uniform", Spread::LogUniform}})
          .value_or(Spread::Uniform);
  // The mass slot of the sequence draws a mass, or a density that makes the mass from the
  // radius (the generator's own key, else the top-level material's).
  const bool by_density = o.has("density") || (!o.has("mass") && g.material.density.has_value());
  const auto mass = by_density ? range(o, "density", g.material.density.value_or(0.0f), false)
                               : range(o, "mass", g.material.mass, false);
  if (by_density && !m.is_static) {  // the mass grows with both: the extremes bound every sphere's
    const Where at = o.has("density") ? o.at("density") : o.where();
    check_mass(mass_of(mass.first, radius.first), mass.first, radius.first, at);
    check_mass(mass_of(mass.second, radius.second), mass.second, radius.second, at);
  }
  const auto speed = range(o, "speed", 0.0f, true);

  // The documented sequence (docs/scene_format.md): per sphere x, y, z, radius, mass (or
  // density), speed, then direction triples until one lies inside the unit ball (and not at
  // its centre).
  std::mt19937_64 rng(seed);
  auto between = [&](float a, float b) { return a + (b - a) * unit_float(rng); };
  // min (max/min)^u: each decade of radii as likely as the next. In double, rounded once to
  // float, so any libm within an ulp of double gives the same float; clamped against rounding.
  auto log_between = [&](float a, float b) {
    const double r = double(a) * std::exp(double(unit_float(rng)) * std::log(double(b) / double(a)));
    return std::clamp(static_cast<float>(r), a, b);
  };
  out.reserve(out.size() + n);
  for (std::size_t k = 0; k < n; ++k) {
    Material mk = m;
    // One statement each: the arguments of one call are drawn in an order the compiler picks
    // (GCC: z, y, x), which made the scene differ between compilers.
    const float x = between(lo.x(), hi.x());
    const float y = between(lo.y(), hi.y());
    const float z = between(lo.z(), hi.z());
    const Vec3 position(x, y, z);
    mk.radius = radius_spread == Spread::LogUniform ? log_between(radius.first, radius.second)
                                                    : between(radius.first, radius.second);
    const float drawn = between(mass.first, mass.second);
    mk.mass = by_density ? mass_of(drawn, mk.radius) : drawn;
    const float v = between(speed.first, speed.second);
    float dx, dy, dz, length2;
    do {
      dx = 2.0f * unit_float(rng) - 1.0f;
      dy = 2.0f * unit_float(rng) - 1.0f;
      dz = 2.0f * unit_float(rng) - 1.0f;
      length2 = dx * dx + dy * dy + dz * dz;
    } while (!(length2 > 1e-6f && length2 <= 1.0f));
    const float scale = v / std::sqrt(length2);
    out.push_back(sphere(position, Vec3(dx * scale, dy * scale, dz * scale), Vec3::Zero(), mk));
  }
}

bool is_counted_generator(const json& j) { return j.is_object() && (j.contains("lattice") || j.contains("random")); }

/// Adds up the spheres every generator will make and refuses, before any is made, more than
/// kMaxSpheres or more than fit the memory limit beside the terrain (`terrain_bytes`).
/// Malformed generators are skipped here: the reader reports them where it meets them.
void check_sphere_total(const json& generators, const Where& at, const SceneOverrides& overrides,
                        double terrain_bytes) {
  std::uint64_t total = 0;
  for (std::size_t k = 0; k < generators.size(); ++k) {
    const json& g = generators[k];
    if (!g.is_object() || g.size() != 1) continue;
    const std::string& kind = g.begin().key();
    const json& body = g.begin().value();
    if (kind == "list" && body.is_array()) total += body.size();
    if ((kind == "lattice" || kind == "random") && body.is_object() && body.contains("count"))
      total += overrides.spheres ? *overrides.spheres
                                 : static_cast<std::uint64_t>(
                                       to_integer(body["count"], at.index(k).key(kind).key("count"), 0, kMaxSpheres));
  }
  if (total > static_cast<std::uint64_t>(kMaxSpheres))
    at.fail("makes " + std::to_string(total) + " spheres, more than " + std::to_string(kMaxSpheres));
  const MemoryLimit& limit = overrides.memory_limit;
  const double bytes = kBytesPerSphereGuide * double(total) + terrain_bytes;
  if (limit.bytes > 0.0 && bytes > limit.bytes)
    at.fail(
        "making " + std::to_string(total) + " spheres " +
        over_memory_limit(bytes,
                          std::to_string(static_cast<int>(kBytesPerSphereGuide)) +
                              " bytes a sphere, the most measured: docs/benchmarks.md, Memory" +
                              (terrain_bytes > 0.0 ? "; the terrain " + format_bytes(terrain_bytes) : std::string()),
                          limit));
}

// ---- adding to the World ----------------------------------------------------------------------
// The reader checks what it can before the World does, so that its messages name the field. What
// only the World checks (how far out a terrain may lie for its cell size, a plane's offset over
// its normal's length, a sphere's mass, speed or resolution where it lies) is named here by the
// path of the value the World refused.

/// World::set_terrain; the material was checked, so its refusal is of a terrain reaching so far
/// out that floats there do not resolve its cells (kTerrainCellResolution): named by the cell
/// size when the file gives one, else by the origin when it gives one, else by the terrain.
void set_terrain(World& world, const std::shared_ptr<const Terrain>& terrain, float restitution, float friction,
                 const Object& o) {
  try {
    world.set_terrain(terrain, restitution, friction);
  } catch (const InvalidArgument& e) {
    (o.has("cell_size") ? o.at("cell_size") : o.has("origin") ? o.at("origin") : o.where()).fail(e.what());
  }
}

/// World::add_plane; its refusal named by the plane's offset. The normal, the offset and the
/// material were checked, so what is left is the World's rule that offset / |normal| be a
/// finite float: the two numbers are added as %g (the World prints them with std::to_string).
void add_plane(World& world, const PlaneDesc& plane, const Where& at) {
  try {
    world.add_plane(plane);
  } catch (const InvalidArgument& e) {
    at.key("offset").fail(std::string(e.what()) + " (offset " + number_text(plane.offset) + " m, |normal| " +
                          number_text(plane.normal.norm()) + ")");
  }
}

/// The spheres one generator made: from sphere `first` on, until the next generator's first.
struct GeneratorSpheres {
  std::size_t first;
  Where at;  ///< "spheres[2].list", "spheres[0].random"
  bool is_list;
};

/// Refuses sphere `k` (World::add_sphere's message `why`) by the generator that made it: a list's
/// element by its path, a generated sphere by its place in the generator's sequence.
[[noreturn]] void refuse_sphere(const std::vector<GeneratorSpheres>& made_by, std::size_t k, const std::string& why) {
  const auto after = std::upper_bound(made_by.begin(), made_by.end(), k,
                                      [](std::size_t index, const GeneratorSpheres& g) { return index < g.first; });
  const GeneratorSpheres& g = *std::prev(after);  // made_by[0].first is 0
  if (g.is_list) g.at.index(k - g.first).fail(why);
  g.at.fail("sphere " + std::to_string(k - g.first) + " of this generator: " + why);
}

// ---- parsing -----------------------------------------------------------------------------------

/// What a value takes in nlohmann::json's document once parsed (libstdc++, 64 bits), to refuse
/// a document over the memory limit while it is parsed. From the layout: sizeof(json) is 16; an
/// array holds its elements in a std::vector (16 bytes each, up to twice that for the vector's
/// growth); an object's member is a std::map node (32 bytes of links, the std::string key and
/// the json: 96 with malloc's header); an object or array points to its std::map or std::vector
/// (48 or 24 bytes, 64 with the header); a string points to a std::string (48 with the header),
/// and a key or string over 15 characters (libstdc++'s in-place buffer) has its characters in
/// another block. Checked against glibc's mallinfo2 for json::parse of 200,000 spheres
/// ({"position": [1.5, 2.5, 3.5], "radius": 0.5}: 75 bytes a value here, 65 measured), of
/// 1,000,000 numbers in one array (32 here, 17 measured) and of nested one-key objects
/// (139 here, 135 measured): never below the measured heap.
constexpr double kJsonArrayElementBytes = 32.0;
constexpr double kJsonObjectMemberBytes = 96.0;
constexpr double kJsonContainerBytes = 64.0;
constexpr double kJsonStringBytes = 48.0;
constexpr std::size_t kJsonInPlaceChars = 15;

/// The heap a key or string's characters take beyond its std::string (none up to 15).
double string_chars_bytes(std::size_t length) { return length > kJsonInPlaceChars ? double(length) + 1.0 + 16.0 : 0.0; }

/// Refuses text over the memory limit before it is read or parsed: the parsed document takes
/// several times the text (about 9 for a list of spheres), so text alone over the limit cannot fit.
void check_text_size(const std::string& source, double text_bytes, const MemoryLimit& limit) {
  if (limit.bytes > 0.0 && text_bytes > limit.bytes)
    throw std::invalid_argument(source + ": the text " +
                                over_memory_limit(text_bytes, "the file's JSON text, before it is parsed", limit));
}

/// Builds the document from nlohmann's SAX events (json::sax_parse) and follows where in it the
/// parser is, so that a syntax error, a number beyond a double, a key given twice (nlohmann keeps
/// the last silently), nesting beyond kMaxSceneNesting and a document over the memory limit are
/// refused naming their path. Refusing deep nesting here, as the parser meets it, keeps every
/// later recursion over the document shallow. json::parse with a callback did the same, but
/// nlohmann's callback builder looks through the parent container for a discarded value after
/// every element: quadratic, over 25 s for a list of 400,000 spheres. The document is built
/// through json's public API, as nlohmann's own (internal) SAX builder builds it.
class DocumentBuilder {
 public:
  DocumentBuilder(json& doc, const std::string& source, std::size_t text_bytes, const MemoryLimit& limit)
      : doc_(doc), source_(source), text_bytes_(double(text_bytes)), limit_(limit) {}

  bool null() { return add_scalar(json(nullptr)); }
  bool boolean(bool value) { return add_scalar(json(value)); }
  bool number_integer(json::number_integer_t value) { return add_scalar(json(value)); }
  bool number_unsigned(json::number_unsigned_t value) { return add_scalar(json(value)); }
  bool number_float(json::number_float_t value, const json::string_t& /*text*/) { return add_scalar(json(value)); }
  bool string(json::string_t& value) {
    document_bytes_ += kJsonStringBytes + string_chars_bytes(value.size());
    return add_scalar(json(std::move(value)));
  }
  bool binary(json::binary_t& value) { return add_scalar(json::binary(std::move(value))); }
  bool start_object(std::size_t /*elements*/) { return open(json::object(), /*is_array=*/false); }
  bool start_array(std::size_t /*elements*/) { return open(json::array(), /*is_array=*/true); }
  bool key(json::string_t& name) {
    Frame& object = frames_.back();
    if (!object.keys.insert(name).second) {
      const Where at = container();
      at.fail("duplicate key \"" + name + "\"" + (at.path.empty() ? " at top level" : "") +
              " (a key may be given once)");
    }
    document_bytes_ += string_chars_bytes(name.size());
    member_ = &(*object.value)[name];
    object.key = std::move(name);
    return true;
  }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  /// A syntax error (its message has the line and column) or a number beyond a double (406),
  /// named by the path of the value being parsed.
  template <class Exception>
  [[noreturn]] bool parse_error(std::size_t /*position*/, const std::string& /*token*/, const Exception& error) {
    const bool beyond_double = std::is_same_v<Exception, json::out_of_range>;
    where().fail((beyond_double ? "must be a finite number (a double holds up to about 1.8e308): " : "") +
                 std::string(error.what()));
  }

  /// The value being parsed now ("spheres[2].random.count").
  [[nodiscard]] Where where() const { return path_through(frames_.size()); }

 private:
  struct Frame {
    json* value;  ///< the array or object, in the document
    bool is_array;
    std::size_t next_index;      ///< arrays: elements finished so far
    std::string key;             ///< objects: the latest key
    std::set<std::string> keys;  ///< objects: every key so far
  };

  /// Puts `value` where the parser is (the root, the next element of the open array or the
  /// open object's latest key) and returns it there.
  json* place(json&& value) {
    count_value();
    if (frames_.empty()) {
      doc_ = std::move(value);
      return &doc_;
    }
    json& container = *frames_.back().value;
    if (!container.is_array()) {
      *member_ = std::move(value);
      return member_;
    }
    container.push_back(std::move(value));
    return &container.back();
  }

  bool open(json&& empty, bool is_array) {
    if (frames_.size() >= static_cast<std::size_t>(kMaxSceneNesting))
      where().fail("arrays and objects nest deeper than " + std::to_string(kMaxSceneNesting) + " levels");
    document_bytes_ += kJsonContainerBytes;
    json* value = place(std::move(empty));
    frames_.push_back({.value = value, .is_array = is_array, .next_index = 0, .key = {}, .keys = {}});
    return true;
  }

  bool close() {
    frames_.pop_back();
    finish_element();
    return true;
  }

  /// A number, string, true, false or null: one whole element of its container.
  bool add_scalar(json&& value) {
    place(std::move(value));
    finish_element();
    return true;
  }

  /// Counts a value's place in its container and refuses the document once it and the text
  /// are over the memory limit.
  void count_value() {
    ++values_;
    document_bytes_ += frames_.empty() || frames_.back().is_array ? kJsonArrayElementBytes : kJsonObjectMemberBytes;
    if (limit_.bytes > 0.0 && text_bytes_ + document_bytes_ > limit_.bytes) refuse_over_memory_limit();
  }

  [[noreturn]] void refuse_over_memory_limit() const {
    const std::string why = "the text " + format_bytes(text_bytes_) + " and " + std::to_string(values_) +
                            " JSON values so far at " + std::to_string(std::lround(document_bytes_ / values_)) +
                            " bytes each in nlohmann::json; the parse stopped here";
    where().fail("the parsed document " + over_memory_limit(text_bytes_ + document_bytes_, why, limit_));
  }

  /// The innermost object or array itself.
  [[nodiscard]] Where container() const { return path_through(frames_.size() - 1); }

  /// The place the first `levels` frames point at.
  [[nodiscard]] Where path_through(std::size_t levels) const {
    std::string path;
    for (std::size_t k = 0; k < levels; ++k) {
      const Frame& f = frames_[k];
      if (f.is_array)
        path += "[" + std::to_string(f.next_index) + "]";
      else
        path += (path.empty() ? "" : ".") + f.key;
    }
    return {source_, path};
  }

  void finish_element() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().next_index;
  }

  json& doc_;
  const std::string& source_;
  double text_bytes_;
  const MemoryLimit& limit_;
  std::vector<Frame> frames_;
  json* member_ = nullptr;  ///< the open object's member for the latest key
  std::size_t values_ = 0;
  double document_bytes_ = 0.0;  ///< the estimate of the document so far, without the text
};

// ---- reading the file ----------------------------------------------------------------------------

/// What a path that is not a regular file is, for the message refusing it.
const char* describe_file_type(std::filesystem::file_type type) {
  using std::filesystem::file_type;
  switch (type) {
    case file_type::directory:
      return "a directory";
    case file_type::fifo:
      return "a pipe (FIFO)";
    case file_type::character:
      return "a character device";
    case file_type::block:
      return "a block device";
    case file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

/// The size of the regular file at `path` (after symbolic links). Anything else is refused by
/// its kind without being opened: opening a FIFO (`--scene <(generate)`) waits for a writer that
/// may never come, and a device has no size to bound the read (/dev/zero never ends).
std::uintmax_t regular_file_size(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found)
    throw std::invalid_argument(path + ": cannot open the scene file (no such file)");
  if (error) throw std::invalid_argument(path + ": cannot open the scene file (" + error.message() + ")");
  if (status.type() == fs::file_type::directory)
    throw std::invalid_argument(path + ": is a directory, not a scene file");
  if (status.type() != fs::file_type::regular)
    throw std::invalid_argument(path + ": is " + describe_file_type(status.type()) +
                                ", not a scene file (write the scene to a file)");
  const std::uintmax_t size = fs::file_size(path, error);
  if (error) throw std::invalid_argument(path + ": cannot read the scene file's size (" + error.message() + ")");
  return size;
}

/// The file's `size` bytes, and no more: a file that is shorter or longer by then changed while
/// it was read (one byte past `size` is read to notice it), and the memory limit was checked
/// against `size`.
std::string read_file_of_size(const std::string& path, std::uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open the scene file");
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  const auto got = static_cast<std::uintmax_t>(in.gcount());
  if (in.bad()) throw std::invalid_argument(path + ": cannot read the scene file");
  if (got != size || in.peek() != std::ifstream::traits_type::eof())
    throw std::invalid_argument(path + ": changed while being read (its size was " + std::to_string(size) + " bytes; " +
                                (got < size ? "only " + std::to_string(got) + " could be read" : "it held more") + ")");
  return text;
}

}  // namespace

Scene parse_scene_json(const json& doc, const std::string& source_name, const SceneOverrides& overrides,
                       const std::string& base_dir) {
  const Where root{source_name, ""};
  const Object top(doc, root,
                   {"format", "version", "description", "gravity", "dt", "steps", "threads", "settings", "terrain",
                    "planes", "meshes", "material", "spheres"});
  // The format and version first: a newer file's new keys should not read as typos.
  const std::optional<std::string> format = top.opt_string("format");
  if (format != "hail-scene")
    root.fail(format ? "\"format\" must be \"hail-scene\", got \"" + *format + "\""
                     : "missing \"format\": \"hail-scene\"");
  if (!top.has("version"))
    root.fail("missing required key \"version\" (this hail-bench reads version " + std::to_string(kSceneFormatVersion) +
              ")");
  const std::int64_t version = to_integer(top["version"], top.at("version"), 1, std::numeric_limits<int>::max());
  if (version != kSceneFormatVersion)
    top.at("version").fail("this hail-bench reads version " + std::to_string(kSceneFormatVersion) + ", got " +
                           std::to_string(version));
  top.reject_unknown_keys();

  Scene scene;
  scene.description = top.opt_string("description").value_or("scene file " + source_name);
  scene.dt = positive(top, "dt", 1.0f / 60.0f);
  scene.default_steps = static_cast<int>(top.integer("steps", 600, 1, std::numeric_limits<int>::max()));

  WorldSettings settings;
  settings.gravity = top.vec3("gravity", settings.gravity);
  settings.threads = static_cast<int>(top.integer("threads", 0, 0, 4096));
  if (top.has("settings")) read_settings(top["settings"], top.at("settings"), settings);

  // A dt the World would refuse on its first step (too many substeps: World::step's contract,
  // check_step) is refused now, naming the field or flag, before minutes of set-up.
  try {
    check_step(settings, overrides.dt ? *overrides.dt : scene.dt);
  } catch (const InvalidArgument& e) {
    const std::string why = std::string(e.what()).substr(std::string_view(e.what()).starts_with("hail: ") ? 6 : 0);
    if (overrides.dt) throw std::invalid_argument(source_name + ": --dt: " + why);
    (top.has("dt") ? top.at("dt") : root).fail(why);
  }

  // The spheres alone first, so that too many are refused before a terrain is built for them.
  if (top.has("spheres") && top["spheres"].is_array())
    check_sphere_total(top["spheres"], top.at("spheres"), overrides, 0.0);
  std::shared_ptr<const Terrain> terrain;
  float terrain_restitution = 0.5f, terrain_friction = 0.5f;
  if (top.has("terrain") && !top["terrain"].is_null())
    read_terrain(Object(top["terrain"], top.at("terrain"),
                        {"function", "heightmap", "format", "size", "cell_size", "height_scale", "height_offset",
                         "origin", "coefficient", "restitution", "friction"}),
                 base_dir, overrides.memory_limit, scene, terrain_restitution, terrain_friction, terrain);

  std::vector<PlaneDesc> planes;
  if (top.has("planes")) {
    const json& list = top["planes"];
    if (!list.is_array()) top.at("planes").fail("must be an array, got " + got(list));
    for (std::size_t k = 0; k < list.size(); ++k) {
      const Object p(list[k], top.at("planes").index(k), {"normal", "offset", "restitution", "friction"});
      p.reject_unknown_keys();
      const Vec3 normal = to_vec3(p.required("normal"), p.at("normal"));
      if (!(normal.norm() > 1e-6f)) p.at("normal").fail("must not be zero, got " + got(p["normal"]));
      planes.push_back({.normal = normal,
                        .offset = p.number("offset", 0.0f),
                        .restitution = unit_interval(p, "restitution", 0.5f),
                        .friction = non_negative(p, "friction", 0.5f)});
    }
  }

  // Meshes: loaded (and their files checked) now; added to the World with the planes.
  struct SceneMesh {
    TriangleMesh mesh;
    MeshTransform transform;
    float restitution, friction;
  };
  std::vector<SceneMesh> meshes;
  if (top.has("meshes")) {
    const json& list = top["meshes"];
    if (!list.is_array()) top.at("meshes").fail("must be an array, got " + got(list));
    for (std::size_t k = 0; k < list.size(); ++k) {
      const Object m(list[k], top.at("meshes").index(k),
                     {"file", "position", "rotation", "scale", "restitution", "friction"});
      m.reject_unknown_keys();
      if (!m.has("file")) m.where().fail("missing required key \"file\" (an .obj or .stl file)");
      std::filesystem::path path(*m.opt_string("file"));
      if (path.is_relative()) path = std::filesystem::path(base_dir) / path;
      MeshTransform transform{.position = m.vec3("position", Vec3(0, 0, 0)), .scale = positive(m, "scale", 1.0f)};
      if (m.has("rotation")) {
        const Object r(m["rotation"], m.at("rotation"), {"axis", "degrees"});
        r.reject_unknown_keys();
        transform.axis = r.vec3("axis", transform.axis);
        transform.degrees = r.number("degrees", 0.0f);
        try {
          transform.validate();
        } catch (const InvalidArgument& e) {
          r.where().fail(e.what());
        }
      }
      std::optional<TriangleMesh> mesh;
      try {
        mesh = TriangleMesh::load(path.string());
      } catch (const FileError& e) {
        m.at("file").fail(e.what());
      }
      meshes.push_back(
          {std::move(*mesh), transform, unit_interval(m, "restitution", 0.5f), non_negative(m, "friction", 0.5f)});
    }
  }

  GeneratorContext context{.material = {}, .terrain = terrain.get(), .count_override = std::nullopt};
  if (top.has("material")) {
    const Object m(top["material"], top.at("material"), {"radius", "mass", "density", "restitution", "friction"});
    m.reject_unknown_keys();
    context.material = read_material(m, {});
  }

  std::vector<SphereDesc> spheres;
  std::vector<GeneratorSpheres> made_by;
  if (top.has("spheres")) {
    const json& generators = top["spheres"];
    const Where at = top.at("spheres");
    if (!generators.is_array()) at.fail("must be an array of generators, got " + got(generators));
    if (overrides.spheres) {
      const auto counted = std::count_if(generators.begin(), generators.end(), is_counted_generator);
      if (counted != 1)
        at.fail("--spheres needs exactly one \"lattice\" or \"random\" generator to resize, the file has " +
                std::to_string(counted));
    }
    check_sphere_total(generators, at, overrides,
                       terrain ? terrain_bytes(terrain->heightmap().cols(), terrain->heightmap().rows()) : 0.0);
    for (std::size_t k = 0; k < generators.size(); ++k) {
      const Object gen(generators[k], at.index(k), {"list", "lattice", "random"});
      gen.reject_unknown_keys();
      if (generators[k].size() != 1) gen.where().fail("must have exactly one of \"list\", \"lattice\" or \"random\"");
      GeneratorContext g = context;
      if (is_counted_generator(generators[k])) g.count_override = overrides.spheres;
      made_by.push_back(
          {.first = spheres.size(), .at = gen.at(generators[k].begin().key()), .is_list = gen.has("list")});
      if (gen.has("list")) {
        read_list(gen["list"], gen.at("list"), g, spheres);
      } else if (gen.has("lattice")) {
        read_lattice(
            Object(gen["lattice"], gen.at("lattice"),
                   {"count", "layout", "layer_side", "max_layer_side", "spacing", "centre", "y_from", "velocity",
                    "towards", "angular_velocity", "radius", "mass", "density", "restitution", "friction", "static"}),
            g, spheres);
      } else {
        read_random(Object(gen["random"], gen.at("random"),
                           {"count", "seed", "box_min", "box_max", "radius", "radius_distribution", "mass", "density",
                            "speed", "restitution", "friction", "static"}),
                    g, spheres);
      }
    }
  }

  // The command line has the last word.
  if (overrides.threads) settings.threads = *overrides.threads;
  if (overrides.steps) scene.default_steps = *overrides.steps;
  if (overrides.dt) scene.dt = *overrides.dt;
  try {
    set_settings(settings, overrides.set);
  } catch (const std::invalid_argument& e) {
    root.fail(e.what());
  }

  // Every value was checked above; the World checks again, and its message gets the file's name.
  try {
    scene.world = std::make_unique<World>(settings);
  } catch (const InvalidArgument& e) {
    root.fail(e.what());
  }
  if (terrain)
    set_terrain(*scene.world, terrain, terrain_restitution, terrain_friction,
                Object(top["terrain"], top.at("terrain"), {}));
  for (std::size_t k = 0; k < planes.size(); ++k) add_plane(*scene.world, planes[k], top.at("planes").index(k));
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    try {
      scene.world->add_mesh(meshes[k].mesh, meshes[k].transform, meshes[k].restitution, meshes[k].friction);
    } catch (const InvalidArgument& e) {
      top.at("meshes").index(k).fail(e.what());
    }
  }
  scene.world->reserve(spheres.size());
  scene.ids.reserve(spheres.size());
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    try {
      scene.ids.push_back(scene.world->add_sphere(spheres[k]));
    } catch (const InvalidArgument& e) {
      refuse_sphere(made_by, k, e.what());
    }
  }
  return scene;
}

Scene parse_scene_text(std::string_view text, const std::string& source_name, const SceneOverrides& overrides,
                       const std::string& base_dir) {
  check_text_size(source_name, double(text.size()), overrides.memory_limit);
  json doc;
  DocumentBuilder builder(doc, source_name, text.size(), overrides.memory_limit);
  try {
    json::sax_parse(text, &builder, json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true);
  } catch (const json::exception& e) {  // parse errors end in the builder; anything else is named here
    builder.where().fail(e.what());
  }
  return parse_scene_json(doc, source_name, overrides, base_dir);
}

Scene load_scene_file(const std::string& path, const SceneOverrides& overrides) {
  const std::uintmax_t size = regular_file_size(path);
  check_text_size(path, double(size), overrides.memory_limit);
  const std::string text = read_file_of_size(path, size);
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  return parse_scene_text(text, path, overrides, folder.empty() ? std::string(".") : folder.string());
}

}  // namespace hail::bench
