#include "compare_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "cli.h"
#include "kernel/terrain/terrain_parts.h"
#include "peer_engine.h"
#include "peer_engine_bullet.h"
#include "scenes/machine_info.h"
#include "scenes/metrics.h"
#include "scenes/output_file.h"
#include "scenes/scene_run.h"

namespace hail::bench {
namespace {}  // namespace

namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The figures of one engine's final state, measured the same way for every engine from its
/// read_state(), independently of the engines' own contact lists.
struct PeerErrors {
  std::size_t tunnelled = 0;      ///< centres below the terrain surface at their (x, z), inside its extent
  std::size_t fell_off = 0;       ///< centres outside the terrain's x/z extent
  std::size_t nan_spheres = 0;    ///< spheres with any non-finite position, velocity or spin
  double ground_penetration = 0;  ///< m, deepest sphere into the terrain or a plane
  double sphere_penetration = 0;  ///< m, deepest overlap of two spheres
  double kinetic_energy = 0;      ///< J, translational + rotational (I = 2/5 m r^2)
  double momentum = 0;            ///< kg m/s, |sum m v|
};

PeerErrors measure(const PeerScene& scene, const Terrain* terrain, const std::vector<PeerState>& state) {
  PeerErrors e;
  const std::size_t n = state.size();
  std::vector<float> px(n), py(n), pz(n), radius(n);
  double p[3] = {0, 0, 0};
  for (std::size_t k = 0; k < n; ++k) {
    const PeerSphere& s = scene.spheres[k];
    const PeerState& x = state[k];
    px[k] = x.position.x(), py[k] = x.position.y(), pz[k] = x.position.z(), radius[k] = s.radius;
    if (!x.position.allFinite() || !x.velocity.allFinite() || !x.angular_velocity.allFinite()) {
      ++e.nan_spheres;
      continue;
    }
    if (s.mass > 0.0f) {
      const double v2 = x.velocity.cast<double>().squaredNorm(), w2 = x.angular_velocity.cast<double>().squaredNorm();
      const double inertia = 0.4 * double(s.mass) * double(s.radius) * double(s.radius);
      e.kinetic_energy += 0.5 * double(s.mass) * v2 + 0.5 * inertia * w2;
      for (int a = 0; a < 3; ++a) p[a] += double(s.mass) * double(x.velocity[a]);
    }
    for (const PeerPlane& plane : scene.planes)
      e.ground_penetration = std::max(e.ground_penetration,
                                      double(s.radius) - (double(plane.normal.dot(x.position)) - double(plane.offset)));
    if (!scene.heightmap) continue;
    const HeightmapExtent ext = scene.heightmap->extent();
    const float xx = x.position.x(), y = x.position.y(), z = x.position.z();
    if (!(xx >= ext.min_x && xx <= ext.max_x && z >= ext.min_z && z <= ext.max_z)) {
      ++e.fell_off;
      continue;
    }
    if (y < scene.heightmap->surface_height(xx, z)) ++e.tunnelled;
    e.ground_penetration = std::max<double>(e.ground_penetration, terrain->penetration(xx, y, z, s.radius));
  }
  e.sphere_penetration = max_pair_overlap(px, py, pz, radius);
  e.momentum = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  return e;
}

/// One engine configuration and everything measured of it.
struct Contender {
  std::string label;
  std::function<std::unique_ptr<PeerEngine>()> make;
  std::vector<double> run_medians, run_means, setup_s;
  PeerErrors errors;  // of the last run
  int asleep = -1;    // Bullet: bodies deactivated (ISLAND_SLEEPING) at the end of the last run
};

/// Bodies a Bullet engine has put to sleep, or -1 for any other engine.
int sleeping_bodies(PeerEngine& engine) {
  btDiscreteDynamicsWorld* world = bullet_world(engine);
  return world ? bullet_sleeping_bodies(*world) : -1;
}

void run_once(Contender& c, const PeerScene& scene, const Terrain* terrain, float dt, int steps, int warmup,
              const std::string& progress_label, bool quiet) {
  using clock = std::chrono::steady_clock;
  const auto setup_start = clock::now();
  std::unique_ptr<PeerEngine> engine = c.make();
  c.setup_s.push_back(std::chrono::duration<double>(clock::now() - setup_start).count());
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<std::size_t>(steps));
  auto last_progress = clock::now();
  for (int k = 0; k < steps; ++k) {
    const auto t0 = clock::now();
    engine->step(dt);
    step_ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    if (!quiet && clock::now() - last_progress > std::chrono::seconds(3)) {
      std::fprintf(stderr, "  %s step %d/%d, %.2f ms/step so far\n", progress_label.c_str(), k + 1, steps,
                   std::accumulate(step_ms.begin(), step_ms.end(), 0.0) / double(step_ms.size()));
      last_progress = clock::now();
    }
  }
  const std::vector<double> timed(step_ms.begin() + warmup, step_ms.end());
  c.run_medians.push_back(median_of(timed));
  c.run_means.push_back(std::accumulate(timed.begin(), timed.end(), 0.0) / double(timed.size()));
  std::vector<PeerState> state;
  engine->read_state(state);
  c.errors = measure(scene, terrain, state);
  c.asleep = sleeping_bodies(*engine);
}

