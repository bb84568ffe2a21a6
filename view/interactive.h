#pragma once
// hail-view with a window: a live run (stepped on its own thread) or a replay, the orbit camera
// on the mouse, the ImGui panel beside it.

#include "view/view_options.h"

namespace hail::view {

/// The process exit status.
int run_window(const ViewOptions& options);

}  // namespace hail::view
