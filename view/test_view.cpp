// hail-view's parts that need no OpenGL (hail-view-tests, ctest label "view"): the simulation
// thread hands over whole steps and its controls (pause, single step, reset, threads, spawn,
// fire) do what they say, a thread change carrying the run on bitwise; the frames carry the
// contacts, grid cells and islands of their own step when asked; the debug lines and island
// labels; the camera's cursor ray; a replay's frames and speeds; the command line, the checks of
// its picture paths, pictures written whole or not at all, and the scene drawn under a replay.

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <thread>

#include "hail/recording.h"
#include "hail/snapshot.h"
#include "scenes/metrics.h"
#include "scenes/scene_file.h"
#include "scenes/scene_run.h"
#include "tests/catch.h"
#include "view/camera.h"
#include "view/debug_lines.h"
#include "view/islands.h"
#include "view/live_simulation.h"
#include "view/png_file.h"
#include "view/replay.h"
#include "view/scene_source.h"
#include "view/stacked_plot.h"
#include "view/view_options.h"

using namespace hail;
using namespace hail::view;

namespace {

SceneFactory rain(std::size_t spheres) {
  return [spheres](const SceneChoice& c) {
    bench::SceneParams p;
    p.spheres = c.spheres.value_or(spheres);
    p.threads = c.threads;
    p.settings.pair_search = c.pair_search.value_or(p.settings.pair_search);
    return bench::find_scene("terrain-rain").build(p);
  };
}

/// Polls sim.latest until `done(frame)` (10 s at most).
template <class Done>
Frame wait_for(LiveSimulation& sim, Frame frame, Done done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!done(frame) && std::chrono::steady_clock::now() < until) {
    sim.latest(frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return frame;
}

/// The frame a plain run of the scene gives after `steps` steps, with its error figures.
Frame reference(std::size_t spheres, int threads, std::uint64_t steps) {
  bench::Scene scene = rain(spheres)({.threads = threads});
  for (std::uint64_t k = 0; k < steps; ++k) scene.world->step(scene.dt);
  Frame frame;
  capture_frame(*scene.world, 0.0, steps, frame);
  const bench::ErrorFigures errors = bench::measure_errors(scene);
  frame.deepest_overlap = std::max(errors.max_sphere_penetration, errors.max_terrain_penetration);
  frame.tunnelled = errors.tunnelled;
  return frame;
}

/// parse_view_options on hail-view and `words`.
std::optional<ViewOptions> parse(std::vector<std::string> words) {
  words.insert(words.begin(), "hail-view");
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  return parse_view_options(int(argv.size()), argv.data());
}

/// A folder of its own under the temporary directory, removed with what it holds.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  [[nodiscard]] std::string file(const std::string& name, const std::string& content = "") const {
    const std::string p = (path / name).string();
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }
};

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// check_view_paths's refusal of the command line `words`, or "" where it accepts them.
std::string path_refusal(const std::vector<std::string>& words) {
  const std::optional<ViewOptions> o = parse(words);
  REQUIRE(o);
  try {
    check_view_paths(*o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

/// What scene_of_recording gave, shared with the thread that ran it.
struct SceneForReplay {
  bench::Scene scene;
  std::string note;
};

/// scene_of_recording(header, scene_file) on a thread of its own, waited for `limit`: null if it
/// has not returned by then. The thread is detached rather than joined (as std::async's future
/// would on destruction), so that a viewer that opens a FIFO fails the test instead of hanging it.
std::shared_ptr<SceneForReplay> scene_of_recording_within(std::chrono::seconds limit, const RecordingHeader& header,
                                                          const std::string& scene_file = "") {
  auto result = std::make_shared<SceneForReplay>();
  auto finished = std::make_shared<std::promise<void>>();
  std::future<void> done = finished->get_future();
  std::thread([result, finished, header, scene_file] {
    try {
      result->scene = scene_of_recording(header, scene_file, result->note);
      finished->set_value();
    } catch (...) {
      finished->set_exception(std::current_exception());
    }
  }).detach();
  if (done.wait_for(limit) != std::future_status::ready) return nullptr;
  done.get();  // rethrows what it threw
  return result;
}

/// A scene file on terrain-rain's terrain with one listed sphere: a list cannot be resized to
/// one sphere, so the viewer builds it whole.
constexpr const char* kSceneWithTerrain = R"({
  "format": "hail-scene", "version": 1, "dt": 0.0166666675,
  "terrain": {"function": "terrain-rain", "size": [64, 64], "cell_size": 1.0},
  "material": {"radius": 1.0, "mass": 1.0},
  "spheres": [{"list": [{"position": [30, 20, 30]}]}]
})";

/// The state before the first step of a simulation made paused.
Frame first_frame(LiveSimulation& sim) {
  Frame frame;
  REQUIRE(sim.latest(frame));
  REQUIRE(frame.step == 0);
  return frame;
}

}  // namespace

