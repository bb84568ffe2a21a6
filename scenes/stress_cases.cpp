#include "scenes/stress_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "hail/triangle_mesh.h"
#include "scenes/mesh_shapes.h"
#include "scenes/scenes.h"
#include "scenes/steep_heightmaps.h"

namespace hail::bench {
namespace {

using clock_type = std::chrono::steady_clock;

std::shared_ptr<const Terrain> flat_terrain(int side = 64, float height = 0.0f, HeightmapParams params = {}) {
  return std::make_shared<const Terrain>(
      Heightmap::from_function(side, side, params, [=](float, float) { return height; }));
}

std::shared_ptr<const Terrain> rain_terrain(HeightmapParams params = {}, float lift = 0.0f) {
  return std::make_shared<const Terrain>(Heightmap::from_function(256, 256, params, [&](float x, float z) {
    return lift + terrain_rain_height(x - params.origin_x, z - params.origin_z);
  }));
}

std::string format(const char* fmt, double a, double b = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, fmt, a, b);
  return buffer;
}

/// Steps the world `steps` times of dt, watching every step (pairs every `pair_every` steps).
StressResult watch(World& world, const std::string& name, const std::string& invariants, int steps, float dt,
                   StressBounds bounds, double energy_scale = 1.0, double momentum_scale = 1.0, int pair_every = 1) {
  StressResult r;
  r.name = name, r.invariants = invariants, r.bounds = bounds;
  StressWatch w(world, energy_scale, momentum_scale);
  const auto t0 = clock_type::now();
  for (int k = 0; k < steps; ++k) {
    world.step(dt);
    w.after_step(world, (k + 1) % pair_every == 0 || k + 1 == steps);
  }
  r.wall_s = std::chrono::duration<double>(clock_type::now() - t0).count();
  r.worst = w.worst();
  judge(r);
  return r;
}

/// Folds one run of a case with several variants into the case: worst of the worst values,
/// failures labelled with the variant.
void merge_into(StressResult& all, const StressResult& r, const std::string& label) {
  all.wall_s += r.wall_s;
  StressWorst& a = all.worst;
  a.non_finite = std::max(a.non_finite, r.worst.non_finite);
  a.below_surface = std::max(a.below_surface, r.worst.below_surface);
  a.sphere_penetration = std::max(a.sphere_penetration, r.worst.sphere_penetration);
  a.ground_penetration = std::max(a.ground_penetration, r.worst.ground_penetration);
  a.energy_growth = std::max(a.energy_growth, r.worst.energy_growth);
  a.momentum_drift = std::max(a.momentum_drift, r.worst.momentum_drift);
  a.steps += r.worst.steps;
  for (const std::string& f : r.failures) all.failures.push_back(label + f);
}

/// The contact solver of the cases being run (stress_cases' argument): every case builds its
/// world from all_threads() (or SceneParams), so the battery runs with either solver without
/// a parameter threaded through each case.
Solver battery_solver = Solver::Passes;

WorldSettings all_threads() {
  WorldSettings s;
  s.threads = 0;
  s.solver = battery_solver;
  return s;
}

/// A 3 x 3 layer of light spheres touching on flat ground, a heavy one resting in the middle
/// hollow on top.
StressResult heavy_on_light() {
  World w(all_threads());
  w.set_terrain(flat_terrain(), 0.5f, 0.5f);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) w.add_sphere({.position = {31.0f + i, 0.5f, 31.0f + j}, .radius = 0.5f, .mass = 1.0f});
  // Resting on the four around (31.5, 31.5): centre sqrt(1 - 0.5) above their centres.
  w.add_sphere({.position = {31.5f, 0.5f + std::sqrt(0.5f), 31.5f}, .radius = 0.5f, .mass = 1e4f});
  return watch(w, "mass-ratio-1e4-on-1", "1e4 kg sphere on nine 1 kg spheres on flat ground, 10 s", 600, 1.0f / 60.0f,
               {});
}

/// Three spheres stacked straight up on flat ground: 1 kg at the bottom, then 100 kg, then 1e4 kg.
StressResult stack_ratios() {
  World w(all_threads());
  w.set_terrain(flat_terrain(), 0.5f, 0.5f);
  const float masses[3] = {1.0f, 100.0f, 1e4f};
  for (int k = 0; k < 3; ++k)
    w.add_sphere({.position = {32.0f, 0.5f + k * 1.0f, 32.0f}, .radius = 0.5f, .mass = masses[k]});
  return watch(w, "stack-1-100-1e4", "vertical stack 1 : 100 : 10,000 kg (bottom to top) on flat ground, 10 s", 600,
               1.0f / 60.0f, {});
}

/// A 1e-3 kg sphere at rest hit head-on by a 1e3 kg one at 10 m/s, e = 1, no gravity.
StressResult light_hit_by_heavy() {
  WorldSettings s = all_threads();
  s.gravity = Vec3(0, 0, 0);
  World w(s);
  const SphereId light =
      w.add_sphere({.position = {2, 0, 0}, .radius = 0.5f, .mass = 1e-3f, .restitution = 1, .friction = 0});
  w.add_sphere(
      {.position = {-2, 0, 0}, .velocity = {10, 0, 0}, .radius = 0.5f, .mass = 1e3f, .restitution = 1, .friction = 0});
  StressBounds b;
  b.energy_growth = 1e-5, b.momentum_drift = 1e-6;
  StressResult r =
      watch(w, "light-hit-by-heavy", "1e-3 kg hit by 1e3 kg at 10 m/s, e = 1, no gravity: momentum and energy held",
            120, 1.0f / 60.0f, b, 1.0, 1.0);
  const double expected = 2.0 * 1e3 / (1e3 + 1e-3) * 10.0;
  const double got = w.velocity(light).x();
  r.note = format("light sphere leaves at %.6g m/s (exact %.6g)", got, expected);
  if (std::fabs(got - expected) > 1e-4 * expected) r.failures.push_back("light sphere's velocity off: " + r.note);
  return r;
}

