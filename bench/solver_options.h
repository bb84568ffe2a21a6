#pragma once
// The contact solver's flags, shared by `hail-bench run` and `hail-bench accuracy`: --solver
// passes|soft (WorldSettings::solver) and the soft step's knobs (WorldSettings::soft_step).

#include "hail/world_settings.h"

namespace CLI {
class App;
}

namespace hail::bench {

/// Adds --solver and the soft step's knobs (add_soft_step_options), writing them to `solver` and
/// `soft`.
void add_solver_options(CLI::App& app, Solver& solver, SoftStepParams& soft);

/// The soft step's knobs alone: --substeps, --contact-cycles, --damping-ratio, --relax,
/// --depenetration-max.
void add_soft_step_options(CLI::App& app, SoftStepParams& soft);

/// "passes" or "soft", as --solver takes them.
[[nodiscard]] const char* solver_name(Solver solver);

}  // namespace hail::bench