TEST_CASE("The live simulation steps whole steps, and single steps, resets and thread changes keep the run", "[view]") {
  LiveSimulation sim(rain(300), {.threads = 1}, /*paused=*/true);
  sim.set_speed(100.0f);  // as fast as it goes
  Frame frame = first_frame(sim);
  sim.set_paused(false);  // runs a while ...
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step >= 5; });
  sim.set_paused(true);              // ... and stops at a step of its own choosing:
  for (int quiet = 0; quiet < 3;) {  // the last one published (none new for 3 x 100 ms)
    quiet = sim.latest(frame) ? 0 : quiet + 1;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::uint64_t stopped = frame.step;
  CHECK(frame.centre == reference(300, 1, stopped).centre);  // a whole step, the plain run's

  sim.set_threads(2);
  // Single steps to step 240 at least, where spheres lie on the ground and each other.
  const std::uint64_t target = std::max<std::uint64_t>(stopped + 10, 240);
  for (std::uint64_t k = stopped; k < target; ++k) sim.step_once();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == target; });
  REQUIRE(frame.step == target);
  CHECK(sim.thread_count() == 2);
  const Frame plain = reference(300, 1, target);
  CHECK(frame.centre == plain.centre);                    // bitwise, across the thread change
  CHECK(frame.deepest_overlap > 0.0);                     // (spheres in contact, so the figure can tell steps apart)
  CHECK(frame.deepest_overlap == plain.deepest_overlap);  // the error figures of that step
  CHECK(frame.tunnelled == plain.tunnelled);

  sim.reset();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == 0; });
  CHECK(frame.step == 0);
  CHECK(frame.centre == reference(300, 2, 0).centre);
}

TEST_CASE("Spawning drops a block of spheres where the ray meets the terrain; firing adds one fast sphere", "[view]") {
  LiveSimulation sim(rain(100), {.threads = 1}, /*paused=*/true);
  Frame frame = first_frame(sim);
  const std::size_t n = frame.size();
  sim.spawn_at(Vec3(0.0f, 200.0f, 0.0f), Vec3(0.0f, -1.0f, 0.0f));
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.size() == n + 27; });
  REQUIRE(frame.size() == n + 27);
  const float ground = bench::terrain_rain_height(0.0f, 0.0f);
  for (std::size_t k = n; k < n + 27; ++k) {
    CHECK(std::abs(frame.centre[3 * k]) < 3.0f);
    CHECK(frame.centre[3 * k + 1] > ground);
  }
  sim.spawn_at(Vec3(0.0f, 200.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f));  // up: meets nothing
  sim.fire(Vec3(0.0f, 40.0f, 0.0f), Vec3(1.0f, -1.0f, 0.0f), 80.0f);
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.size() == n + 28; });
  REQUIRE(frame.size() == n + 28);
  CHECK(frame.speed.back() == Approx(80.0f));

  sim.choose_for_reset(60, PairSearch::Grid, false);  // taken at the reset, not before
  const std::uint64_t at = frame.step;
  sim.step_once();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == at + 1; });
  REQUIRE(frame.step == at + 1);
  CHECK(frame.size() == n + 28);
  sim.reset();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == 0; });
  CHECK(frame.size() == 60);
}

