#pragma once
// A scene stepped on a thread of its own, so that a slow step never freezes the window. The
// render thread reads the latest whole step (latest()) and sends controls (pause, single step,
// reset, playback speed, threads, material), which the simulation thread applies between steps:
// the World is only ever touched by that thread.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "scenes/scenes.h"
#include "view/draw_choices.h"
#include "view/frame.h"
#include "view/static_geometry.h"

namespace hail::view {

/// What the panel may change in how the scene is built; nullopt: the scene's own.
struct SceneChoice {
  int threads = 0;  ///< worker threads (0: all)
  std::optional<std::size_t> spheres = std::nullopt;
  std::optional<PairSearch> pair_search = std::nullopt;
  std::optional<bool> sleep = std::nullopt;  ///< WorldSettings::sleep
};

/// Builds the scene as chosen.
using SceneFactory = std::function<bench::Scene(const SceneChoice&)>;

/// The World's state now, as a Frame (slot order), with the last step's figures, and what
/// `capture` asks for of the last step.
void capture_frame(const World& world, double step_ms, std::uint64_t step, Frame& out, const Capture& capture = {});

/// Up to this many spheres a live run measures its error figures after every step (untimed;
/// O(spheres) with a pair search): beyond it they would slow the run they describe.
inline constexpr std::size_t kErrorFiguresUpTo = 100'000;

class LiveSimulation {
 public:
  /// Builds the scene and starts stepping it (or, `paused`, waits for step_once or set_paused(false)).
  LiveSimulation(SceneFactory factory, const SceneChoice& choice, bool paused = false);
  ~LiveSimulation();
  LiveSimulation(const LiveSimulation&) = delete;
  LiveSimulation& operator=(const LiveSimulation&) = delete;

  /// Copies the latest whole step (or the state a reset, threads or material change left) into
  /// `out` if this reader has not had it yet; true if it did. One reader: the render thread.
  bool latest(Frame& out);

  void set_paused(bool paused);
  void step_once();  ///< one step, while paused
  void reset();      ///< the scene built again, from its start
  /// The sphere count, pair search and sleeping the next reset builds with.
  void choose_for_reset(std::size_t spheres, PairSearch pair_search, bool sleep);
  /// What the frames carry from now on (the current one again at once, so that a toggle shows
  /// while paused).
  void set_capture(const Capture& capture);
  /// Steps per wall second = speed / dt (1: real time, 0.1: slow motion); the physics is the
  /// same at every speed (dt never changes), only the pacing.
  void set_speed(float speed) { speed_.store(speed); }
  /// Rebuilt on this many threads, its state carried over by a snapshot (bitwise the same run).
  void set_threads(int threads);
  /// Restitution and friction of every sphere.
  void set_material(float restitution, float friction);
  /// A 3 x 3 x 3 block of spheres dropped a few radii above where the ray first meets the scene
  /// (World::raycast); nothing if it meets nothing.
  void spawn_at(const Vec3& origin, const Vec3& direction);
  /// One sphere shot from `origin` along `direction` at `speed` m/s (fast enough for continuous
  /// collision: it should stop on the terrain, not pass through).
  void fire(const Vec3& origin, const Vec3& direction, float speed);

  /// The scene's terrain and planes, as built (a reset builds the same scene again).
  [[nodiscard]] const StaticGeometry& geometry() const { return geometry_; }
  [[nodiscard]] bool paused() const { return paused_.load(); }
  [[nodiscard]] float dt() const { return dt_; }
  [[nodiscard]] int thread_count() const { return thread_count_.load(); }

 private:
  void run();
  void apply_requests();  // on the simulation thread

  SceneFactory factory_;
  SceneChoice choice_;  // on the simulation thread; threads changes come through threads_requested_
  bench::Scene scene_;
  StaticGeometry geometry_;
  float dt_ = 1.0f / 60.0f;
  std::uint64_t steps_ = 0;
  std::atomic<bool> paused_{false}, stop_{false};
  std::atomic<float> speed_{1.0f};
  std::atomic<int> thread_count_{0};

  std::mutex mutex_;  // guards what follows
  std::condition_variable wake_;
  int single_steps_ = 0;
  bool reset_requested_ = false;
  int threads_requested_ = -1;
  std::optional<SceneChoice> choice_requested_;  // for the next reset
  bool material_requested_ = false;
  Capture capture_;  // what the frames carry
  bool capture_requested_ = false;
  float restitution_ = 0.5f, friction_ = 0.5f;
  std::vector<std::function<void(World&)>> edits_;  // spawn and fire, in the order asked
  Frame published_;
  std::uint64_t version_ = 0;       // raised on every publish
  std::uint64_t seen_version_ = 0;  // the last version latest() handed out

  std::thread thread_;  // last: started once everything above exists
};

}  // namespace hail::view