/// Radius 0.01 spheres rained onto radius 10 spheres resting on flat ground.
StressResult small_among_large() {
  World w(all_threads());
  w.set_terrain(flat_terrain(128), 0.5f, 0.5f);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      w.add_sphere({.position = {40.0f + 20.0f * i, 10.0f, 40.0f + 20.0f * j}, .radius = 10.0f, .mass = 1000.0f});
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int k = 0; k < 200; ++k)
    w.add_sphere({.position = {35.0f + 50.0f * u(rng), 22.0f + 5.0f * u(rng), 35.0f + 50.0f * u(rng)},
                  .radius = 0.01f,
                  .mass = 1e-3f});
  return watch(w, "radius-0.01-among-10", "200 spheres of radius 0.01 onto nine of radius 10 on flat ground, 5 s", 300,
               1.0f / 60.0f, {});
}

/// Spheres at 1e4 m/s into terrain-rain's terrain, continuous collision on.
StressResult bullets_1e4() {
  World w(all_threads());
  w.set_terrain(rain_terrain(), 0.5f, 0.5f);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int k = 0; k < 100; ++k) {
    const float a = 6.2831853f * u(rng), dip = 0.3f + 1.2f * u(rng);
    w.add_sphere({.position = {40.0f + 170.0f * u(rng), 20.0f + 20.0f * u(rng), 40.0f + 170.0f * u(rng)},
                  .velocity = Vec3(std::cos(a) * std::cos(dip), -std::sin(dip), std::sin(a) * std::cos(dip)) * 1e4f,
                  .radius = 0.25f,
                  .mass = 1.0f});
  }
  return watch(w, "speed-1e4-into-terrain", "100 spheres at 1e4 m/s into terrain-rain's terrain, 2 s", 120,
               1.0f / 60.0f, {}, 1.0, 1.0);
}

/// A 1e4 m/s sphere into a resting pile on flat ground.
StressResult bullet_into_pile() {
  World w(all_threads());
  w.set_terrain(flat_terrain(), 0.5f, 0.5f);
  for (int y = 0; y < 3; ++y)
    for (int z = 0; z < 4; ++z)
      for (int x = 0; x < 4; ++x)
        w.add_sphere({.position = {30.0f + x, 0.5f + y, 30.0f + z}, .radius = 0.5f, .mass = 1.0f});
  for (int k = 0; k < 120; ++k) w.step(1.0f / 60.0f);  // settle
  w.add_sphere({.position = {5.0f, 1.0f, 31.2f}, .velocity = {1e4f, 0.0f, 0.0f}, .radius = 0.5f, .mass = 1.0f});
  return watch(w, "speed-1e4-into-pile", "a 1e4 m/s sphere into a settled pile of 48 on flat ground, 2 s", 120,
               1.0f / 60.0f, {});
}

/// The same small pile on terrain-rain's terrain at dt from 1e-5 s to 1/20 s, 0.5 s each.
StressResult time_steps() {
  StressResult all;
  all.name = "dt-1e-5-to-1/20";
  all.invariants = "27 spheres dropped on terrain-rain's terrain at dt 1e-5, 1e-4, 1e-3, 1/60, 1/20 (0.5 s each)";
  for (const float dt : {1e-5f, 1e-4f, 1e-3f, 1.0f / 60.0f, 1.0f / 20.0f}) {
    World w(all_threads());
    w.set_terrain(rain_terrain(), 0.5f, 0.5f);
    for (int k = 0; k < 27; ++k)
      w.add_sphere({.position = {127.0f + (k % 3), 12.0f + (k / 9) * 1.0f, 127.0f + ((k / 3) % 3)},
                    .radius = 0.45f,
                    .mass = 1.0f});
    const int steps = static_cast<int>(std::lround(0.5 / dt));
    const StressResult r = watch(w, all.name, all.invariants, steps, dt, {}, 100.0, 1.0, steps > 1000 ? 100 : 1);
    merge_into(all, r, format("dt %.3g: ", dt));
  }
  return all;
}

