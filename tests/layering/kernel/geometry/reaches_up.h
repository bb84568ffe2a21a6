#pragma once
// A fixture for the layer check (cmake/HailCheckLayers.cmake), never compiled: geometry, the
// layer below the solver, includes a solver header. The check must refuse it (tests/CMakeLists.txt).
#include "kernel/solver/integrate.h"