TEST_CASE("The camera's ray through the middle of the view points at its target", "[view]") {
  OrbitCamera camera;
  camera.target = Eigen::Vector3f(3.0f, 1.0f, -2.0f);
  camera.distance = 25.0f;
  const auto [origin, direction] = camera.ray_through(400.0, 300.0, 800, 600);
  const Eigen::Vector3f towards = (camera.target - camera.eye()).normalized();
  CHECK(direction.dot(towards) == Approx(1.0f).margin(1e-5));
  CHECK((origin - camera.eye()).norm() < 0.1f);
  const auto [left_origin, left] = camera.ray_through(0.0, 300.0, 800, 600);
  const Eigen::Vector3f right_axis = camera.view().block<1, 3>(0, 0).transpose();
  CHECK(left.dot(right_axis) < -0.1f);  // the left edge of the view looks left
}

TEST_CASE("A replay shows the recorded positions, with speeds from velocities or frame differences", "[view]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-view-test";
  std::filesystem::create_directories(dir);
  World world(WorldSettings{.threads = 1});
  world.add_sphere({.position = {0, 0, 0}, .velocity = {3, 0, 4}, .radius = 0.5f});
  world.set_gravity_scale(world.handles()[0], 0.0f);
  for (const bool velocities : {false, true}) {
    const auto path = dir / (velocities ? "v.hailrec" : "p.hailrec");
    {
      std::ofstream file(path, std::ios::binary);
      RecordingWriter writer(file, recording_header(world, {}, "one", 0.5f, 2, velocities));
      writer.write_frame(recording_frame(world, writer.header(), 0));
      RecordingFrame moved = recording_frame(world, writer.header(), 2);
      moved.positions = {3.0f, 0.0f, 4.0f};  // 5 m in 2 steps of 0.5 s: 5 m/s
      writer.write_frame(moved);
      writer.finish();
    }
    Replay replay(path.string());
    Frame frame;
    replay.load(1, frame);
    CHECK(frame.step == 2);
    CHECK(frame.centre == std::vector<float>{3.0f, 0.0f, 4.0f});
    CHECK(frame.radius == std::vector<float>{0.5f});
    CHECK(frame.speed[0] == Approx(5.0f));
    replay.load(0, frame);
    CHECK(frame.speed[0] == Approx(velocities ? 5.0f : 0.0f));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("Asked, the frames carry the contacts, grid cells and islands of their own step, also while paused",
          "[view]") {
  // 1,200 spheres: the automatic pair search is the grid.
  LiveSimulation sim(rain(1200), {.threads = 1}, /*paused=*/true);
  Frame frame = first_frame(sim);
  CHECK(frame.contacts.empty());
  const Capture all{.islands = true, .contacts = true, .grid = true};
  sim.set_capture(all);
  constexpr std::uint64_t kSteps = 150;
  for (std::uint64_t k = 0; k < kSteps; ++k) sim.step_once();
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.step == kSteps; });
  REQUIRE(frame.step == kSteps);
  bench::Scene scene = rain(1200)({.threads = 1});
  for (std::uint64_t k = 0; k < kSteps; ++k) scene.world->step(scene.dt);
  Frame plain;
  capture_frame(*scene.world, 0.0, kSteps, plain, all);
  REQUIRE(!plain.contacts.empty());
  REQUIRE(!plain.grid_cells.empty());
  CHECK(frame.contacts == plain.contacts);  // those of the step shown, bitwise
  CHECK(frame.grid_cells.size() == plain.grid_cells.size());
  CHECK(frame.island == plain.island);
  REQUIRE(frame.island.size() == frame.size());
  // Spheres on the ground touch others: some island has more than one sphere.
  std::vector<std::uint32_t> labels = frame.island;
  std::sort(labels.begin(), labels.end());
  CHECK(std::adjacent_find(labels.begin(), labels.end()) != labels.end());
  // Each contact's point lies on the surface of a sphere of the frame, one radius from its centre.
  const Vec3 point(frame.contacts[0], frame.contacts[1], frame.contacts[2]);
  const Vec3 normal(frame.contacts[3], frame.contacts[4], frame.contacts[5]);
  CHECK(normal.norm() == Approx(1.0f).margin(1e-4));
  const Vec3 centre = point - frame.contacts[6] * normal;
  bool found = false;
  for (std::size_t k = 0; k < frame.size() && !found; ++k)
    found = (Vec3(frame.centre[3 * k], frame.centre[3 * k + 1], frame.centre[3 * k + 2]) - centre).norm() < 1e-4f;
  CHECK(found);

  sim.set_capture({});  // shown at once, though paused: the same step without them
  frame = wait_for(sim, frame, [&](const Frame& f) { return f.contacts.empty(); });
  CHECK(frame.step == kSteps);
  CHECK(frame.contacts.empty());
  CHECK(frame.grid_cells.empty());
  CHECK(frame.island.empty());
}

