#include "solver_options.h"

#include "cli.h"

namespace hail::bench {

const char* solver_name(Solver solver) { return solver == Solver::SoftStep ? "soft" : "passes"; }

void add_solver_options(CLI::App& app, Solver& solver, SoftStepParams& soft) {
  app.add_option_function<std::string>(
         "--solver", [&solver](const std::string& v) { solver = v == "soft" ? Solver::SoftStep : Solver::Passes; },
         "the contact solver: passes (collision and resting passes, the default) or soft (Box2D v3's soft step)")
      ->check(CLI::IsMember({"passes", "soft"}));
  add_soft_step_options(app, soft);
}

void add_soft_step_options(CLI::App& app, SoftStepParams& soft) {
  add_count(app, "--substeps", soft.substeps, 1, kMaxIterations, "soft step: substeps per step");
  add_number(app, "--contact-cycles", soft.contact_cycles, 0.0, 0.25,
             "soft step: contact stiffness, cycles per substep (ground contacts twice this)", /*exclude_min=*/true);
  add_number(app, "--damping-ratio", soft.damping_ratio, 0.0, 1e6, "soft step: contact damping ratio",
             /*exclude_min=*/true);
  add_count(app, "--relax", soft.relax_iterations, 0, kMaxIterations, "soft step: relax iterations per substep");
  add_count(app, "--depenetration-max", soft.depenetration_iterations_max, 0, kMaxIterations,
            "soft step: most depenetration passes a step (past depenetration_iterations while an overlap is "
            "beyond twice the slop)");
}

}  // namespace hail::bench
