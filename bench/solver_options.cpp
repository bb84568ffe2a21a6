#include "solver_options.h"

namespace hail::bench {

const char* solver_name(Solver solver) { return solver == Solver::SoftStep ? "soft" : "passes"; }

}  // namespace hail::bench