TEST_CASE("Debug lines: 12 edges a box, the BVH level's nodes and the leaves above, normals out of the surface",
          "[view]") {
  LineList list;
  list.add_box({.min = Vec3(0, 0, 0), .max = Vec3(1, 2, 3)}, kBvhCyan);
  REQUIRE(list.segments() == 12);
  float length = 0.0f;
  for (std::size_t k = 0; k < 12; ++k) {
    const float* v = &list.vertices[12 * k];
    const Vec3 a(v[0], v[1], v[2]), b(v[6], v[7], v[8]);
    CHECK((a - b).cwiseAbs().minCoeff() == 0.0f);  // along one axis
    length += (a - b).norm();
    CHECK(v[3] == 0.0f);  // cyan
    CHECK(v[4] == 1.0f);
  }
  CHECK(length == Approx(4.0f * (1 + 2 + 3)));

  // root (inner) -> a leaf, and an inner node -> two leaves.
  const DebugBox box;
  const std::vector<BvhNodeBox> nodes = {{.box = box, .depth = 0},
                                         {.box = box, .depth = 1, .leaf = true},
                                         {.box = box, .depth = 1},
                                         {.box = box, .depth = 2, .leaf = true},
                                         {.box = box, .depth = 2, .leaf = true}};
  CHECK(bvh_level(nodes, -1).empty());
  CHECK(bvh_level(nodes, 0).size() == 1);
  CHECK(bvh_level(nodes, 1).size() == 2);
  CHECK(bvh_level(nodes, 2).size() == 3);  // the leaf at depth 1 and the two at 2
  CHECK(bvh_level(nodes, 9).size() == 3);

  Frame frame;
  frame.contacts = {1.0f, 0.0f, 2.0f, 0.0f, -1.0f, 0.0f, 0.5f};  // a sphere of radius 0.5 on the ground
  frame.grid_cells = {{.min = Vec3(0, 0, 0), .max = Vec3(2, 2, 2)}};
  DebugLines lines;
  build_debug_lines(frame, nodes, {}, lines);
  CHECK(lines.tested.empty());
  CHECK(lines.overlay.empty());
  build_debug_lines(frame, nodes, {.normals = true, .bvh_depth = 1, .grid = true}, lines);
  CHECK(lines.tested.segments() == 12 * (2 + 1));
  REQUIRE(lines.overlay.segments() == 1);
  const std::vector<float> up = {1.0f, 0.0f, 2.0f, 1.0f, 1.0f, 0.0f, 1.0f, 0.5f, 2.0f, 1.0f, 1.0f, 0.0f};
  CHECK(lines.overlay.vertices == up);  // from the point, a radius up, yellow
}

