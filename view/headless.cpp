#include "view/headless.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "view/camera.h"
#include "view/live_simulation.h"
#include "view/png_file.h"
#include "view/renderer.h"
#include "view/replay.h"
#include "view/scene_source.h"
#include "view/window.h"

namespace hail::view {
namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// --frames DIR --every K: pictures of the run at step 0, K, 2K, ... up to --steps (or of every
/// K-th recorded frame), the camera fixed where it framed the first.
int write_sequence(const ViewOptions& o) {
  std::filesystem::create_directories(o.frames_dir);
  bench::Scene scene;
  std::optional<Replay> replay;
  std::string note;
  Frame frame;
  if (!o.replay_path.empty()) {
    replay.emplace(o.replay_path);
    if (replay->frame_count() == 0) throw std::runtime_error("the recording has no frames");
    scene = scene_of_recording(replay->header(), note);
    replay->load(0, frame);
  } else {
    scene = scene_factory(o)(o.params.threads);
    capture_frame(*scene.world, 0.0, 0, frame);
  }
  if (!note.empty()) std::fprintf(stderr, "hail-view: %s\n", note.c_str());
  GLFWwindow* window = open_window(o.width, o.height, /*visible=*/false, "hail-view");
  int pictures = 0;
  {
    const StaticGeometry geometry = StaticGeometry::of(*scene.world);
    const Bounds bounds = scene_bounds(geometry, frame);
    Renderer renderer(geometry.heightmap(), geometry.planes, bounds.centre(), bounds.extent());
    OrbitCamera camera;
    const Bounds focus = focus_bounds(bounds, frame);
    camera.frame_box(focus.min, focus.max);
    OffscreenTarget target(o.width, o.height);
    auto picture = [&] {
      target.bind();
      renderer.draw(frame, true, camera, o.width, o.height);
      char name[32];
      std::snprintf(name, sizeof name, "frame-%06d.png", pictures++);
      write_png((std::filesystem::path(o.frames_dir) / name).string(), o.width, o.height, target.read_rgb());
    };
    if (replay) {
      for (std::size_t k = 0; k < replay->frame_count(); k += std::size_t(o.every)) {
        replay->load(k, frame);
        picture();
      }
    } else {
      picture();
      for (int step = 1; step <= o.steps; ++step) {
        scene.world->step(scene.dt);
        if (step % o.every != 0) continue;
        capture_frame(*scene.world, 0.0, std::uint64_t(step), frame);
        picture();
      }
    }
  }
  close_window(window);
  std::printf("hail-view: %d pictures written to %s (frame-000000.png ...)\n", pictures, o.frames_dir.c_str());
  return 0;
}

}  // namespace

int run_headless(const ViewOptions& o) {
  if (!o.frames_dir.empty()) return write_sequence(o);
  bench::Scene scene;
  Frame frame;
  std::string title, note;
  double step_ms = 0.0;
  if (!o.replay_path.empty()) {
    Replay replay(o.replay_path);
    if (replay.frame_count() == 0) throw std::runtime_error("the recording has no frames");
    scene = scene_of_recording(replay.header(), note);
    replay.load(std::min<std::size_t>(std::size_t(o.steps), replay.frame_count() - 1), frame);
    title = o.replay_path;
  } else {
    scene = scene_factory(o)(o.params.threads);
    title = o.scene_file.empty() ? o.scene : o.scene_file;
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < o.steps; ++k) scene.world->step(scene.dt);
    step_ms = o.steps > 0 ? ms_since(start) / o.steps : 0.0;
    capture_frame(*scene.world, step_ms, std::uint64_t(o.steps), frame);
  }
  if (!note.empty()) std::fprintf(stderr, "hail-view: %s\n", note.c_str());

  GLFWwindow* window = open_window(o.width, o.height, /*visible=*/false, "hail-view");
  int status = 0;
  {
    const StaticGeometry geometry = StaticGeometry::of(*scene.world);
    const Bounds bounds = scene_bounds(geometry, frame);
    Renderer renderer(geometry.heightmap(), geometry.planes, bounds.centre(), bounds.extent());
    OrbitCamera camera;
    const Bounds focus = focus_bounds(bounds, frame);
    camera.frame_box(focus.min, focus.max);
    OffscreenTarget target(o.width, o.height);
    target.bind();
    renderer.draw(frame, true, camera, o.width, o.height);  // the first draw uploads and compiles
    glFinish();
    constexpr int kDraws = 5;
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < kDraws; ++k) renderer.draw(frame, true, camera, o.width, o.height);
    glFinish();
    const double draw_ms = ms_since(start) / kDraws;
    write_png(o.screenshot_path, o.width, o.height, target.read_rgb());
    std::printf("hail-view: %s, %zu spheres, step %llu: %.3f ms/step, %.3f ms/draw (%dx%d, upload included; %s, %s)\n",
                title.c_str(), frame.size(), static_cast<unsigned long long>(frame.step), step_ms, draw_ms, o.width,
                o.height, reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
                reinterpret_cast<const char*>(glGetString(GL_VERSION)));
    std::printf("hail-view: picture written to %s\n", o.screenshot_path.c_str());
    if (glGetError() != GL_NO_ERROR) {
      std::fprintf(stderr, "hail-view: OpenGL reported an error\n");
      status = 1;
    }
  }
  close_window(window);
  return status;
}

}  // namespace hail::view