/// Coincident centres, and spheres placed exactly on triangle edges and vertices.
StressResult coincident_and_edges() {
  World w(all_threads());
  w.set_terrain(rain_terrain(), 0.5f, 0.5f);
  w.add_sphere({.position = {100.0f, 20.0f, 100.0f}, .radius = 0.5f, .mass = 1.0f});
  w.add_sphere({.position = {100.0f, 20.0f, 100.0f}, .radius = 0.5f, .mass = 1.0f});  // same centre
  const Heightmap& h = w.terrain()->heightmap();
  for (int i = 60; i < 64; ++i) {
    // Lowest point exactly on vertex (i, 60), and on the midpoint of the diagonal of cell (i, 62).
    w.add_sphere({.position = {float(i), h.h(i, 60) + 0.5f, 60.0f}, .radius = 0.5f, .mass = 1.0f});
    const float mx = i + 0.5f, mz = 62.5f;
    w.add_sphere({.position = {mx, h.surface_height(mx, mz) + 0.5f, mz}, .radius = 0.5f, .mass = 1.0f});
  }
  StressBounds b;
  b.sphere_penetration = 2.1;  // the coincident pair starts fully overlapped; the case checks it is pushed apart
  StressResult r =
      watch(w, "coincident-and-on-edges", "two spheres with the same centre; spheres on vertices and edges, 3 s", 180,
            1.0f / 60.0f, b, 10.0);
  const SphereState s = w.spheres();
  double closest = 1e9;
  for (std::size_t i = 0; i < w.sphere_count(); ++i)
    for (std::size_t j = i + 1; j < w.sphere_count(); ++j) {
      const double dx = s.px[j] - s.px[i], dy = s.py[j] - s.py[i], dz = s.pz[j] - s.pz[i];
      closest = std::min(closest, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
  r.note = format("closest centres at the end %.4g m (touching: 1)", closest);
  if (closest < 0.95) r.failures.push_back("spheres still overlapping at the end: " + r.note);
  return r;
}

/// A vertical 10 m cliff and one-cell spikes 8 m high; spheres rain onto both.
StressResult cliffs_and_spikes() {
  World w(all_threads());
  auto terrain = std::make_shared<const Terrain>(Heightmap::from_function(64, 64, {}, [](float x, float z) {
    if (int(x) == 20 && int(z) % 8 == 4) return 8.0f;  // spikes one vertex wide
    return x < 32.0f ? 10.0f : 0.0f;                   // the cliff between x = 31 and 32
  }));
  w.set_terrain(terrain, 0.5f, 0.5f);
  for (int k = 0; k < 100; ++k)
    w.add_sphere({.position = {16.0f + (k % 10) * 2.0f, 14.0f + (k / 50), 4.0f + ((k / 10) % 5) * 12.0f},
                  .velocity = {6.0f, 0.0f, 0.0f},
                  .radius = 0.4f,
                  .mass = 1.0f});
  return watch(w, "cliff-and-spikes", "100 spheres rolled over a 10 m vertical cliff and 8 m one-vertex spikes, 6 s",
               360, 1.0f / 60.0f, {}, 100.0);
}

/// terrain-rain's terrain lifted to 1e4 m, and moved 1e4 m and 1e5 m away from the origin.
StressResult far_away(float offset, float lift, const char* name) {
  World w(all_threads());
  HeightmapParams params;
  params.origin_x = offset, params.origin_z = offset;
  w.set_terrain(rain_terrain(params, lift), 0.5f, 0.5f);
  for (int k = 0; k < 100; ++k)
    w.add_sphere({.position = {offset + 120.0f + (k % 10) * 1.5f, lift + 13.0f, offset + 120.0f + (k / 10) * 1.5f},
                  .radius = 0.5f,
                  .mass = 1.0f});
  StressBounds b;
  b.energy_growth = 0.01;
  return watch(w, name, "100 spheres raining onto terrain-rain's terrain, moved away from the origin, 5 s", 300,
               1.0f / 60.0f, b, 1000.0);
}

/// Restitution 0 and 1, friction 0 and 10, time scale 0 and 100 on a small rain.
StressResult materials_and_time_scale() {
  StressResult all;
  all.name = "materials-and-time-scale";
  all.invariants = "27 spheres on terrain-rain's terrain with e 0 / 1, mu 0 / 10, time scale 0 / 100, 2 s each";
  struct Variant {
    float e, mu, scale;
  };
  for (const Variant v : {Variant{0, 0.5f, 1}, Variant{1, 0.5f, 1}, Variant{0.5f, 0, 1}, Variant{0.5f, 10, 1},
                          Variant{0.5f, 0.5f, 0}, Variant{0.5f, 0.5f, 100}}) {
    WorldSettings s = all_threads();
    s.time_scale = v.scale;
    World w(s);
    w.set_terrain(rain_terrain(), v.e, v.mu);
    for (int k = 0; k < 27; ++k)
      w.add_sphere({.position = {127.0f + (k % 3), 12.0f + (k / 9) * 1.0f, 127.0f + ((k / 3) % 3)},
                    .radius = 0.45f,
                    .mass = 1.0f,
                    .restitution = v.e,
                    .friction = v.mu});
    const StressResult r = watch(w, all.name, all.invariants, 120, 1.0f / 60.0f, {}, 100.0);
    char label[64];
    std::snprintf(label, sizeof label, "e %g, mu %g, time scale %g: ", v.e, v.mu, v.scale);
    merge_into(all, r, label);
  }
  return all;
}

/// 27 spheres on flat ground at time scales 300 (100 substeps a step) and 750 (250 of the 256
/// allowed), 1 s of frames each; a time scale past the limit is refused, the world unchanged.
StressResult long_time_steps() {
  StressResult all;
  all.name = "time-scale-300-and-750";
  all.invariants = "27 spheres on flat ground at time scale 300 and 750 (each 1/60 s frame 5 and 12.5 s); 1e4 refused";
  for (const float scale : {300.0f, 750.0f}) {
    WorldSettings s = all_threads();
    s.time_scale = scale;
    World w(s);
    w.set_terrain(flat_terrain(), 0.5f, 0.5f);
    for (int k = 0; k < 27; ++k)
      w.add_sphere(
          {.position = {31.0f + (k % 3), 0.5f + (k / 9), 31.0f + ((k / 3) % 3)}, .radius = 0.5f, .mass = 1.0f});
    merge_into(all, watch(w, all.name, all.invariants, scale < 500 ? 18 : 6, 1.0f / 60.0f, {}, 100.0),
               format("time scale %g: ", scale));
  }
  WorldSettings past = all_threads();
  past.time_scale = 1e4f;
  World w(past);
  w.add_sphere({.position = {0, 1, 0}});
  const std::uint64_t before = w.state_hash();
  bool refused = false;
  try {
    w.step(1.0f / 60.0f);
  } catch (const InvalidArgument&) {
    refused = true;
  }
  if (!refused || w.state_hash() != before)
    all.failures.push_back("time scale 1e4 (2,778 substeps) was not refused cleanly");
  all.note = "time scale 1e4 refused (max_substeps)";
  return all;
}

/// Spheres of radius 1e-4 near the origin and of radius 1e4 far out, on planes.
StressResult radius_extremes() {
  StressResult all;
  all.name = "radius-1e-4-and-1e4";
  all.invariants =
      "8 spheres of radius 1e-4 (a pile at the origin) and 3 of radius 1e4 (rolling on a tilted plane), 2 s";
  {
    World w(all_threads());
    w.add_plane({});
    for (int k = 0; k < 8; ++k)
      w.add_sphere({.position = {0.0002f * (k % 2), 0.0001f + 0.0002f * (k / 4), 0.0002f * ((k / 2) % 2)},
                    .radius = 1e-4f,
                    .mass = 1e-9f});
    merge_into(all, watch(w, all.name, all.invariants, 120, 1.0f / 60.0f, {}, 1e-12), "radius 1e-4: ");
  }
  {
    World w(all_threads());
    w.add_plane({.normal = {0.1f, 1.0f, 0.0f}});
    for (int k = 0; k < 3; ++k) {
      // The plane is y = -0.1 x; each centre 1.06 radii from it (|normal| = 1.005 before normalising).
      const float x = 1e5f + 2.5e4f * static_cast<float>(k);
      w.add_sphere({.position = {x, 1.06f * 1.005f * 1e4f - 0.1f * x, 0.0f}, .radius = 1e4f, .mass = 1e9f});
    }
    merge_into(all, watch(w, all.name, all.invariants, 120, 1.0f / 60.0f, {}, 1e12), "radius 1e4: ");
  }
  return all;
}

/// 1,000 spheres with one centre above flat ground: every pair a contact, within the cap.
StressResult many_coincident() {
  World w(all_threads());
  w.set_terrain(flat_terrain(), 0.5f, 0.5f);
  for (int k = 0; k < 1000; ++k) w.add_sphere({.position = {32.0f, 10.0f, 32.0f}, .radius = 0.5f, .mass = 1.0f});
  w.step(1.0f / 60.0f);  // every pair a contact: 499,500 found, 64,000 kept (max_sphere_contacts_per_sphere)
  const bool capped = w.last_step_stats().sphere_contacts_capped;
  StressBounds b;
  b.sphere_penetration = b.ground_penetration = b.energy_growth = -1;  // they start inside each other
  StressResult r =
      watch(w, "coincident-1000", "1,000 spheres at one point above flat ground, 0.5 s: finite, none below the ground",
            29, 1.0f / 60.0f, b, 1e4, 1.0, 10);
  r.note = capped ? "first step's contacts capped" : "first step's contacts not capped";
  if (!capped) r.failures.push_back("the first step's contacts were not capped: " + r.note);
  return r;
}

/// Spheres placed with their centres inside terrain-rain's hills, 0.01 to 10 radii deep.
StressResult inside_terrain() {
  World w(all_threads());
  w.set_terrain(rain_terrain(), 0.5f, 0.5f);
  const Heightmap& h = w.terrain()->heightmap();
  int k = 0;
  for (const float depth : {0.005f, 0.5f, 5.0f})
    for (int j = 0; j < 10; ++j, ++k) {
      const float x = 40.0f + 17.0f * j, z = 60.0f + 40.0f * (k / 10);
      w.add_sphere({.position = {x, h.surface_height(x, z) - depth, z}, .radius = 0.5f, .mass = 1.0f});
    }
  StressBounds b;
  b.energy_growth = -1;  // lifted out: the start energy is below the ground
  return watch(w, "start-inside-terrain", "30 spheres starting 0.01, 1 and 10 radii inside terrain-rain's hills, 2 s",
               120, 1.0f / 60.0f, b, 100.0);
}

/// A box of five planes (one tilted) with 64 spheres dropped in.
StressResult plane_box() {
  World w(all_threads());
  w.add_plane({.normal = {0.2f, 1.0f, 0.0f}});
  w.add_plane({.normal = {1, 0, 0}, .offset = -4});
  w.add_plane({.normal = {-1, 0, 0}, .offset = -4});
  w.add_plane({.normal = {0, 0, 1}, .offset = -4});
  w.add_plane({.normal = {0, 0, -1}, .offset = -4});
  for (int k = 0; k < 64; ++k)
    w.add_sphere({.position = {-3.0f + (k % 4) * 2.0f, 3.0f + (k / 16) * 1.5f, -3.0f + ((k / 4) % 4) * 2.0f},
                  .radius = 0.5f,
                  .mass = 1.0f});
  return watch(w, "plane-box", "64 spheres dropped into a box of four walls and a tilted floor (planes), 3 s", 180,
               1.0f / 60.0f, {}, 100.0);
}

/// Spheres added and removed between steps on terrain-rain's terrain.
StressResult add_and_remove() {
  World w(all_threads());
  w.set_terrain(rain_terrain(), 0.5f, 0.5f);
  std::vector<SphereId> ids;
  StressResult all;
  all.name = "add-and-remove";
  all.invariants = "terrain-rain's terrain, 4 spheres added and 3 removed (oldest, newest, middle) every step, 2 s";
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int step = 0; step < 120; ++step) {
    for (int k = 0; k < 4; ++k)
      ids.push_back(w.add_sphere({.position = {100.0f + 40.0f * u(rng), 15.0f + 5.0f * u(rng), 100.0f + 40.0f * u(rng)},
                                  .radius = 0.3f + 0.3f * u(rng),
                                  .mass = 1.0f}));
    for (int which = 0; which < 3; ++which) {
      const std::size_t at = which == 0 ? 0 : which == 1 ? ids.size() - 1 : ids.size() / 2;
      w.remove_sphere(ids[at]);
      ids.erase(ids.begin() + static_cast<std::ptrdiff_t>(at));
    }
    // One step watched at a time: the energy of a world whose spheres change is not conserved.
    StressBounds b;
    b.energy_growth = -1;
    merge_into(all, watch(w, all.name, all.invariants, 1, 1.0f / 60.0f, b), format("step %.0f: ", step));
  }
  all.note = format("%.0f spheres at the end", double(w.sphere_count()));
  return all;
}

/// bowl-pile with 10,000 spheres for 20 s: it must end at rest.
StressResult dense_pile() {
  SceneParams p;
  p.spheres = 10000;
  p.settings.solver = battery_solver;
  Scene scene = build_bowl_pile(p);
  World& w = *scene.world;
  StressResult r =
      watch(w, "bowl-pile-10k-20s", "bowl-pile, 10,000 spheres, 1,200 steps: settles (KE < 1e-3 J per sphere)", 1200,
            1.0f / 60.0f, {}, 1e4, 1.0, 100);
  const double per_sphere = w.kinetic_energy() / double(w.sphere_count());
  r.note = format("kinetic energy at 20 s: %.3g J per sphere", per_sphere);
  if (!(per_sphere < 1e-3)) r.failures.push_back("not at rest: " + r.note);
  return r;
}

/// bowl-pile with 10,000 spheres and rolling resistance 0.05: asleep within 15 s. Its rolling
/// impulses are warm-started; started from zero every step, the whole pile crept (1-2 mm a
/// second) and the last sphere fell asleep after 28.9 s. The passes solver only (the soft step
/// has no rolling resistance).
StressResult rolling_pile_asleep() {
  const char* name = "bowl-pile-10k-rolling-asleep";
  const char* invariants = "bowl-pile, 10,000 spheres, rolling_resistance 0.05, 900 steps: every sphere asleep by 15 s";
  if (battery_solver == Solver::SoftStep) {
    StressResult r;
    r.name = name, r.invariants = invariants;
    r.note = "skipped: rolling resistance is the passes solver's";
    return r;
  }
  SceneParams p;
  p.spheres = 10000;
  p.settings.rolling_resistance = 0.05f;
  Scene scene = build_bowl_pile(p);
  World& w = *scene.world;
  StressResult r = watch(w, name, invariants, 900, 1.0f / 60.0f, {}, 1e4, 1.0, 100);
  const std::size_t asleep = w.last_step_stats().sleeping;
  r.note = format("%.0f of %.0f spheres asleep at 15 s", double(asleep), double(w.sphere_count()));
  if (asleep != w.sphere_count()) r.failures.push_back("not asleep: " + r.note);
  return r;
}

/// 500 spheres created at one point on flat ground (issue 28, part 4): each coincident pair
/// parts along its own direction (kernel/geometry/coincident_normal.h). Overlapping at the start, so
/// the first second is watched for finite state and the ground only; from then on the usual
/// bounds hold (overlaps within 5% of r, no energy gained), and the heap must end spread out
/// over the ground, not stacked as a column (the fixed +y normal's column of 500 stood 499 m).
StressResult coincident_heap() {
  World w(all_threads());
  w.set_terrain(flat_terrain(), 0.5f, 0.5f);
  for (int k = 0; k < 500; ++k) w.add_sphere({.position = {32.0f, 0.5f, 32.0f}, .radius = 0.5f, .mass = 1.0f});
  StressResult all;
  all.name = "coincident-500-on-ground";
  all.invariants =
      "500 spheres created at one point on flat ground, 4 s: apart within 1 s, then the usual bounds; "
      "spread over the ground, not a column";
  StressBounds parting;
  parting.sphere_penetration = parting.energy_growth = -1;  // they start inside each other
  merge_into(all, watch(w, all.name, all.invariants, 60, 1.0f / 60.0f, parting, 1e4), "parting (0-1 s): ");
  merge_into(all, watch(w, all.name, all.invariants, 180, 1.0f / 60.0f, {}, 1e4), "apart (1-4 s): ");
  const SphereState s = w.spheres();
  float top = 0.0f, reach = 0.0f;
  for (std::size_t i = 0; i < w.sphere_count(); ++i) {
    top = std::max(top, s.py[i]);
    reach = std::max({reach, std::abs(s.px[i] - 32.0f), std::abs(s.pz[i] - 32.0f)});
  }
  all.note = format("highest centre %.3g m, farthest %.3g m from the start on the ground", top, reach);
  if (!(top < 10.0f)) all.failures.push_back("stacked up: " + all.note);
  if (!(reach > 2.0f)) all.failures.push_back("not spread over the ground: " + all.note);
  return all;
}

/// terrain-rain's pile 1e4 m out: 1,024 spheres in one 32 x 32 layer (1.5 m apart) dropped
/// from 13 m, 150 steps there, then World::shift_origin brings everything home for 150 more.
/// Every step checks centres below the surface and overlaps, before and after the shift.
StressResult far_rain_shifted_home() {
  constexpr float kFar = 1e4f;
  World w(all_threads());
  HeightmapParams params;
  params.origin_x = params.origin_z = kFar;
  w.set_terrain(rain_terrain(params), 0.5f, 0.5f);
  for (int k = 0; k < 1024; ++k)
    w.add_sphere({.position = {kFar + 127.5f + (float(k % 32) - 16.0f) * 1.5f, 13.0f,
                               kFar + 127.5f + (float(k / 32) - 16.0f) * 1.5f},
                  .radius = 0.5f,
                  .mass = 1.0f});
  StressResult all;
  all.name = "far-1e4-rain-shifted-home";
  all.invariants = "1,024 spheres raining onto terrain-rain's terrain 1e4 m out, 2.5 s; shift_origin home; 2.5 s more";
  // The sphere overlap bound is the rain's, not 5%: one sphere's deepest overlap while the layer
  // lands and slides into the valleys is chaotic. The same case at the origin, with solver tiles
  // of 128 to 2,048 spheres, gave 3.1% to 8.7% of the radius (far out: 2.3% to 9.9%); what the
  // case guards, precision far out and across the shift, is in the ground bound (5%, 1.0-1.5%
  // measured), the centres-below-the-surface count and the energy.
  all.bounds = StressBounds{.sphere_penetration = 0.15};
  merge_into(all, watch(w, all.name, all.invariants, 150, 1.0f / 60.0f, all.bounds, 1000.0), "1e4 m out: ");
  w.shift_origin({kFar, 0.0f, kFar});
  merge_into(all, watch(w, all.name, all.invariants, 150, 1.0f / 60.0f, all.bounds, 1000.0), "shifted home: ");
  return all;
}

/// The steepest slope between neighbouring vertices along x or z, degrees.
double steepest_slope_deg(const Heightmap& h) {
  double steepest = 0.0;
  for (std::uint32_t j = 0; j + 1 < h.rows(); ++j)
    for (std::uint32_t i = 0; i + 1 < h.cols(); ++i) {
      const double here = h.height(i, j);
      steepest = std::max({steepest, std::fabs(h.height(i + 1, j) - here) / h.params().cell_x,
                           std::fabs(h.height(i, j + 1) - here) / h.params().cell_z});
    }
  return std::atan(steepest) * 180.0 / 3.14159265358979;
}

/// Rain over steep ground (issue 28, part 1): the shipped DEMs (slopes to 84 degrees) and the
/// generated noise, cliff, spike and fold maps (scenes/steep_heightmaps.h), every step checked
/// for centres below the surface and for ground overlap, where a ghost contact from a steep
/// triangle's plane used to throw spheres through ridges.
StressResult steep_rains() {
  StressResult all;
  all.name = "steep-terrain-rain";
  all.invariants = "rain on the two shipped DEMs and four generated steep maps (slopes past 80 degrees), 4 s each";
  std::vector<std::pair<std::string, std::shared_ptr<const Terrain>>> maps;
  // The DEMs at 1 m cells, heights divided by 6 (Jacksboro: 0-140 m) and by 100 (Salish: 36 m
  // of relief): steps of up to 5-10 m between neighbouring samples, slopes to 84 degrees.
  struct Dem {
    const char* label;
    const char* file;
    float scale, offset, divide;
  };
  for (const Dem& d : {Dem{"jacksboro", kJacksboroFile, kJacksboroScaleM, kJacksboroOffsetM, 6.0f},
                       Dem{"salish", "salish_topobathy_120x91.pgm", 0.0555733577478f, -1437.0f, 100.0f}}) {
    HeightmapParams params;
    params.height_scale = d.scale / d.divide;
    params.height_offset = d.offset / d.divide;
    maps.emplace_back(d.label, std::make_shared<const Terrain>(
                                   Heightmap::load_pgm(std::string(HAIL_SOURCE_DIR) + "/data/" + d.file, params)));
  }
  for (const SteepKind kind : kSteepKinds)
    maps.emplace_back(steep_kind_name(kind), std::make_shared<const Terrain>(steep_heightmap(kind, 28, 48, 48)));
  for (const auto& [label, terrain] : maps) {
    World w(all_threads());
    w.set_terrain(terrain, 0.3f, 0.6f);
    const HeightmapExtent e = terrain->heightmap().extent();
    std::mt19937 rng(28);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    // 144 spheres on a 12 x 12 lattice over the middle of the map, dropped from 1-10 m above
    // the surface under them, so that they land at up to 14 m/s among ridges and pits.
    for (int k = 0; k < 144; ++k) {
      const float x = e.min_x + (e.max_x - e.min_x) * (0.1f + 0.8f * ((k % 12) + 0.5f * u(rng)) / 12.0f);
      const float z = e.min_z + (e.max_z - e.min_z) * (0.1f + 0.8f * ((k / 12) + 0.5f * u(rng)) / 12.0f);
      const float r = 0.15f + 0.35f * u(rng);
      float y = terrain->heightmap().surface_height(x, z) + r + 1.0f + 9.0f * u(rng);
      while (terrain->penetration(x, y, z, r + 0.01f) > 0.0f) y += 0.25f * r;  // clear of every steep wall
      w.add_sphere({.position = {x, y, z}, .radius = r, .mass = 1.0f});
    }
    StressBounds b;
    b.energy_growth = 0.01;
    // Spheres bounce off cliffs mid-step (swept): a pair they meet after such a bounce is found
    // only in the next step, from the path predicted at the step's start. On the cliff map one
    // such pair overlapped by 17% of the smaller radius for one step (7.8 m/s after the bounce,
    // 2026-11-27); the ground, below-surface and energy bounds are the ones this case is for.
    b.sphere_penetration = 0.25;
    merge_into(all, watch(w, all.name, all.invariants, 240, 1.0f / 60.0f, b, 1000.0), label + ": ");
    all.note += (all.note.empty() ? "steepest: " : ", ") + label +
                format(" %.0f deg", steepest_slope_deg(terrain->heightmap()));
  }
  all.bounds.energy_growth = 0.01;
  all.bounds.sphere_penetration = 0.25;
  return all;
}

/// The mixed-mass rains: two layers of side x side spheres on a lattice of `spacing` m from
/// (40, 20, 40), the second `rise` m above the first, each jittered by up to 1 m in x and z, radii
/// log-uniform in [min_r, max_r] at 1000 kg/m^3, drawn from `seed`.
void add_log_uniform_rain(World& w, unsigned seed, int side, float spacing, float rise, float min_r, float max_r) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  constexpr float density = 1000.0f;
  for (int layer = 0; layer < 2; ++layer)
    for (int i = 0; i < side; ++i)
      for (int j = 0; j < side; ++j) {
        const float r = min_r * std::pow(max_r / min_r, u(rng));
        const float mass = density * 4.18879f * r * r * r;
        w.add_sphere({.position = {40.0f + spacing * i + u(rng), 20.0f + rise * layer, 40.0f + spacing * j + u(rng)},
                      .radius = r,
                      .mass = mass});
      }
}