TEST_CASE("Island labels: the smallest handle index of spheres in contact, kept asleep; immovable spheres in none",
          "[view]") {
  WorldSettings settings;
  settings.threads = 1;
  settings.gravity = Vec3(0.0f, 0.0f, 0.0f);
  settings.sleep = true;
  settings.sleep_time = 0.1f;
  World world(settings);
  // Two pairs just touching (overlap below the depenetration slop: nothing moves), one alone,
  // one static sphere touching the last pair.
  const float touching = 2.0f * 0.5f - 0.001f;
  world.add_sphere({.position = Vec3(0, 0, 0), .radius = 0.5f});                             // 0
  world.add_sphere({.position = Vec3(touching, 0, 0), .radius = 0.5f});                      // 1: with 0
  world.add_sphere({.position = Vec3(20, 0, 0), .radius = 0.5f});                            // 2: alone
  world.add_sphere({.position = Vec3(40, 0, 0), .radius = 0.5f});                            // 3
  world.add_sphere({.position = Vec3(40 + touching, 0, 0), .radius = 0.5f});                 // 4: with 3
  world.add_sphere({.position = Vec3(40, touching, 0), .radius = 0.5f, .is_static = true});  // 5
  // An island sleeps only where it is supported (kernel/world/sleep_islands.h): a static sphere
  // under the first pair too.
  world.add_sphere({.position = Vec3(0, -touching, 0), .radius = 0.5f, .is_static = true});  // 6
  world.step(1.0f / 60.0f);
  std::vector<std::uint32_t> labels;
  island_labels(world, labels);
  const auto label_of = [&](std::uint32_t index) { return labels[std::size_t(world.soa().slot_of_index(index))]; };
  CHECK(label_of(0) == 0);
  CHECK(label_of(1) == 0);
  CHECK(label_of(2) == 2);
  CHECK(label_of(3) == 3);
  CHECK(label_of(4) == 3);  // the static sphere joins them to nothing
  CHECK(label_of(5) == kNoIsland);
  std::vector<std::uint32_t> awake_labels(6);
  for (std::uint32_t i = 0; i < 6; ++i) awake_labels[i] = label_of(i);
  for (int k = 0; k < 30; ++k) world.step(1.0f / 60.0f);  // 0.5 s at rest: asleep
  const auto slot = [&](std::uint32_t index) { return std::size_t(world.soa().slot_of_index(index)); };
  REQUIRE(world.is_sleeping(world.id_at(slot(0))));
  REQUIRE(world.is_sleeping(world.id_at(slot(4))));
  island_labels(world, labels);
  for (std::uint32_t i = 0; i < 6; ++i) CHECK(labels[slot(i)] == awake_labels[i]);  // SphereSoA::sleep_island
  Frame frame;
  capture_frame(world, 0.0, 31, frame);
  CHECK(frame.sleeping[slot(0)] == 1);

  const auto c0 = island_colour(0), c1 = island_colour(1), c2 = island_colour(2);
  CHECK(c0 != c1);
  CHECK(c1 != c2);
  CHECK(island_colour(kNoIsland) == std::array<float, 3>{0.5f, 0.5f, 0.5f});
}

TEST_CASE("The phase plot stacks each step's phases: a column's bands end where the next begins, its top the sum",
          "[view]") {
  const std::vector<std::vector<float>> phases = {{1.0f, 2.0f}, {0.5f, -1.0f}, {0.25f, 3.0f}};
  const std::vector<float> tops = stack_series(phases);
  REQUIRE(tops.size() == 2 * 4);
  CHECK(tops == std::vector<float>{0.0f, 1.0f, 1.5f, 1.75f, 0.0f, 2.0f, 2.0f, 5.0f});  // a negative time counts as 0
  CHECK(stack_series({}).empty());
}

