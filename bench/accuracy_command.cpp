#include "accuracy_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "accuracy_cases.h"
#include "cli.h"
#include "gnuplot.h"
#include "peer_engine.h"
#include "scenes/machine_info.h"
#include "scenes/metrics.h"
#include "scenes/output_file.h"
#include "scenes/scenes.h"
#include "setting_flags.h"

namespace hail::bench {
namespace {

using clock_type = std::chrono::steady_clock;

/// One engine with one setting of its cost knobs.
struct Variant {
  std::string name;
  std::function<std::unique_ptr<PeerEngine>(const PeerScene&)> make;
  int substeps = 1;  ///< engine steps of dt / substeps per frame
};

std::vector<Variant> variants(const AccuracyOptions& o) {
  auto hail_with = [](auto tweak) {
    return [tweak](const PeerScene& scene) {
      WorldSettings s;
      s.threads = 1;  // the cases hold a few spheres: one thread, no scheduling noise
      tweak(s);
      return make_hail_engine(scene, s);
    };
  };
  std::vector<Variant> v;
  v.push_back({"hail", hail_with([](WorldSettings&) {}), 1});
  // The default integrator is the uniform-acceleration one; semi-implicit Euler was until 0.2.0.
  v.push_back({"hail-semi-implicit-euler",
               hail_with([](WorldSettings& s) { s.integrator = Integrator::SemiImplicitEuler; }), 1});
  v.push_back({"hail-4-substeps", hail_with([](WorldSettings&) {}), 4});
  v.push_back({"hail-4+2-passes",
               hail_with([](WorldSettings& s) { s.collision_iterations = 4, s.resting_iterations = 2; }), 1});
  // The soft step (Solver::SoftStep) with the knobs given, then with fewer and more substeps,
  // and with semi-implicit Euler.
  const SoftStepParams soft = o.settings.soft_step;
  auto soft_with = [&](int substeps, Integrator integrator) {
    return hail_with([soft, substeps, integrator](WorldSettings& s) {
      s.solver = Solver::SoftStep, s.soft_step = soft, s.integrator = integrator;
      s.soft_step.substeps = substeps;
    });
  };
  const Integrator by_default = WorldSettings{}.integrator;
  v.push_back({"hail-soft", soft_with(soft.substeps, by_default), 1});
  v.push_back({"hail-soft-semi-implicit-euler", soft_with(soft.substeps, Integrator::SemiImplicitEuler), 1});
  for (int substeps : {1, 2, 8})
    if (substeps != soft.substeps)
      v.push_back({"hail-soft-" + std::to_string(substeps) + "-substeps", soft_with(substeps, by_default), 1});
  // Peers at their defaults, and with 4 substeps per frame (their usual accuracy knob).
  for (const PeerFactory& peer : peer_factories())
    v.push_back({peer.name, peer.make, peer.name.ends_with("-4-substeps") ? 4 : 1});
  if (!o.only.empty())
    std::erase_if(v, [&](const Variant& x) { return std::find(o.only.begin(), o.only.end(), x.name) == o.only.end(); });
  return v;
}

}  // namespace

namespace {

struct Row {
  std::string what, variant;
  double dt = 0, error = 0, wall_ms = 0;
  std::string note;
};

/// Runs the case once; returns its error and the wall time spent in step() (ms).
std::pair<double, double> run_case(AccuracyCase& c, const Variant& v, double dt) {
  const PeerScene scene = c.scene();
  std::unique_ptr<PeerEngine> engine = v.make(scene);
  c.reset();
  std::vector<PeerState> state;
  const long frames = std::lround(c.duration() / dt);
  const float sub = static_cast<float>(dt / v.substeps);
  double stepping = 0.0;
  for (long f = 1; f <= frames; ++f) {
    const auto t0 = clock_type::now();
    for (int s = 0; s < v.substeps; ++s) engine->step(sub);
    stepping += std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
    engine->read_state(state);
    c.observe(state, static_cast<double>(f) * dt);
  }
  return {c.error(), stepping};
}

/// What a scene run ends with besides its positions: deepest sphere and ground penetration (m)
/// and kinetic energy (J, translational + rotational of solid spheres).
struct SceneFigures {
  double sphere_penetration = 0, ground_penetration = 0, kinetic_energy = 0;
};

SceneFigures scene_figures(const PeerScene& scene, const Terrain* terrain, const std::vector<PeerState>& state) {
  SceneFigures f;
  std::vector<float> px, py, pz, r;
  for (std::size_t k = 0; k < state.size(); ++k) {
    const PeerSphere& s = scene.spheres[k];
    px.push_back(state[k].position.x()), py.push_back(state[k].position.y()), pz.push_back(state[k].position.z());
    r.push_back(s.radius);
    f.kinetic_energy += 0.5 * s.mass * double(state[k].velocity.squaredNorm()) +
                        0.5 * 0.4 * s.mass * s.radius * s.radius * double(state[k].angular_velocity.squaredNorm());
    if (terrain)
      f.ground_penetration =
          std::max<double>(f.ground_penetration, terrain->penetration(px.back(), py.back(), pz.back(), s.radius));
  }
  f.sphere_penetration = max_pair_overlap(px, py, pz, r);
  return f;
}

/// Positions after `seconds` of a scene at dt, and the wall time of the stepping.
std::pair<std::vector<PeerState>, double> run_scene_for(const PeerScene& scene, const Variant& v, double dt,
                                                        double seconds) {
  std::unique_ptr<PeerEngine> engine = v.make(scene);
  const long frames = std::lround(seconds / dt);
  const float sub = static_cast<float>(dt / v.substeps);
  const auto t0 = clock_type::now();
  for (long f = 0; f < frames; ++f)
    for (int s = 0; s < v.substeps; ++s) engine->step(sub);
  const double ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
  std::vector<PeerState> state;
  engine->read_state(state);
  return {state, ms};
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::string dt_label(double dt) {
  char buffer[32];
  const double inverse = 1.0 / dt;
  if (std::fabs(inverse - std::round(inverse)) < 1e-6)
    std::snprintf(buffer, sizeof buffer, "1/%.0f", inverse);
  else
    std::snprintf(buffer, sizeof buffer, "%.6g", dt);
  return buffer;
}

// One SVG per case: error against wall time, log-log, one line per variant through its dts.
const char* kGnuplotScript = R"(# hail-bench accuracy: work-precision plots, one per case.
set terminal svg size 760,480 dynamic font 'sans,11'
set logscale xy
set grid
set key outside right
set xlabel 'wall time of the run (ms, stepping only)'
set ylabel 'relative error (below 1e-9 drawn at 1e-9)'
do for [c=1:words(CASES)] {
  name = word(CASES, c)
  set output 'accuracy_'.name.'.svg'
  set title name.' ('.MACHINE.')'
  plot for [v=1:words(VARIANTS)] 'accuracy_'.name.'.dat' index (v - 1) using 1:2 with linespoints title word(VARIANTS, v)
}
)";

}  // namespace

int accuracy_command(const AccuracyOptions& o) {
  prepare_output_dir(o.out_dir);  // before the runs: a folder that cannot be written fails now, not at the end
  const std::vector<Variant> vs = variants(o);
  std::vector<Row> rows;
  std::printf("hail-bench accuracy: error against wall time (%s, %s); median wall time of %d runs\n",
              cpu_model().c_str(), simd_path().c_str(), o.repeats);
  std::printf("  %-20s %-22s %8s %12s %12s\n", "case", "engine / knob", "dt", "error", "wall ms");
  std::vector<std::unique_ptr<AccuracyCase>> cases = known_answer_cases();
  for (auto& c : cases) {
    for (const Variant& v : vs) {
      for (double dt : o.dts) {
        std::vector<double> walls;
        double error = 0.0;
        for (int r = 0; r < o.repeats; ++r) {
          const auto [e, ms] = run_case(*c, v, dt);
          error = e, walls.push_back(ms);
        }
        rows.push_back({c->name(), v.name, dt, error, median(walls), ""});
        std::printf("  %-20s %-22s %8s %12.3e %12.3f\n", c->name().c_str(), v.name.c_str(), dt_label(dt).c_str(), error,
                    rows.back().wall_ms);
        std::fflush(stdout);
      }
    }
  }

  if (!o.no_scenes) {
    // No exact answer: compare with hail at dt / 16 after 1 s (RMS of positions over spheres).
    SceneParams params;
    params.spheres = o.scene_spheres;
    params.threads = 1;
    const std::pair<const char*, SceneBuilder> scenes[] = {{"terrain-rain", build_terrain_rain},
                                                           {"bowl-pile", build_bowl_pile}};
    for (const auto& [name, build] : scenes) {
      const PeerScene peer = peer_scene_from(build(params), name);
      const Terrain terrain(*peer.heightmap);
      const double base = 1.0 / 60.0, seconds = 1.0;
      if (!o.quiet) std::fprintf(stderr, "  %s: reference run at dt = 1/960 ...\n", name);
      const std::vector<PeerState> reference = run_scene_for(peer, vs[0], base / 16.0, seconds).first;
      const double reference_energy = scene_figures(peer, &terrain, reference).kinetic_energy;
      for (const Variant& v : vs) {
        for (double dt : {base, base / 4.0}) {
          std::vector<double> walls;
          std::vector<PeerState> state;
          for (int r = 0; r < o.repeats; ++r) {
            auto [s, ms] = run_scene_for(peer, v, dt, seconds);
            state = std::move(s), walls.push_back(ms);
          }
          double sum = 0.0;
          std::size_t nan = 0;
          for (std::size_t k = 0; k < state.size(); ++k) {
            const Vec3 d = state[k].position - reference[k].position;
            if (!d.allFinite())
              ++nan;
            else
              sum += double(d.squaredNorm());
          }
          const double rms = std::sqrt(sum / double(std::max<std::size_t>(state.size(), 1)));
          const std::string what = std::string(name) + "-" + std::to_string(o.scene_spheres);
          const SceneFigures fig = scene_figures(peer, &terrain, state);
          char note[160];
          std::snprintf(note, sizeof note, "penetration %.3g m spheres / %.3g m ground; KE %+.2f%% vs the reference%s",
                        fig.sphere_penetration, fig.ground_penetration,
                        100.0 * (fig.kinetic_energy - reference_energy) / std::max(reference_energy, 1e-9),
                        nan ? (", " + std::to_string(nan) + " NaN").c_str() : "");
          rows.push_back({what, v.name, dt, rms, median(walls), note});
          std::printf("  %-20s %-22s %8s %12.3e %12.3f   (m, RMS position vs dt = 1/960 at t = 1 s; %s)\n",
                      what.c_str(), v.name.c_str(), dt_label(dt).c_str(), rms, rows.back().wall_ms, note);
          std::fflush(stdout);
        }
      }
    }
  }

  nlohmann::json runs = nlohmann::json::array();
  write_file_atomically(o.out_dir + "/accuracy.csv", [&](std::ostream& csv) {
    csv << "case,engine,dt,error,wall_ms,note\n";
    for (const Row& r : rows)
      csv << r.what << ',' << r.variant << ',' << r.dt << ',' << r.error << ',' << r.wall_ms << ",\"" << r.note
          << "\"\n";
  });
  for (const Row& r : rows)
    runs.push_back({{"case", r.what},
                    {"engine", r.variant},
                    {"dt", r.dt},
                    {"error", r.error},
                    {"wall_ms", r.wall_ms},
                    {"note", r.note}});
  write_file_atomically(o.out_dir + "/accuracy.json", [&](std::ostream& out) {
    out << nlohmann::json{{"machine", {{"cpu", cpu_model()}, {"simd", simd_path()}}}, {"runs", runs}}.dump(2) << "\n";
  });
  std::printf("  data: %s/accuracy.csv, %s/accuracy.json\n", o.out_dir.c_str(), o.out_dir.c_str());
  if (o.no_plot) return 0;

  std::vector<std::string> case_names, variant_names;
  for (const Row& r : rows) {
    if (std::find(case_names.begin(), case_names.end(), r.what) == case_names.end()) case_names.push_back(r.what);
    if (std::find(variant_names.begin(), variant_names.end(), r.variant) == variant_names.end())
      variant_names.push_back(r.variant);
  }
  std::string cases_word, variants_word;
  for (const std::string& c : case_names) {
    cases_word += (cases_word.empty() ? "" : " ") + c;
    write_file_atomically(o.out_dir + "/accuracy_" + c + ".dat", [&](std::ostream& dat) {
      for (const std::string& v : variant_names) {  // one block per variant, two blank lines apart (gnuplot's index)
        dat << "# " << v << ": wall_ms error\n";
        for (const Row& r : rows)
          if (r.what == c && r.variant == v) dat << r.wall_ms << ' ' << std::max(r.error, 1e-9) << '\n';
        dat << "\n\n";
      }
    });
  }
  for (const std::string& v : variant_names) variants_word += (variants_word.empty() ? "" : " ") + v;
  write_file_atomically(o.out_dir + "/accuracy.gp", [](std::ostream& gp) { gp << kGnuplotScript; });
  plot_with_gnuplot(o.out_dir, "accuracy.gp",
                    "CASES=" + gnuplot_string(cases_word) + "; VARIANTS=" + gnuplot_string(variants_word) +
                        "; MACHINE=" + gnuplot_string(cpu_model()),
                    o.out_dir + "/accuracy_<case>.svg (one per case)");
  return 0;
}

// The flags of `hail-bench accuracy` (bench/cli.h's rules).

void add_accuracy_options(CLI::App& app, AccuracyOptions& o) {
  app.description("error against wall time: known-answer cases and two scenes, for hail's knobs and the peers");
  app.add_option_function<std::string>(
         "--dt",
         [&o](const std::string& list) {
           o.dts.clear();
           for (std::size_t start = 0; start <= list.size();) {
             const std::size_t end = std::min(list.find(',', start), list.size());
             const std::string item = list.substr(start, end - start);
             o.dts.push_back(item.rfind("1/", 0) == 0 ? 1.0 / parse_real("--dt 1/N", item.substr(2), 1.0, 1e9)
                                                      : parse_real("--dt", item, 0.0, 1.0, /*exclude_min=*/true));
             start = end + 1;
           }
         },
         "time steps, comma-separated, each a number or 1/N in (0, 1] (default 1/60,1/240,1/1000)")
      ->type_name("LIST");
  add_count(app, "--spheres", o.scene_spheres, 1, 10'000'000, "spheres of the terrain-rain and bowl-pile cases");
  add_count(app, "--repeats", o.repeats, 1, 1000, "runs of each case; the median wall time is reported");
  app.add_option("--out", o.out_dir, "folder of the CSV, JSON and plots")->type_name("DIR");
  app.add_flag("--no-plot", o.no_plot, "no gnuplot SVGs");
  app.add_flag("--no-scenes", o.no_scenes, "the known-answer cases only");
  app.add_flag("--quiet", o.quiet, "no progress lines on stderr");
  add_setting_flags(app, o.settings, {"soft_step."});  // --substeps, --contact-cycles, ...
  app.add_option("--variants", o.only, "only these engines / knobs (as the table names them), comma-separated")
      ->delimiter(',')
      ->type_name("LIST");
}

int accuracy_command(const std::vector<std::string>& args) {
  const std::optional<AccuracyOptions> parsed = parse_command("accuracy", add_accuracy_options, args);
  return parsed ? accuracy_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