/// A rain whose radii span two orders of magnitude at equal density (issue 28, part 2): masses
/// from 0.5 kg to 5e5 kg, so light spheres are struck by ones 1e6 times heavier while they
/// lie on the ground. Every step checks that no centre is below the surface.
StressResult wide_mix_rain() {
  World w(all_threads());
  w.set_terrain(rain_terrain(), 0.5f, 0.5f);
  add_log_uniform_rain(w, 28, 17, 10.5f, 15.0f, 0.05f, 5.0f);  // no sphere touches another at the start
  StressBounds b;
  b.energy_growth = 0.01;
  b.sphere_penetration = -1.0;  // reported: a 5 cm sphere under a 5 m one is judged by the ground
  // 6% of the radius, not 5%: the uniform-acceleration integrator may move a sphere pushed
  // sideways up to |g| dt^2 / 2 (1.4 mm at 60 Hz, 2.7% of the smallest radius here) short of its
  // solved velocity, which the contacts' gap limits do not see; its acceleration is kept within
  // what gravity gives on a frictionless support (uniform_step_acceleration), and the passes'
  // worst is 4.62% (4.02% under semi-implicit Euler). The soft step's worst is one sphere in one
  // step and moves with any change of rounding (its spheres in contact end where its substeps
  // put them, whatever that acceleration): 4.02-6.44% in six runs with the acceleration
  // perturbed in its last bits or computed in another order.
  b.ground_penetration = 0.06;
  return watch(w, "wide-mix-rain", "578 spheres, radii 0.05-5 m log-uniform at 1000 kg/m^3 (mass ratio 1e6), 10 s", 600,
               1.0f / 60.0f, b, 1e6);
}

