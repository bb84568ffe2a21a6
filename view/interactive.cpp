#include "view/interactive.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <epoxy/gl.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "view/camera.h"
#include "view/panel.h"
#include "view/renderer.h"
#include "view/replay.h"
#include "view/scene_source.h"
#include "view/window.h"

namespace hail::view {
namespace {

/// Orbit, pan and zoom from the mouse, unless ImGui has it.
void move_camera(GLFWwindow* window, OrbitCamera& camera, int height) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureMouse) return;
  if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
  if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
      glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
    camera.pan(io.MouseDelta.x, io.MouseDelta.y, float(height));
  if (io.MouseWheel != 0.0f) camera.zoom(io.MouseWheel);
}

/// What is shown: a live run or a replay, behind one call per window frame.
class Source {
 public:
  virtual ~Source() = default;
  /// Updates `frame` when there is a newer one; true if it did.
  virtual bool update(Frame& frame, double now_s) = 0;
  virtual void panel(const Frame& frame, Renderer& renderer, const Plots& plots) = 0;
  /// The debug lines on.
  [[nodiscard]] virtual DebugDraw debug_draw() const { return {}; }
  /// Mouse and keys beyond the camera's.
  virtual void input(GLFWwindow* window, const OrbitCamera& camera) {}
};

class LiveSource final : public Source {
 public:
  LiveSource(const ViewOptions& o, std::string title)
      : sim_(scene_factory(o), {.threads = o.params.threads}), title_(std::move(title)) {
    controls_.threads = sim_.thread_count();
    controls_.sleep = o.sleep.value_or(o.params.settings.sleep);
    controls_.draw = o.draw;
    if (o.draw.bvh_depth >= 0) controls_.bvh_depth = o.draw.bvh_depth;
    sim_.set_capture(capture_for(o.colour, o.draw));
    for (const BvhNodeBox& n : sim_.geometry().terrain_bvh) bvh_depth_ = std::max(bvh_depth_, int(n.depth));
  }
  [[nodiscard]] DebugDraw debug_draw() const override { return controls_.draw; }
  bool update(Frame& frame, double) override { return sim_.latest(frame); }
  [[nodiscard]] const LiveSimulation& simulation() const { return sim_; }
  /// Shift + left click: spheres dropped where the cursor points; F: a fast sphere from the eye.
  void input(GLFWwindow* window, const OrbitCamera& camera) override {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantCaptureMouse || io.WantCaptureKeyboard) return;
    double x = 0, y = 0;
    glfwGetCursorPos(window, &x, &y);
    int window_w = 0, window_h = 0;
    glfwGetWindowSize(window, &window_w, &window_h);
    if (io.KeyShift && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
      const auto [origin, direction] = camera.ray_through(x, y, window_w, window_h);
      sim_.spawn_at(origin, direction);
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_F, /*repeat=*/false)) {
      const auto [origin, direction] = camera.ray_through(x, y, window_w, window_h);
      sim_.fire(origin + direction * 2.0f, direction, kFireSpeed);
    }
  }
  static constexpr float kFireSpeed = 80.0f;  ///< m/s: over a metre a step at 60 steps/s
  void panel(const Frame& frame, Renderer& renderer, const Plots& plots) override {
    if (controls_.spheres == 0) controls_.spheres = int(frame.size());  // the scene's own, to start with
    live_panel(title_, frame, sim_, controls_, renderer, plots, bvh_depth_);
  }

 private:
  LiveSimulation sim_;
  int bvh_depth_ = -1;  // the terrain BVH's deepest level
  std::string title_;
  LiveControls controls_;
};

class ReplaySource final : public Source {
 public:
  explicit ReplaySource(const ViewOptions& o) : replay_(o.replay_path), title_(o.replay_path) {
    controls_.frame = std::min(o.steps, std::max(int(replay_.frame_count()) - 1, 0));
    controls_.playing = o.steps == 0;
  }
  Replay& replay() { return replay_; }
  void set_note(std::string note) { note_ = std::move(note); }
  bool update(Frame& frame, double now_s) override {
    const int count = int(replay_.frame_count());
    if (controls_.playing && count > 0 && now_s - shown_at_ >= 1.0 / controls_.frames_per_second) {
      controls_.frame = (controls_.frame + 1) % count;
      shown_at_ = now_s;
    }
    if (controls_.frame == loaded_ || count == 0) return false;
    replay_.load(std::size_t(controls_.frame), frame);
    loaded_ = controls_.frame;
    return true;
  }
  void panel(const Frame& frame, Renderer& renderer, const Plots& plots) override {
    replay_panel(title_, note_, int(replay_.frame_count()), frame, controls_, renderer, plots);
  }

 private:
  Replay replay_;
  std::string title_, note_;
  ReplayControls controls_;
  int loaded_ = -1;
  double shown_at_ = 0.0;
};

}  // namespace

int run_window(const ViewOptions& o) {
  // The scene is built before the window opens: a bad scene file fails without a flash of window.
  std::unique_ptr<Source> source;
  StaticGeometry geometry;  // the terrain and planes drawn
  std::string note;
  if (!o.replay_path.empty()) {
    auto replay = std::make_unique<ReplaySource>(o);
    geometry = StaticGeometry::of(*scene_of_recording(replay->replay().header(), o.scene_file, note).world);
    replay->set_note(note);
    source = std::move(replay);
  } else {
    auto live = std::make_unique<LiveSource>(o, o.scene_file.empty() ? o.scene : o.scene_file);
    geometry = live->simulation().geometry();
    source = std::move(live);
  }
  Frame frame;
  source->update(frame, 0.0);

  GLFWwindow* window = open_window(o.width, o.height, /*visible=*/true, "hail-view");
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  {
    const Bounds bounds = scene_bounds(geometry, frame);
    Renderer renderer(geometry.heightmap(), geometry.planes, geometry.meshes, bounds.centre(), bounds.extent());
    OrbitCamera camera;
    const Bounds focus = focus_bounds(bounds, frame);
    camera.frame_box(focus.min, focus.max);
    camera.distance /= o.zoom;
    renderer.colour_mode = o.colour;
    Plots plots;
    bool changed = true;
    DebugLines lines;
    DebugDraw drawn;  // what `lines` holds
    while (!glfwWindowShouldClose(window)) {
      glfwPollEvents();
      if (source->update(frame, glfwGetTime())) {
        changed = true;
        if (o.replay_path.empty()) plots.add_step(frame);
      }
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      int width = 0, height = 0;
      glfwGetFramebufferSize(window, &width, &height);
      move_camera(window, camera, height);
      source->input(window, camera);
      // The draw time: the spheres' upload and the scene's draw calls, waited for (glFinish),
      // without the panel.
      const auto start = std::chrono::steady_clock::now();
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      const DebugDraw draw = source->debug_draw();
      if (changed || draw != drawn) build_debug_lines(frame, geometry.terrain_bvh, draw, lines), drawn = draw;
      renderer.draw(frame, changed, camera, width, height, draw.any() ? &lines : nullptr);
      glFinish();
      plots.add_draw(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      changed = false;
      source->panel(frame, renderer, plots);
      ImGui::Render();
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      glfwSwapBuffers(window);
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  source.reset();  // stops the simulation thread
  close_window(window);
  return 0;
}

}  // namespace hail::view
