#include "view/headless.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
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

/// What is drawn: the live scene at step 0, or the recording's frame `first` and the scene it names.
struct Subject {
  bench::Scene scene;
  std::optional<Replay> replay;
  Frame frame;
  std::string title;

  Subject(const ViewOptions& o, std::size_t first) {
    std::string note;
    if (!o.replay_path.empty()) {
      replay.emplace(o.replay_path);
      if (replay->frame_count() == 0) throw std::runtime_error("the recording has no frames");
      scene = scene_of_recording(replay->header(), o.scene_file, note);
      replay->load(std::min(first, replay->frame_count() - 1), frame);
      title = o.replay_path;
    } else {
      scene = scene_factory(o)({.threads = o.params.threads});
      capture_frame(*scene.world, 0.0, 0, frame, capture_for(o.colour, o.draw));
      title = o.scene_file.empty() ? o.scene : o.scene_file;
    }
    if (!note.empty()) std::fprintf(stderr, "hail-view: %s\n", note.c_str());
  }
};

/// The renderer, camera and offscreen target of one picture size (a current context needed),
/// the camera framed on `frame`.
struct Picture {
  StaticGeometry geometry;
  Bounds bounds;
  Renderer renderer;
  OrbitCamera camera;
  OffscreenTarget target;
  int width, height;
  DebugDraw debug_draw;
  DebugLines lines;

  Picture(const World& world, const Frame& frame, const ViewOptions& o)
      : geometry(StaticGeometry::of(world)),
        bounds(scene_bounds(geometry, frame)),
        renderer(geometry.heightmap(), geometry.planes, geometry.meshes, bounds.centre(), bounds.extent()),
        target(o.width, o.height),
        width(o.width),
        height(o.height),
        debug_draw(o.draw) {
    const Bounds focus = focus_bounds(bounds, frame);
    camera.frame_box(focus.min, focus.max);
    camera.distance /= o.zoom;
    renderer.colour_mode = o.colour;
  }
  void draw(const Frame& frame) {
    target.bind();
    build_debug_lines(frame, geometry.terrain_bvh, debug_draw, lines);
    renderer.draw(frame, true, camera, width, height, debug_draw.any() ? &lines : nullptr);
  }
  void write(const std::string& path) const { write_png(path, width, height, target.read_rgb()); }
};

/// --frames DIR --every K: pictures of the run at step 0, K, 2K, ... up to --steps (or of every
/// K-th recorded frame), the camera fixed where it framed the first.
int write_sequence(const ViewOptions& o) {
  Subject s(o, 0);
  GLFWwindow* window = open_window(o.width, o.height, /*visible=*/false, "hail-view");
  int pictures = 0;
  {
    Picture picture(*s.scene.world, s.frame, o);
    auto shoot = [&] {
      picture.draw(s.frame);
      picture.write(frame_picture_path(o.frames_dir, pictures++));
    };
    shoot();
    if (s.replay) {
      for (std::size_t k = std::size_t(o.every); k < s.replay->frame_count(); k += std::size_t(o.every)) {
        s.replay->load(k, s.frame);
        shoot();
      }
    } else {
      for (int step = 1; step <= o.steps; ++step) {
        s.scene.world->step(s.scene.dt);
        if (step % o.every != 0) continue;
        capture_frame(*s.scene.world, 0.0, std::uint64_t(step), s.frame, capture_for(o.colour, o.draw));
        shoot();
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
  Subject s(o, std::size_t(o.steps));
  double step_ms = 0.0;
  if (!s.replay) {
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < o.steps; ++k) s.scene.world->step(s.scene.dt);
    step_ms = o.steps > 0 ? ms_since(start) / o.steps : 0.0;
    capture_frame(*s.scene.world, step_ms, std::uint64_t(o.steps), s.frame, capture_for(o.colour, o.draw));
  }
  GLFWwindow* window = open_window(o.width, o.height, /*visible=*/false, "hail-view");
  int status = 0;
  {
    Picture picture(*s.scene.world, s.frame, o);
    picture.draw(s.frame);  // the first draw uploads and compiles
    glFinish();
    constexpr int kDraws = 5;
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < kDraws; ++k) picture.draw(s.frame);
    glFinish();
    const double draw_ms = ms_since(start) / kDraws;
    picture.write(o.screenshot_path);
    std::printf("hail-view: %s, %zu spheres, step %llu: %.3f ms/step, %.3f ms/draw (%dx%d, upload included; %s, %s)\n",
                s.title.c_str(), s.frame.size(), static_cast<unsigned long long>(s.frame.step), step_ms, draw_ms,
                o.width, o.height, reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
                reinterpret_cast<const char*>(glGetString(GL_VERSION)));
    if (s.scene.world && s.scene.world->settings().sleep)
      std::printf("hail-view: %zu spheres asleep\n",
                  std::size_t(std::count(s.frame.sleeping.begin(), s.frame.sleeping.end(), 1)));
    if (picture.debug_draw.any())
      std::printf("hail-view: debug lines: %zu contact normals, %zu box and cell edges\n",
                  picture.lines.overlay.segments(), picture.lines.tested.segments());
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