/// Small spheres under big ones (issue 49, part 1): 2,048 spheres with radii log-uniform in a
/// range spanning two orders of magnitude at 1000 kg/m^3 (masses 1:1e6 to 1:8e6) rained on
/// terrain-rain's terrain, for several seeds and ranges. A light sphere lying on the ground
/// under a heavy one takes nearly all of their pair's correction: it was driven through the
/// ground (a sphere of r 0.039 m struck at 5 m/s fell through it after its sweep) or deep into
/// the heavy sphere. Every step: no centre below the surface, the ground overlap and (passes
/// solver) the sphere overlap bounded.
StressResult small_under_big() {
  StressResult all;
  all.name = "small-under-big-rain";
  all.invariants = "2,048 spheres, radii log-uniform 0.01-2 m (three seeds) and 0.02-1 m at 1000 kg/m^3, 10 s each";
  struct Variant {
    unsigned seed;
    float min_r, max_r;
  };
  for (const Variant v : {Variant{2028, 0.01f, 2.0f}, Variant{7, 0.01f, 2.0f}, Variant{99, 0.01f, 2.0f},
                          Variant{2028, 0.02f, 1.0f}}) {
    World w(all_threads());
    w.set_terrain(rain_terrain(), 0.5f, 0.5f);
    add_log_uniform_rain(w, v.seed, 32, 5.0f, 10.0f, v.min_r, v.max_r);  // no sphere touches another at the start
    StressBounds b;
    b.energy_growth = 0.01;
    // 0.22 of the smaller radius at worst; 1.7 before the ground or a heavier sphere held a
    // pebble struck into it in the sweep, the spheres the solve made fast were swept, and the
    // pairs that met in the sweep were parted last (ContinuousCollision::strike_held,
    // add_struck_fast, part_swept_pairs), when the pebble was thrown between the two impact
    // by impact until the event cap. Left: spheres the solve sped past their contacts but not
    // to fast (0.22, 0.20), and pebbles wedged in the crevice between two boulders (0.18).
    // The soft step: 2.6 radii (16 before the changes above), its soft contacts giving way
    // under the heavy sphere within the step: reported only.
    b.sphere_penetration = battery_solver == Solver::SoftStep ? -1.0 : 0.3;
    // 6.8% of the radius at worst (seed 7), in the step such a sphere is thrown down; 21% before
    // a swept sphere kept its touching ground contacts (kSweptTouchFraction). The soft step:
    // 15.6%, as its soft ground contacts give way under the heavy sphere within the step.
    b.ground_penetration = battery_solver == Solver::SoftStep ? 0.16 : 0.08;
    merge_into(all, watch(w, all.name, all.invariants, 600, 1.0f / 60.0f, b, 1e5),
               format("seed %.0f, r %.2g", double(v.seed), double(v.min_r)) + format("-%.2g: ", double(v.max_r)));
  }
  all.bounds.energy_growth = 0.01;
  all.bounds.sphere_penetration = battery_solver == Solver::SoftStep ? -1.0 : 0.3;
  all.bounds.ground_penetration = battery_solver == Solver::SoftStep ? 0.16 : 0.08;
  return all;
}

