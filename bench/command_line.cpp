#include "command_line.h"

#include <cstdio>
#include <exception>
#include <functional>
#include <stdexcept>

#include "accuracy_command.h"
#include "bvh_build_command.h"
#include "cli.h"
#include "compare_command.h"
#include "kernel/dispatch/simd_dispatch.h"
#include "pairs_command.h"
#include "query_command.h"
#include "rays_command.h"
#include "run_command.h"
#include "scale_command.h"
#include "scenes/scenes.h"
#include "sleep_command.h"
#include "stress_command.h"

namespace hail::bench {
namespace {

constexpr const char* kOverview =
    "hail-bench: the benchmark tool. Every time it prints comes with the run's error figures, the machine,\n"
    "the SIMD path and a hash of the final state. hail-bench COMMAND --help lists a command's options\n"
    "with the range each accepts; docs/benchmarks.md says what each command measures.";

std::string footer() {
  std::string text =
      "--simd PATH (before or after the command) runs the SIMD kernels of PATH instead of the widest this CPU\n"
      "supports; it overrides the HAIL_SIMD environment variable; a path this CPU lacks is an error.\n"
      "exit status: 2 for a bad command line (an unknown option, a count not a whole number in range, an output\n"
      "that cannot be written or would overwrite an input), 1 if a run or a write failed, 3 if a run ended with\n"
      "NaN (stress: 1 if a case failed)\n\n"
      "scenes (defined exactly in docs/scenes.md):\n";
  char line[256];
  for (const SceneEntry& s : scene_registry()) {
    std::snprintf(line, sizeof line, "  %-14s %s\n", s.name, s.summary);
    text += line;
  }
  return text;
}

/// Every command's options, filled while parsing.
struct AllOptions {
  RunCommandOptions run;
  AccuracyOptions accuracy;
  CompareOptions compare;
  StressOptions stress;
  ScaleOptions scale;
  QueryOptions query;
  PairsOptions pairs;
  BvhBuildCommandOptions bvh_build;
  RaysOptions rays;
  SleepOptions sleep;
};

/// One subcommand and what runs it once it is parsed.
struct Command {
  CLI::App* app;
  std::function<int()> run;
};

template <class Options>
void add_command(CLI::App& app, std::vector<Command>& commands, const char* name,
                 void (*add_options)(CLI::App&, Options&), int (*command)(const Options&), Options& options) {
  CLI::App* sub = app.add_subcommand(name);
  use_bench_conventions(*sub);
  add_options(*sub, options);
  sub->fallthrough();  // --simd after the command is hail-bench's
  commands.push_back({sub, [command, &options] { return command(options); }});
}

}  // namespace

int hail_bench(const std::vector<std::string>& args) {
  CLI::App app(kOverview, "hail-bench");
  use_bench_conventions(app);
  app.footer(footer());
  app.require_subcommand(1);
  app.add_option_function<std::string>(
         "--simd", [](const std::string& path) { set_simd_path(parse_simd_path(path)); },
         "run the SIMD kernels of PATH (overrides HAIL_SIMD)")
      ->check(CLI::IsMember({"sse4.2", "avx2", "avx512"}))
      ->type_name("PATH");
  AllOptions o;
  std::vector<Command> commands;
  add_command(app, commands, "run", add_run_options, run_command, o.run);
  add_command(app, commands, "accuracy", add_accuracy_options, accuracy_command, o.accuracy);
  add_command(app, commands, "compare", add_compare_options, compare_command, o.compare);
  add_command(app, commands, "stress", add_stress_options, stress_command, o.stress);
  add_command(app, commands, "scale", add_scale_options, scale_command, o.scale);
  add_command(app, commands, "query", add_query_options, query_command, o.query);
  add_command(app, commands, "pairs", add_pairs_options, pairs_command, o.pairs);
  add_command(app, commands, "bvh-build", add_bvh_build_options, bvh_build_command, o.bvh_build);
  add_command(app, commands, "rays", add_rays_options, rays_command, o.rays);
  add_command(app, commands, "sleep", add_sleep_options, sleep_command, o.sleep);

  if (args.empty() || (args.size() == 1 && args[0] == "help")) {
    std::fputs(app.help().c_str(), stdout);
    return args.empty() ? 2 : 0;
  }
  try {
    try {
      app.parse(std::vector<std::string>(args.rbegin(), args.rend()));  // CLI11 takes them last first
    } catch (const CLI::CallForHelp&) {
      std::fputs(app.help().c_str(), stdout);  // the command's own, after COMMAND --help
      return 0;
    } catch (const CLI::ParseError& e) {
      const std::vector<CLI::App*> chosen = app.get_subcommands();
      const std::string see = chosen.empty() ? "hail-bench --help" : "hail-bench " + chosen[0]->get_name() + " --help";
      std::fprintf(stderr, "hail-bench: %s (see %s)\n", e.what(), see.c_str());
      return 2;
    }
    // Resolves HAIL_SIMD now (when --simd did not choose), so that a bad value stops the run
    // before it starts, with the message of hail::InvalidArgument.
    (void)active_simd_path();
    for (const Command& c : commands)
      if (c.app->parsed()) return c.run();
    return 2;                                 // require_subcommand(1) leaves no way here
  } catch (const std::invalid_argument& e) {  // hail::InvalidArgument too: a bad command line or input
    std::fprintf(stderr, "hail-bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {  // a run or a write that failed
    std::fprintf(stderr, "hail-bench: %s\n", e.what());
    return 1;
  }
}

}  // namespace hail::bench
