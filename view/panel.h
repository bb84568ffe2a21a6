#pragma once
// The ImGui panel: controls for a live run or a replay, and plots of the step's per-phase
// milliseconds, the draw time and the kinetic energy over the last frames.

#include <array>
#include <string>
#include <vector>

#include "view/frame.h"
#include "view/live_simulation.h"
#include "view/renderer.h"

namespace hail::view {

/// The last kLength values of each plotted figure, oldest first.
class Plots {
 public:
  static constexpr int kLength = 240;
  static constexpr int kPhases = 9;
  static constexpr std::array<const char*, kPhases> kPhaseNames = {
      "reorder", "predict", "detect terrain", "detect pairs", "solve", "sweep", "integrate", "depenetrate", "islands"};

  /// A new step (live) adds its figures; a draw adds its time.
  void add_step(const Frame& frame);
  void add_draw(double ms);
  void draw() const;

 private:
  /// The phases' milliseconds stacked, a column per step (stack_series), with a legend, and the
  /// draw time's plot beside it (its own scale: a software rasteriser's draw is ~100 steps).
  void draw_phases() const;
  static void push(std::vector<float>& v, float x);
  std::array<std::vector<float>, kPhases> phases_;
  std::vector<float> step_ms_, draw_ms_, energy_, overlap_, tunnelled_;
};

/// What the live panel edits, kept between frames.
struct LiveControls {
  bool paused = false;
  float speed = 1.0f;
  int threads = 1;
  float restitution = 0.5f, friction = 0.5f;
  int spheres = 0;      ///< for the next reset (0: not yet known)
  int pair_search = 0;  ///< index into the panel's list (0: automatic), for the next reset
  bool sleep = false;   ///< sleeping, for the next reset
  DebugDraw draw;       ///< the debug lines on
  int bvh_depth = 4;    ///< the BVH depth drawn while its checkbox is on
};

/// The live run's panel; calls `sim`'s controls as they are changed. `bvh_depth` is the
/// terrain BVH's deepest level (the depth slider's end; < 0 without a terrain).
void live_panel(const std::string& title, const Frame& frame, LiveSimulation& sim, LiveControls& controls,
                Renderer& renderer, const Plots& plots, int bvh_depth);

/// What the replay panel edits.
struct ReplayControls {
  bool playing = true;
  int frame = 0;
  float frames_per_second = 30.0f;
};

/// The replay's panel; true if the frame to show changed.
bool replay_panel(const std::string& title, const std::string& note, int frame_count, const Frame& frame,
                  ReplayControls& controls, Renderer& renderer, const Plots& plots);

}  // namespace hail::view