std::string format_runs(const std::vector<double>& v) {
  std::string s;
  char buffer[32];
  for (double x : v) {
    std::snprintf(buffer, sizeof buffer, "%s%.2f", s.empty() ? "" : " ", x);
    s += buffer;
  }
  return s;
}

}  // namespace

int compare_command(const CompareOptions& o) {
  check_output_paths({o.json_path});
  const SceneEntry& entry = find_scene(o.scene);
  const Scene scene = entry.build(o.params);
  const PeerScene peer = peer_scene_from(scene, o.scene);
  WorldSettings hail_settings = scene.world->settings();
  hail_settings.threads = o.params.threads;
  const int hail_threads = scene.world->thread_count();
  const int steps = o.steps > 0 ? o.steps : scene.default_steps;
  const int warmup = steps > 120 ? 60 : 0;  // the scenes' definition: report steps 60..
  const float dt = scene.dt;
  std::unique_ptr<const Terrain> terrain;
  if (peer.heightmap) terrain = std::make_unique<const Terrain>(*peer.heightmap);

  std::vector<Contender> contenders;
  contenders.push_back({"hail", [&] { return make_hail_engine(peer, hail_settings); }, {}, {}, {}, {}});
  const bool with_bullet = bullet_available();
  double ray_error = 0.0;
  constexpr int kRaySamples = 64;
  if (with_bullet) {
    contenders.push_back({"Bullet", [&] { return make_bullet_engine(peer, {.sleeping = true}); }, {}, {}, {}, {}});
    contenders.push_back(
        {"Bullet no sleep", [&] { return make_bullet_engine(peer, {.sleeping = false}); }, {}, {}, {}, {}});
    if (peer.heightmap) {
      const std::unique_ptr<PeerEngine> probe = make_bullet_engine(peer, {});
      ray_error = bullet_terrain_ray_error(*probe, *peer.heightmap, kRaySamples);
    }
  } else {
    std::fprintf(stderr,
                 "hail-bench compare: built without Bullet, so hail runs alone. To compare, install Debian's Bullet\n"
                 "    sudo apt-get install libbullet-dev\n"
                 "and configure and build again (cmake finds it through pkg-config).\n");
  }

  // ABBA order over the contenders (hail, Bullet, Bullet no sleep, then the reverse, ...), so a
  // drift in machine speed during the run falls on each alike.
  const int total = o.repeat * static_cast<int>(contenders.size());
  int done = 0;
  for (int r = 0; r < o.repeat; ++r)
    for (std::size_t q = 0; q < contenders.size(); ++q) {
      Contender& c = contenders[r % 2 == 0 ? q : contenders.size() - 1 - q];
      const std::string label = "[" + c.label + " " + std::to_string(r + 1) + "/" + std::to_string(o.repeat) + "]";
      if (!o.quiet) std::fprintf(stderr, "  run %d/%d %s\n", ++done, total, label.c_str());
      run_once(c, peer, terrain.get(), dt, steps, warmup, label, o.quiet);
    }

  const double hail_ms = median_of(contenders[0].run_medians);
  std::vector<PeerState> start_state;
  for (const PeerSphere& s : peer.spheres) start_state.push_back({s.position, s.velocity, s.angular_velocity});
  const PeerErrors start = measure(peer, terrain.get(), start_state);
  const double start_energy = start.kinetic_energy;

  std::printf("hail-bench compare %s  (%s)\n", o.scene.c_str(), scene.description.c_str());
  std::printf("  machine   %s, SIMD %s\n", cpu_model().c_str(), simd_path().c_str());
  std::printf(
      "  scene     %zu spheres, %d steps of dt = %.6g s, timed steps %d..%d; runs each: %d, alternating ABBA\n"
      "  at start  kinetic energy %.6g J, |momentum| %.3g kg m/s\n",
      peer.spheres.size(), steps, dt, warmup, steps - 1, o.repeat, start_energy, start.momentum);
  std::printf("  hail      threads: %d; continuous collision %s, %d collision + %d resting passes, warm start %g\n",
              hail_threads, hail_settings.continuous_collision ? "on" : "off", hail_settings.collision_iterations,
              hail_settings.resting_iterations, double(hail_settings.warm_start_factor));
  if (with_bullet) {
    std::printf(
        "  Bullet    %s, single-threaded (btDiscreteDynamicsWorld): btDbvtBroadphase, "
        "btSequentialImpulseConstraintSolver\n"
        "            with %d iterations (default), one internal step per frame (stepSimulation(dt, 0)), one "
        "btSphereShape\n"
        "            per radius, CCD off (its default); restitution min and friction geometric mean, as hail;\n"
        "            sleeping as Bullet defaults (\"Bullet\") and off (\"Bullet no sleep\")\n",
        bullet_version().c_str(), BulletOptions{}.solver_iterations);
    if (peer.heightmap)
      std::printf(
          "            heightfield placed as hail's terrain: %d vertical ray casts, max |hit - hail surface| = %.3g "
          "m\n",
          kRaySamples * kRaySamples, ray_error);
  } else {
    std::printf("  Bullet    not built in (sudo apt-get install libbullet-dev, then configure again): hail alone\n");
  }

  const int w = 20;
  auto row = [&](const char* name, const std::function<std::string(const Contender&)>& cell) {
    std::printf("  %-24s", name);
    for (const Contender& c : contenders) std::printf(" %*s", w, cell(c).c_str());
    std::printf("\n");
  };
  auto num = [](const char* format, double v) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, format, v);
    return std::string(buffer);
  };
  row("", [](const Contender& c) { return c.label; });
  row("ms/step median", [&](const Contender& c) { return num("%.3f", median_of(c.run_medians)); });
  row("ms/step mean", [&](const Contender& c) { return num("%.3f", median_of(c.run_means)); });
  row("  runs' medians", [&](const Contender& c) { return format_runs(c.run_medians); });
  row("ratio to hail (median)", [&](const Contender& c) { return num("%.2f", median_of(c.run_medians) / hail_ms); });
  row("set-up s", [&](const Contender& c) { return num("%.3f", median_of(c.setup_s)); });
  row("tunnelled", [&](const Contender& c) { return std::to_string(c.errors.tunnelled); });
  row("fell off", [&](const Contender& c) { return std::to_string(c.errors.fell_off); });
  row("max penetration ground m", [&](const Contender& c) { return num("%.4g", c.errors.ground_penetration); });
  row("max penetration pair m", [&](const Contender& c) { return num("%.4g", c.errors.sphere_penetration); });
  row("kinetic energy J", [&](const Contender& c) { return num("%.6g", c.errors.kinetic_energy); });
  row("|momentum| kg m/s", [&](const Contender& c) { return num("%.3g", c.errors.momentum); });
  row("NaN spheres", [&](const Contender& c) { return std::to_string(c.errors.nan_spheres); });
  if (with_bullet)
    row("asleep at end", [&](const Contender& c) { return c.asleep < 0 ? "-" : std::to_string(c.asleep); });
  std::printf("  (ms/step: median over runs of each run's median/mean; errors: final state of the last run)\n");

  if (!o.json_path.empty()) {
    nlohmann::json engines = nlohmann::json::array();
    for (const Contender& c : contenders) {
      const PeerErrors& e = c.errors;
      engines.push_back({{"engine", c.label},
                         {"threads", c.label == "hail" ? hail_threads : 1},
                         {"ms_per_step_median", median_of(c.run_medians)},
                         {"ms_per_step_mean", median_of(c.run_means)},
                         {"run_medians", c.run_medians},
                         {"run_means", c.run_means},
                         {"ratio_to_hail", median_of(c.run_medians) / hail_ms},
                         {"setup_s", median_of(c.setup_s)},
                         {"tunnelled", e.tunnelled},
                         {"fell_off", e.fell_off},
                         {"max_ground_penetration", e.ground_penetration},
                         {"max_sphere_penetration", e.sphere_penetration},
                         {"kinetic_energy", e.kinetic_energy},
                         {"momentum", e.momentum},
                         {"nan_spheres", e.nan_spheres},
                         {"asleep_at_end", c.asleep}});
    }
    const nlohmann::json out_json = {
        {"scene", o.scene},
        {"spheres", peer.spheres.size()},
        {"steps", steps},
        {"timed_steps_from", warmup},
        {"dt", dt},
        {"repeat", o.repeat},
        {"bullet", with_bullet ? bullet_version() : "not built in"},
        {"bullet_terrain_ray_error", ray_error},
        {"kinetic_energy_start", start_energy},
        {"engines", engines},
        {"machine", {{"cpu", cpu_model()}, {"simd", simd_path()}, {"flags", build_flags()}}}};
    write_file_atomically(o.json_path, [&](std::ostream& out) { out << out_json.dump(2) << "\n"; });
  }
  return contenders[0].errors.nan_spheres == 0 ? 0 : 3;
}

// The flags of `hail-bench compare` (bench/cli.h's rules).

void add_compare_options(CLI::App& app, CompareOptions& o) {
  app.description("hail and Bullet (if built in) on the identical scene, R runs each alternating ABBA: one table");
  app.add_option("scene", o.scene, "a built-in scene")->check(CLI::IsMember(scene_names()));
  add_count(app, "--spheres", o.params.spheres, 1, 10'000'000, "sphere count");
  add_count(app, "--threads", o.params.threads, 0, 4096, "hail's worker threads (0: all; Bullet runs on one)");
  add_count(app, "--steps", o.steps, 1, 100'000'000, "steps (default -1: the scene's)");
  add_count(app, "--repeat", o.repeat, 1, 1000, "runs of each engine");
  app.add_option("--json", o.json_path, "every figure as JSON")->type_name("FILE");
  app.add_flag("--quiet", o.quiet, "no progress lines on stderr");
}

int compare_command(const std::vector<std::string>& args) {
  const std::optional<CompareOptions> parsed = parse_command("compare", add_compare_options, args);
  return parsed ? compare_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