TEST_CASE("The command line's colour mode, debug lines, sleeping and zoom", "[view]") {
  const std::optional<ViewOptions> plain = parse({});
  REQUIRE(plain);
  CHECK(plain->colour == ColourMode::Speed);
  CHECK_FALSE(plain->draw.any());
  CHECK_FALSE(plain->sleep);  // the scene's own (on by default)
  const std::optional<ViewOptions> o = parse(
      {"--colour", "island", "--draw-bvh", "3", "--draw-normals", "--draw-grid", "--sleep", "off", "--zoom", "2.5"});
  REQUIRE(o);
  CHECK(o->colour == ColourMode::Island);
  CHECK(o->draw == DebugDraw{.normals = true, .bvh_depth = 3, .grid = true});
  CHECK(capture_for(o->colour, o->draw) == Capture{.islands = true, .contacts = true, .grid = true});
  CHECK(o->sleep == false);
  CHECK(o->zoom == 2.5f);
  CHECK_FALSE(o->continuous_collision);
  CHECK(parse({"--ccd", "off"})->continuous_collision == false);
  CHECK(parse({"--ccd", "on"})->continuous_collision == true);
  CHECK(parse({"--colour", "sleep"})->colour == ColourMode::Sleep);
  CHECK_THROWS_AS(parse({"--colour", "mass"}), std::invalid_argument);
  CHECK_THROWS_AS(parse({"--draw-bvh", "-1"}), std::invalid_argument);
}

TEST_CASE("A picture is refused before the run where it would overwrite an input or cannot be written", "[view]") {
  const TempDir dir("hail-view-paths");
  const std::string recording = dir.file("run.hailrec", "recorded");
  const std::string scene = dir.file("scene.json", "{}");
  const std::string picture = (dir.path / "out.png").string();

  CHECK(path_refusal({"--replay", recording, "--headless", "--screenshot", recording}).find(recording) !=
        std::string::npos);
  CHECK(path_refusal({"--scene", scene, "--headless", "--screenshot", scene}).find(scene) != std::string::npos);
  CHECK_FALSE(
      path_refusal({"--replay", recording, "--headless", "--screenshot", (dir.path / "." / "run.hailrec").string()})
          .empty());  // the same file by another name
  CHECK_FALSE(path_refusal({"--replay", recording, "--scene", scene, "--headless", "--screenshot", scene}).empty());
  // The heightmap a scene file names is an input too (a PNG heightmap is a picture's name).
  const std::string map = dir.file("map.png", "heights");
  const std::string mapped = dir.file("mapped.json", R"({"terrain": {"heightmap": "map.png"}})");
  CHECK(path_refusal({"--scene", mapped, "--headless", "--screenshot", map}).find("map.png") != std::string::npos);
  CHECK(contents(map) == "heights");
  CHECK(contents(recording) == "recorded");  // nothing was written
  CHECK(contents(scene) == "{}");
  CHECK_FALSE(path_refusal({"--headless", "--screenshot", (dir.path / "no-such-folder" / "out.png").string()}).empty());
  CHECK(path_refusal({"--replay", recording, "--scene", scene, "--headless", "--screenshot", picture}).empty());
  CHECK_FALSE(std::filesystem::exists(picture));  // checked, not written

  // --frames DIR: the folder is made; an input lying there under a picture's name is refused,
  // as is a folder that is an input.
  const std::string frames = (dir.path / "frames").string();
  CHECK(path_refusal({"--replay", recording, "--headless", "--frames", frames}).empty());
  CHECK(std::filesystem::is_directory(frames));
  const std::string in_frames = (dir.path / "frames" / "frame-000002.png").string();
  std::filesystem::copy_file(recording, in_frames);
  CHECK(path_refusal({"--replay", in_frames, "--headless", "--frames", frames}).find(in_frames) != std::string::npos);
  CHECK(contents(in_frames) == "recorded");
  CHECK_FALSE(path_refusal({"--replay", recording, "--headless", "--frames", recording}).empty());
  CHECK(frame_picture_path(frames, 12) == (dir.path / "frames" / "frame-000012.png").string());
}