/// The meshes' stress scene (docs/meshes.md): a closed floor 60 m square, an open funnel (a
/// shell) over it and two walls 1 mm thick at x = 12, one closed (a box) and one a shell (a
/// single quad), reaching 20 m to each side and 60 m up.
void add_stress_meshes(World& w) {
  w.add_mesh(box_mesh({-30, -1, -30}, {30, 0, 30}), {}, 0.3f, 0.5f);
  std::vector<Vec3> cone;
  std::vector<std::uint32_t> cone_idx;
  constexpr std::uint32_t kSides = 24;
  for (std::uint32_t k = 0; k < kSides; ++k) {
    const float a = 6.2831853f * float(k) / float(kSides);
    cone.emplace_back(1.2f * std::cos(a), 1.5f, 1.2f * std::sin(a));
    cone.emplace_back(5.0f * std::cos(a), 6.0f, 5.0f * std::sin(a));
  }
  for (std::uint32_t k = 0; k < kSides; ++k) {
    const std::uint32_t n = (k + 1) % kSides;
    cone_idx.insert(cone_idx.end(), {2 * k, 2 * k + 1, 2 * n + 1, 2 * k, 2 * n + 1, 2 * n});
  }
  w.add_mesh(TriangleMesh(cone, cone_idx), {}, 0.3f, 0.5f);
  w.add_mesh(box_mesh({12.0f, 0.0f, -20.0f}, {12.001f, 60.0f, 0.0f}), {}, 0.5f, 0.2f);
  w.add_mesh(TriangleMesh({{12.0f, 0.0f, 0.0f}, {12.0f, 0.0f, 20.0f}, {12.0f, 60.0f, 20.0f}, {12.0f, 60.0f, 0.0f}},
                          {0, 1, 2, 0, 2, 3}),
             {}, 0.5f, 0.2f);
}

