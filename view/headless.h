#pragma once
// hail-view --headless: the scene stepped --steps N times (or a recording's frame N), drawn once
// into an offscreen framebuffer of a hidden window, written as a PNG; the step and draw times
// printed.

#include "view/view_options.h"

namespace hail::view {

/// The process exit status. The options' paths are checked first (check_view_paths, which
/// also makes --frames DIR).
int run_headless(const ViewOptions& options);

}  // namespace hail::view
