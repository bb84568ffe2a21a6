// hail-example: what embedding hail looks like, in one file.
//
//  1. A terrain from a heightmap: a function h(x, z) (default) or a PGM file (argv[1]).
//  2. A World that steps inside the program's own tbb::task_arena (the host owns the threads).
//  3. 256 spheres dropped onto it, 4 s at 60 Hz; after every step the contacts and impacts of the
//     step are scanned once for touch-downs, clacks and their bounce impulses, what a game would
//     turn into sounds.
//  4. Where they landed, read through the zero-copy spans, the ground under each found by a
//     raycast, and the error figures. Exit status 1 if a figure is off, 2 on bad arguments.
//
//   hail-example                                      rolling hills in a bowl, from a function
//   hail-example data/jacksboro_srtm3_403x344.pgm     the SRTM DEM, 1 m cells, heights / 80
//                                                     (as data/scenes/terrain-rain-dem.json)

#include <hail/hail.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <optional>
#include <vector>

#include <oneapi/tbb/task_arena.h>

namespace {

constexpr int kSide = 16;                 // spheres per row of the drop grid
constexpr float kSpacing = 1.2f;          // m between neighbours in the grid
constexpr float kRadius = 0.4f;           // m
constexpr float kDt = 1.0f / 60.0f;       // s
constexpr int kSteps = 240;               // 4 s
constexpr float kMaxPenetration = 0.05f;  // m: fail above this (hail's own figure is ~0.005)

hail::Heightmap make_heightmap(int argc, char** argv) {
  if (argc > 1) {
    // 16-bit PGM samples to metres: terrain-rain-dem's scale (the DEM's metres divided by 80).
    const hail::HeightmapParams params{
        .cell_x = 1.0f, .cell_z = 1.0f, .height_scale = 0.00016021973f, .height_offset = 2.95f};
    return hail::Heightmap::load_pgm(argv[1], params);
  }
  // 129 x 129 vertices, 0.5 m apart, centred on the origin: a bowl with bumps, so nothing rolls off.
  const hail::HeightmapParams params{.cell_x = 0.5f, .cell_z = 0.5f, .origin_x = -32.0f, .origin_z = -32.0f};
  return hail::Heightmap::from_function(129, 129, params, [](float x, float z) {
    return 0.004f * (x * x + z * z) + 0.6f * std::sin(0.5f * x) * std::cos(0.4f * z);
  });
}

int run(int argc, char** argv) {
  std::printf("hail %s example\n", HAIL_VERSION_STRING);

  // 1. Terrain: immutable once built, shared with the World (and any other World).
  auto terrain = std::make_shared<const hail::Terrain>(make_heightmap(argc, argv));
  const hail::Heightmap& map = terrain->heightmap();
  std::printf("terrain: %u x %u vertices, %zu triangles, heights %.2f..%.2f m\n", map.cols(), map.rows(),
              terrain->triangle_count(), map.min_height(), map.max_height());

  // 2. The host's arena: hail's step() runs its parallel phases here and nowhere else.
  tbb::task_arena arena(2);
  hail::World world({.gravity = {0.0f, -9.81f, 0.0f}}, arena);
  world.set_terrain(terrain, /*restitution=*/0.3f, /*friction=*/0.6f);

  // 3. A grid of spheres over the middle of the map, 2 m above its highest point.
  const hail::HeightmapExtent extent = map.extent();
  const float cx = 0.5f * (extent.min_x + extent.max_x), cz = 0.5f * (extent.min_z + extent.max_z);
  std::vector<hail::SphereId> ids;
  world.reserve(kSide * kSide);  // adding them allocates nothing more
  for (int i = 0; i < kSide; ++i)
    for (int k = 0; k < kSide; ++k) {
      const float x = cx + (static_cast<float>(i) - 0.5f * (kSide - 1)) * kSpacing;
      const float z = cz + (static_cast<float>(k) - 0.5f * (kSide - 1)) * kSpacing;
      ids.push_back(world.add_sphere({.position = {x, map.max_height() + 2.0f + 0.05f * static_cast<float>(i), z},
                                      .radius = kRadius,
                                      .mass = 1.0f,
                                      .restitution = 0.3f,
                                      .friction = 0.6f}));
    }

  // Step, and read each step's contacts in one pass: no callback inside the solver's loops.
  // First touches are the events a game would play a sound for: a sphere's first touch of the
  // ground (touch-down) and its first touch of another sphere (clack).
  std::vector<float> touched_down_at(ids.size(), -1.0f), clacked_at(ids.size(), -1.0f);  // by SphereId::index
  std::size_t touchdowns = 0, clacks = 0, bounces = 0;  // bounces: contacts and impacts with a bounce impulse
  float loudest = 0.0f;                                 // the largest bounce impulse, N s
  double step_ms = 0.0;
  // Views of the World's own arrays: taken once, valid for as long as no sphere is added or
  // removed, and they see every step (indexed by dense slot, as the contacts are).
  const hail::SphereState state = world.spheres();
  for (int step = 1; step <= kSteps; ++step) {
    world.step(kDt);
    step_ms += world.last_phase_times().total();
    const float t = static_cast<float>(step) * kDt;
    auto first_touch = [&](std::vector<float>& at, std::uint32_t slot, std::size_t& count) {
      const hail::SphereId who = world.id_at(slot);  // slot -> handle, valid until the next step
      if (at[who.index] < 0.0f) {
        at[who.index] = t;
        ++count;
      }
    };
    // A contact is listed when its sphere could reach the surface within the step
    // (speculative); it touched when an impulse acted on it: bounce_impulse (the collision
    // passes: what a sound's loudness follows) or normal_impulse (resting on it). Impacts taken
    // at their exact time (planes reached within the step, fast spheres) come separately.
    auto touched = [&](std::uint32_t a, std::uint32_t b, std::uint32_t feature) {
      if (b == hail::kStaticBody) {
        if (!(feature & hail::kPlaneFeature)) first_touch(touched_down_at, a, touchdowns);  // terrain
      } else {
        first_touch(clacked_at, a, clacks);
        first_touch(clacked_at, b, clacks);
      }
    };
    for (const hail::Contact& c : world.last_contacts()) {
      if (c.bounce_impulse > 0.0f) loudest = std::max(loudest, c.bounce_impulse), ++bounces;
      if (c.bounce_impulse > 0.0f || c.normal_impulse > 0.0f) touched(c.a, c.b, c.feature);
    }
    for (const hail::Impact& i : world.last_impacts()) {
      loudest = std::max(loudest, i.impulse), ++bounces;
      touched(i.a, i.b, i.feature);
    }
    if (step % 60 == 0)
      std::printf("t = %.1f s: %zu/%zu spheres have touched down, %zu contacts this step, KE %.1f J\n", t, touchdowns,
                  ids.size(), world.last_contacts().size(), world.kinetic_energy());
  }

  // 4. Where they landed, through the same spans (slots may have moved: look them up again).
  float max_penetration = 0.0f, max_raycast_error = 0.0f, lowest = 1e30f, highest = -1e30f;
  double clearance_sum = 0.0;
  std::size_t on_terrain = 0;
  for (std::size_t n = 0; n < ids.size(); ++n) {
    const auto slot = static_cast<std::size_t>(world.slot_of(ids[n]));
    const hail::Vec3 p(state.px[slot], state.py[slot], state.pz[slot]);
    const float r = state.radius[slot];
    lowest = std::min(lowest, p.y());
    highest = std::max(highest, p.y());
    max_penetration = std::max(max_penetration, terrain->penetration(p.x(), p.y(), p.z(), r));
    // The ground straight below the centre: a raycast, checked against the heightmap's surface.
    const std::optional<hail::TerrainRayHit> ground = terrain->raycast(p, hail::Vec3(0.0f, -1.0f, 0.0f));
    if (!ground) continue;  // off the map's edge
    ++on_terrain;
    clearance_sum += ground->t - r;
    max_raycast_error = std::max(max_raycast_error, std::abs(ground->point.y() - map.surface_height(p.x(), p.z())));
    if (n < 4)
      std::printf(
          "sphere %zu landed at (%.2f, %.2f, %.2f) m, %.3f m above the ground (slope normal y %.2f), "
          "touched down at %.2f s\n",
          n, p.x(), p.y(), p.z(), ground->t - r, ground->normal.y(), touched_down_at[ids[n].index]);
  }
  const double mean_clearance = on_terrain ? clearance_sum / static_cast<double>(on_terrain) : 0.0;
  std::printf("landed: %zu spheres, %zu over the terrain, centres at y %.2f..%.2f m\n", ids.size(), on_terrain, lowest,
              highest);
  std::printf(
      "errors: max penetration %.4f m, mean clearance under centre %.4f m, raycast vs heightmap %.2e m, "
      "NaN %zu\n",
      max_penetration, mean_clearance, max_raycast_error, world.nan_count());
  std::printf(
      "sounds: %zu touch-downs, %zu first clacks, %zu bounces (loudest %.2f N s); %.3f ms/step on %d threads; "
      "state hash %016llx\n",
      touchdowns, clacks, bounces, loudest, step_ms / kSteps, world.thread_count(),
      static_cast<unsigned long long>(world.state_hash()));

  bool ok = true;
  auto require = [&](bool condition, const char* what) {
    if (!condition) std::printf("FAILED: %s\n", what);
    ok = ok && condition;
  };
  require(world.nan_count() == 0, "no NaN in the state");
  require(max_penetration <= kMaxPenetration, "no sphere deeper than 5 cm in the terrain");
  require(max_raycast_error <= 1e-3f, "raycast lands on the heightmap's surface within 1 mm");
  std::size_t touched_something = 0;
  for (std::size_t n = 0; n < ids.size(); ++n)
    touched_something += touched_down_at[ids[n].index] >= 0.0f || clacked_at[ids[n].index] >= 0.0f;
  require(touched_something == ids.size(), "every sphere touched the ground or another sphere");
  require(touchdowns >= ids.size() / 2, "at least half of the spheres touched the ground");
  // Dropped 2 m and more (over 6 m/s at impact): the first bounces carry about (1 + e) m v.
  require(bounces > 0 && loudest > 1.3f * 1.0f * 6.0f, "the landings bounced with (1 + e) m v");
  require(on_terrain >= ids.size() * 9 / 10, "at least 90% of the spheres are still over the terrain");
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2) {
    std::fprintf(stderr, "usage: %s [heightmap.pgm]\n", argv[0]);
    return 2;
  }
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {  // hail::InvalidArgument, hail::FileError: the message names the value
    std::fprintf(stderr, "hail-example: %s\n", e.what());
    return 1;
  }
}
