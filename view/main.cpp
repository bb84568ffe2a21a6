// hail-view: watch a hail scene live and tune it (pause, step, reset, time scale, threads,
// material), replay a recording with a scrubber (hail-bench run ... --record FILE), or render a
// picture without a window (--headless --screenshot FILE.png). GLFW + OpenGL 3.3 core + Dear
// ImGui, all from Debian packages; built only where they are found (the top CMakeLists.txt).

#include <cstdio>
#include <exception>

#include "view/headless.h"
#include "view/interactive.h"
#include "view/view_options.h"

int main(int argc, char** argv) {
  try {
    const auto options = hail::view::parse_view_options(argc, argv);
    if (!options) return 0;
    // Before anything is built or run: a picture that cannot be written, or that would be
    // written over the recording or scene shown, is a bad command line.
    hail::view::check_view_paths(*options);
    return options->headless ? hail::view::run_headless(*options) : hail::view::run_window(*options);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "hail-view: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hail-view: %s\n", e.what());
    return 1;
  }
}