TEST_CASE("A picture is written whole or not at all: a failed write is an error naming the path", "[view]") {
  const TempDir dir("hail-view-png");
  const std::vector<unsigned char> rgb(64 * 64 * 3, 200);
  const std::string picture = (dir.path / "picture.png").string();
  write_png(picture, 64, 64, rgb);
  CHECK(contents(picture).substr(0, 4) == "\x89PNG");
  const std::string first = contents(picture);

  const std::string missing = (dir.path / "no-such-folder" / "picture.png").string();
  CHECK_THROWS_AS(write_png(missing, 64, 64, rgb), std::runtime_error);
  if (std::filesystem::exists("/dev/full")) {  // a full disk: the write fails, and says so
    std::string message;
    try {
      write_png("/dev/full", 64, 64, rgb);
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    CHECK(message.find("/dev/full") != std::string::npos);
  }
  write_png(picture, 64, 64, std::vector<unsigned char>(64 * 64 * 3, 10));  // replaced whole
  CHECK(contents(picture).substr(0, 4) == "\x89PNG");
  CHECK(contents(picture) != first);
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path)) ++files;
  CHECK(files == 1);  // no temporary left behind
}

TEST_CASE("A recording's scene name is looked up among the built-in scenes only, never opened as a path", "[view]") {
  const TempDir dir("hail-view-recorded-scene");
  const std::string fifo = (dir.path / "scene.fifo").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string scene_file = dir.file("scene.json", kSceneWithTerrain);
  for (const std::string& name : {fifo, std::string("/dev/zero"), scene_file}) {
    RecordingHeader header;
    header.scene = name;
    header.has_terrain = true;
    header.dt = 1.0f / 60.0f;
    const auto drawn = scene_of_recording_within(std::chrono::seconds(5), header);
    INFO("the recorded scene " << name);
    REQUIRE(drawn);                                           // returned at once: the name was not opened
    CHECK(drawn->scene.world->terrain() == nullptr);          // spheres only ...
    CHECK(drawn->note.find("--scene") != std::string::npos);  // ... and the way to the terrain
  }
}

TEST_CASE("--replay with --scene draws that scene file's terrain, checked by its content hash", "[view]") {
  const TempDir dir("hail-view-replay-scene");
  const std::string scene_file = dir.file("scene.json", kSceneWithTerrain);
  const std::string recording = dir.file("run.hailrec", "recorded");
  const std::optional<ViewOptions> o = parse({"--replay", recording, "--scene", scene_file});
  REQUIRE(o);  // accepted together
  CHECK(o->replay_path == recording);
  CHECK(o->scene_file == scene_file);

  const bench::Scene whole = bench::load_scene_file(scene_file);
  REQUIRE(whole.world->terrain());
  RecordingHeader header;
  header.scene = scene_file;
  header.has_terrain = true;
  header.terrain_hash = terrain_content_hash(*whole.world->terrain());
  header.dt = 1.0f / 60.0f;
  std::string note;
  bench::Scene drawn = scene_of_recording(header, scene_file, note);
  CHECK(drawn.world->terrain() != nullptr);
  CHECK(note.empty());

  header.terrain_hash += 1;  // another terrain was recorded: not drawn, and the note says why
  drawn = scene_of_recording(header, scene_file, note);
  CHECK(drawn.world->terrain() == nullptr);
  CHECK(note.find("content hash") != std::string::npos);

  // A built-in scene needs no --scene.
  header.scene = "terrain-rain";
  bench::SceneParams one;
  one.spheres = 1;
  one.threads = 1;
  header.terrain_hash = terrain_content_hash(*bench::find_scene("terrain-rain").build(one).world->terrain());
  note.clear();
  drawn = scene_of_recording(header, "", note);
  CHECK(drawn.world->terrain() != nullptr);
  CHECK(note.empty());
}
