#pragma once
// Every WorldSettings field, declared once: its name (also its scene-file key, "soft_step.substeps"
// inside the "settings" object), its valid range, one line of documentation, and where it
// travels: a snapshot, a scene file (inside "settings", or at the top level), hail-bench's
// command line. From this one list:
// - World::validate checks every range (InvalidArgument naming the field and its range);
// - snapshots save and read the fields it marks, in its order (kernel/world/snapshot_format.h);
// - scene files read their keys (scenes/scene_file.cpp);
// - hail-bench makes its setting flags (--resting, --solver, ...) and --set NAME=VALUE
//   (bench/setting_flags.cpp, scenes/setting_text.cpp);
// - the settings table of docs/embedding.md is written (tests/test_settings_table.cpp checks
//   that the page matches it);
// and any program (an engine's settings UI, bindings) can walk it: for_each_setting.
// Adding a setting means a field in WorldSettings, a line here, and the code that uses it.
//
// The order is the snapshot's byte order: append new settings, never reorder (a snapshot reader
// of an older version relies on it), and raise kSnapshotVersion when a carried setting is added.

#include <cfloat>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "hail/world_settings.h"

namespace hail {

/// A setting's range and where it travels. A number must lie in [min, max] (an end is open where
/// min_open / max_open say so) and be finite unless `infinity` allows +infinity; a Vec3 must be
/// finite; an enum must be one of `values` ("|"-separated names, in the enum's order: the names
/// scene files and the command line use); a bool is any bool.
struct SettingSpec {
  const char* name;
  double min = 0.0;
  double max = 0.0;
  bool min_open = false;
  bool max_open = false;
  bool infinity = false;
  const char* values = nullptr;
  /// Saved in snapshots (all but threads: a restored World keeps its own threads or arena).
  bool snapshot = true;
  /// A scene file gives it at its top level ("gravity": [0, -9.81, 0]) rather than inside its
  /// "settings" object.
  bool scene_top_level = false;
  /// hail-bench's flag for it, without the dashes ("resting" is --resting N), or none: every
  /// setting also takes --set NAME=VALUE.
  const char* flag = nullptr;
  const char* doc = "";
};

namespace settings_detail {
inline constexpr double kFloatMax = FLT_MAX;
inline constexpr double kIntMax = INT_MAX;
}  // namespace settings_detail

/// Calls f(field, spec) for every setting of `s` (a WorldSettings, const or not), in the table's
/// order. `field` is a reference to the member itself.
template <class Settings, class F>
constexpr void for_each_setting(Settings& s, F&& f) {
  using settings_detail::kFloatMax;
  using settings_detail::kIntMax;
  // A field added to WorldSettings changes its size (mostly): list it here.
  static_assert(sizeof(WorldSettings) == 168, "a WorldSettings field was added: list it in for_each_setting");
  f(s.gravity, SettingSpec{.name = "gravity",
                           .scene_top_level = true,
                           .doc = "m/s^2; |g| times the longest step (max_substeps * max_substep) at most "
                                  "kMaxSphereSpeed"});
  f(s.time_scale, SettingSpec{.name = "time_scale", .max = kFloatMax, .doc = "simulated seconds per second; 0 pauses"});
  f(s.max_substep, SettingSpec{.name = "max_substep",
                               .min = kMinStep,
                               .max = kFloatMax,
                               .doc = "s; longer steps (after time_scale) are split into equal substeps"});
  f(s.max_substeps, SettingSpec{.name = "max_substeps",
                                .min = 1,
                                .max = kMaxSubstepsCap,
                                .doc = "most substeps one step may take; a step needing more is refused"});
  f(s.integrator, SettingSpec{.name = "integrator",
                              .values = "semi-implicit-euler|uniform-acceleration",
                              .flag = "integrator",
                              .doc = "how positions follow velocities"});
  f(s.solver, SettingSpec{.name = "solver", .values = "passes|soft", .flag = "solver", .doc = "the contact solver"});
  f(s.soft_step.substeps, SettingSpec{.name = "soft_step.substeps",
                                      .min = 1,
                                      .max = kMaxIterations,
                                      .flag = "substeps",
                                      .doc = "soft step: substeps per step"});
  f(s.soft_step.contact_cycles, SettingSpec{.name = "soft_step.contact_cycles",
                                            .min = 0,
                                            .max = 0.25,
                                            .min_open = true,
                                            .flag = "contact-cycles",
                                            .doc = "soft step: contact stiffness, cycles per substep"});
  f(s.soft_step.damping_ratio, SettingSpec{.name = "soft_step.damping_ratio",
                                           .min = 0,
                                           .max = kFloatMax,
                                           .min_open = true,
                                           .flag = "damping-ratio",
                                           .doc = "soft step: contact damping ratio"});
  f(s.soft_step.relax_iterations, SettingSpec{.name = "soft_step.relax_iterations",
                                              .max = kMaxIterations,
                                              .flag = "relax",
                                              .doc = "soft step: rigid iterations after each soft one"});
  f(s.soft_step.max_push_speed, SettingSpec{.name = "soft_step.max_push_speed",
                                            .min = 0,
                                            .max = kFloatMax,
                                            .min_open = true,
                                            .doc = "soft step: m/s, fastest push out of an overlap"});
  f(s.soft_step.depenetration_iterations_max,
    SettingSpec{.name = "soft_step.depenetration_iterations_max",
                .max = kMaxIterations,
                .flag = "depenetration-max",
                .doc = "soft step: most depenetration passes for small spheres"});
  f(s.collision_iterations,
    SettingSpec{.name = "collision_iterations", .max = kMaxIterations, .doc = "passes that bounce closing contacts"});
  f(s.resting_iterations, SettingSpec{.name = "resting_iterations",
                                      .max = kMaxIterations,
                                      .flag = "resting",
                                      .doc = "sequential-impulse passes for resting contacts"});
  f(s.depenetration_iterations, SettingSpec{.name = "depenetration_iterations",
                                            .max = kMaxIterations,
                                            .doc = "position-correction passes after integration"});
  f(s.solver_tile_spheres, SettingSpec{.name = "solver_tile_spheres",
                                       .max = 100'000'000,
                                       .flag = "tile",
                                       .doc = "spheres per solver tile: 0 (no tiles) or at least "
                                              "kMinSolverTileSpheres"});
  f(s.depenetration.fraction,
    SettingSpec{.name = "depenetration.fraction", .max = 1, .doc = "share of the excess overlap removed per pass"});
  f(s.depenetration.slop_fraction, SettingSpec{.name = "depenetration.slop_fraction",
                                               .max = kFloatMax,
                                               .doc = "overlap tolerated, as a fraction of the smaller radius"});
  f(s.restitution_threshold, SettingSpec{.name = "restitution_threshold",
                                         .max = kFloatMax,
                                         .doc = "m/s; closing speeds below max(this, 2 |g| dt) rest, not bounce"});
  f(s.sphere_collisions, SettingSpec{.name = "sphere_collisions", .doc = "spheres meet each other"});
  f(s.pair_search, SettingSpec{.name = "pair_search",
                               .values = "auto|brute|grid|sweep|bvh",
                               .flag = "pairs",
                               .doc = "how sphere pairs are found (speed only: every search finds the same pairs)"});
  f(s.speculative_radii, SettingSpec{.name = "speculative_radii",
                                     .max = kFloatMax,
                                     .doc = "cap of the speculative pair margin, in radii of the larger sphere"});
  f(s.max_sphere_contacts_per_sphere, SettingSpec{.name = "max_sphere_contacts_per_sphere",
                                                  .min = 1,
                                                  .max = 1'000'000,
                                                  .doc = "guard: sphere contacts a step may make, per sphere"});
  f(s.pair_margin_travel, SettingSpec{.name = "pair_margin_travel",
                                      .max = kFloatMax,
                                      .doc = "a pair's own margin, in distances its spheres close per step"});
  f(s.reorder_interval, SettingSpec{.name = "reorder_interval",
                                    .max = kIntMax,
                                    .flag = "reorder",
                                    .doc = "steps between Morton re-sorts of the slots; 0 never"});
  f(s.warm_start_factor, SettingSpec{.name = "warm_start_factor",
                                     .max = 1,
                                     .flag = "warm-start",
                                     .doc = "share of last step's impulses a contact starts with; 0 turns warm "
                                            "starting off"});
  f(s.continuous_collision,
    SettingSpec{
        .name = "continuous_collision", .flag = "ccd", .doc = "fast spheres move impact by impact (no tunnelling)"});
  f(s.fast_travel_fraction, SettingSpec{.name = "fast_travel_fraction",
                                        .min = 0,
                                        .max = 1,
                                        .min_open = true,
                                        .doc = "radii a sphere travels in a step before it is swept"});
  f(s.max_sweep_events,
    SettingSpec{
        .name = "max_sweep_events", .min = 1, .max = kIntMax, .doc = "guard: impacts of one swept sphere per step"});
  f(s.shock_mass_ratio, SettingSpec{.name = "shock_mass_ratio",
                                    .min = 1,
                                    .max = kFloatMax,
                                    .infinity = true,
                                    .doc = "mass ratio from which shock propagation runs; infinity never"});
  f(s.rotation,
    SettingSpec{.name = "rotation", .flag = "rotation", .doc = "spheres spin and roll (off: no angular work)"});
  f(s.rolling_resistance, SettingSpec{.name = "rolling_resistance",
                                      .max = kFloatMax,
                                      .flag = "rolling-resistance",
                                      .doc = "torque opposing rolling, mu_r r N (0: none; the passes solver)"});
  f(s.sleep, SettingSpec{.name = "sleep", .flag = "sleep", .doc = "islands at rest sleep until woken"});
  f(s.sleep_linear_speed,
    SettingSpec{.name = "sleep_linear_speed", .max = kFloatMax, .doc = "m/s below which a sphere may sleep"});
  f(s.sleep_angular_speed,
    SettingSpec{.name = "sleep_angular_speed", .max = kFloatMax, .doc = "rad/s below which a sphere may sleep"});
  f(s.sleep_time, SettingSpec{.name = "sleep_time", .max = kFloatMax, .doc = "s an island rests before it sleeps"});
  f(s.threads, SettingSpec{.name = "threads",
                           .max = 4096,
                           .snapshot = false,
                           .scene_top_level = true,
                           .doc = "worker threads; 0 all hardware threads (ignored with the caller's arena)"});
}

/// How many values an enum setting has: the names in spec.values.
constexpr std::size_t setting_value_count(const SettingSpec& spec) {
  if (!spec.values) return 0;
  std::size_t count = 1;
  for (const char* c = spec.values; *c; ++c) count += *c == '|' ? 1 : 0;
  return count;
}

/// The name of an enum setting's value number `index` (< setting_value_count): "soft" for
/// solver 1.
constexpr std::string_view setting_value_name(const SettingSpec& spec, std::size_t index) {
  std::string_view rest = spec.values;
  for (; index > 0; --index) rest.remove_prefix(rest.find('|') + 1);
  return rest.substr(0, rest.find('|'));
}

/// The number of an enum setting's value called `name`, or setting_value_count(spec) if none is.
constexpr std::size_t setting_value_index(const SettingSpec& spec, std::string_view name) {
  std::size_t index = 0;
  while (index < setting_value_count(spec) && setting_value_name(spec, index) != name) ++index;
  return index;
}

/// A number's range as the messages and docs write it: "[0, 1000]", "(0, 0.25]", "[0, inf)";
/// whole numbers in full ("2147483647"), others as printf's %g.
inline std::string setting_range_text(const SettingSpec& spec) {
  auto end = [](double v) {
    if (v >= settings_detail::kFloatMax) return std::string("inf");
    char text[32];
    std::snprintf(text, sizeof text, v == std::floor(v) && std::fabs(v) < 1e15 ? "%.0f" : "%g", v);
    return std::string(text);
  };
  return std::string(spec.min_open ? "(" : "[") + end(spec.min) + ", " + end(spec.max) +
         (spec.max_open || spec.max >= settings_detail::kFloatMax ? ")" : "]");
}

}  // namespace hail