/// Steps a world of add_stress_meshes 360 times, watching every step; also counts as below the
/// surface each centre under the floor's top (within the floor) and each sphere of `fired` that
/// crossed x = 12 within the walls' span in a step.
StressResult watch_meshes(World& w, StressResult r, const std::vector<SphereId>& fired) {
  StressWatch watch_each(w, 1e5);
  std::vector<float> x_before(fired.size());
  const auto t0 = clock_type::now();
  for (int k = 0; k < 360; ++k) {
    for (std::size_t f = 0; f < fired.size(); ++f) x_before[f] = w.position(fired[f]).x();
    w.step(1.0f / 60.0f);
    watch_each.after_step(w);
    std::size_t out = 0;
    const SphereSoA& s = w.soa();
    for (std::size_t i = 0; i < s.size(); ++i)
      out += s.py[i] < 0.0f && std::fabs(s.px[i]) < 30.0f && std::fabs(s.pz[i]) < 30.0f;
    for (std::size_t f = 0; f < fired.size(); ++f) {
      const Vec3 p = w.position(fired[f]);
      out += x_before[f] <= 12.0f && p.x() > 12.0f && std::fabs(p.z()) < 19.5f && p.y() < 59.5f;
    }
    r.worst.below_surface = std::max(r.worst.below_surface, out);
  }
  r.wall_s = std::chrono::duration<double>(clock_type::now() - t0).count();
  const std::size_t below = r.worst.below_surface;
  r.worst = watch_each.worst();
  r.worst.below_surface = below;
  judge(r);
  return r;
}

/// 60 spheres (radii 0.05-0.25 m, 1000 kg/m^3) fired at 20-60 m/s at the two 1 mm walls of
/// add_stress_meshes, half at each: none crosses a wall, nothing sinks into a mesh or another sphere.
StressResult mesh_thin_walls() {
  StressResult r;
  r.name = "meshes-thin-walls-60-m-s";
  r.invariants = "60 spheres fired at 20-60 m/s at 1 mm walls (a closed box, a shell) over a mesh floor, 6 s";
  r.bounds.energy_growth = 0.01;
  World w(all_threads());
  add_stress_meshes(w);
  std::mt19937 rng(51);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<SphereId> fired;
  for (int k = 0; k < 60; ++k) {
    const float radius = 0.05f + 0.2f * u(rng);
    const float z = k % 2 == 0 ? -5.5f + 5.0f * u(rng) : 1.0f + 4.5f * u(rng);  // the closed wall, then the shell
    fired.push_back(w.add_sphere({.position = {-6.0f - 0.6f * float(k / 2), 0.5f + 5.0f * u(rng), z},
                                  .velocity = {20.0f + 40.0f * u(rng), 0.0f, 0.0f},
                                  .radius = radius,
                                  .mass = 1000.0f * 4.18879f * radius * radius * radius}));
  }
  return watch_meshes(w, r, fired);
}

/// 600 spheres, radii 0.1-0.5 m at 1000 kg/m^3 (masses 1:125), rain into the open funnel of
/// add_stress_meshes and pile on its floor. The ground bound is small-under-big-rain's on terrain
/// (0.019 r measured; 0.36 before meshes had the guard). The sphere bound is 0.4 of the smaller
/// radius, not terrain's 0.3: 0.35 measured, where the guard moves a light sphere out of the mesh
/// and into the heavy one pressing it (depenetration parts them in the next steps; 0.28 without
/// the guard, with the light sphere 0.36 r inside the mesh instead).
StressResult mesh_funnel_rain() {
  StressResult r;
  r.name = "meshes-funnel-rain";
  r.invariants = "600 spheres, radii 0.1-0.5 m at 1000 kg/m^3, rain through an open mesh funnel onto a mesh floor, 6 s";
  r.bounds.energy_growth = 0.01;
  r.bounds.sphere_penetration = battery_solver == Solver::SoftStep ? -1.0 : 0.4;
  r.bounds.ground_penetration = battery_solver == Solver::SoftStep ? 0.16 : 0.08;
  World w(all_threads());
  add_stress_meshes(w);
  std::mt19937 rng(51);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int k = 0; k < 600; ++k) {
    const float radius = 0.1f + 0.4f * u(rng);
    // A 5 x 5 lattice a layer, 1.2 m apart and layers 1.1 m apart: no two touch at the start.
    const float x = -2.4f + 1.2f * float(k % 5) + 0.1f * u(rng), z = -2.4f + 1.2f * float((k / 5) % 5) + 0.1f * u(rng);
    w.add_sphere({.position = {x, 7.0f + 1.1f * float(k / 25), z},
                  .radius = radius,
                  .mass = 1000.0f * 4.18879f * radius * radius * radius});
  }
  return watch_meshes(w, r, {});
}

}  // namespace

void judge(StressResult& r) {
  const StressWorst& w = r.worst;
  const StressBounds& b = r.bounds;
  if (w.non_finite > 0) r.failures.push_back(format("%.0f non-finite state components", double(w.non_finite)));
  if (w.below_surface > 0)
    r.failures.push_back(format("%.0f centres below the terrain surface", double(w.below_surface)));
  if (b.sphere_penetration >= 0 && w.sphere_penetration > b.sphere_penetration)
    r.failures.push_back(format("sphere penetration %.3g of the smaller radius (bound %.3g)", w.sphere_penetration,
                                b.sphere_penetration));
  if (b.ground_penetration >= 0 && w.ground_penetration > b.ground_penetration)
    r.failures.push_back(
        format("ground penetration %.3g of the radius (bound %.3g)", w.ground_penetration, b.ground_penetration));
  if (b.energy_growth >= 0 && w.energy_growth > b.energy_growth)
    r.failures.push_back(format("mechanical energy grew by %.3g (bound %.3g)", w.energy_growth, b.energy_growth));
  if (b.momentum_drift >= 0 && w.momentum_drift > b.momentum_drift)
    r.failures.push_back(format("momentum drifted by %.3g (bound %.3g)", w.momentum_drift, b.momentum_drift));
}

std::vector<StressCase> stress_cases(Solver solver) {
  std::vector<StressCase> cases{
      {"mass-ratio-1e4-on-1", false, heavy_on_light},
      {"stack-1-100-1e4", false, stack_ratios},
      {"light-hit-by-heavy", false, light_hit_by_heavy},
      {"radius-0.01-among-10", false, small_among_large},
      {"speed-1e4-into-terrain", false, bullets_1e4},
      {"speed-1e4-into-pile", false, bullet_into_pile},
      {"dt-1e-5-to-1/20", false, time_steps},
      {"coincident-and-on-edges", false, coincident_and_edges},
      {"cliff-and-spikes", false, cliffs_and_spikes},
      {"rain-at-origin", false, [] { return far_away(0.0f, 0.0f, "rain-at-origin"); }},
      {"heights-1e4", false, [] { return far_away(0.0f, 1e4f, "heights-1e4"); }},
      {"far-1e4", false, [] { return far_away(1e4f, 0.0f, "far-1e4"); }},
      {"far-1e5", false, [] { return far_away(1e5f, 0.0f, "far-1e5"); }},
      {"far-1.25e5", false, [] { return far_away(1.25e5f, 0.0f, "far-1.25e5"); }},
      {"materials-and-time-scale", false, materials_and_time_scale},
      {"time-scale-300-and-750", false, long_time_steps},
      {"radius-1e-4-and-1e4", false, radius_extremes},
      {"coincident-1000", false, many_coincident},
      {"start-inside-terrain", false, inside_terrain},
      {"plane-box", false, plane_box},
      {"add-and-remove", false, add_and_remove},
      {"coincident-500-on-ground", false, coincident_heap},
      {"far-1e4-rain-shifted-home", false, far_rain_shifted_home},
      {"steep-terrain-rain", false, steep_rains},
      {"wide-mix-rain", false, wide_mix_rain},
      {"small-under-big-rain", false, small_under_big},
      {"meshes-thin-walls-60-m-s", false, mesh_thin_walls},
      {"meshes-funnel-rain", false, mesh_funnel_rain},
      {"bowl-pile-10k-20s", true, dense_pile},
      {"bowl-pile-10k-rolling-asleep", true, rolling_pile_asleep},
  };
  for (StressCase& c : cases)
    c.run = [run = std::move(c.run), solver] {
      battery_solver = solver;
      StressResult r = run();
      battery_solver = Solver::Passes;
      return r;
    };
  return cases;
}

}  // namespace hail::bench
