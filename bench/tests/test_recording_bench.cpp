// hail-bench run --record FILE --every K --velocities: the recording names the scene and its
// terrain, lists the spheres in the order the scene added them, and its frames are the run's
// positions and velocities at steps 0, K, 2K, ...; --every without --record is refused.
#include <filesystem>
#include <string>
#include <vector>

#include "bench/run_command.h"
#include "tests/catch.h"
#include "hail/recording.h"
#include "hail/snapshot.h"
#include "scenes/scene_run.h"
#include "scenes/scenes.h"

namespace bench = hail::bench;

TEST_CASE("hail-bench run --record writes the run's frames", "[bench][recording]") {
  const auto dir = std::filesystem::temp_directory_path() / "hail-recording-bench";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "rain.hailrec").string();
  REQUIRE(bench::run_command({"terrain-rain", "--spheres", "200", "--steps", "20", "--threads", "1", "--quiet",
                              "--record", file, "--every", "10", "--velocities"}) == 0);
  const hail::RecordingReader reader = hail::RecordingReader::open_file(file);
  bench::SceneParams params;
  params.spheres = 200;
  params.threads = 1;
  bench::Scene scene = bench::find_scene("terrain-rain").build(params);
  const hail::RecordingHeader& h = reader.header();
  CHECK(h.scene == "terrain-rain");
  CHECK(h.has_terrain);
  CHECK(h.terrain_hash == hail::terrain_content_hash(*scene.world->terrain()));
  CHECK(h.every == 10);
  CHECK(h.dt == scene.dt);
  CHECK(h.handles == scene.ids);
  REQUIRE(reader.frame_count() == 3);
  for (int step = 0; step <= 20; ++step) {
    if (step > 0) scene.world->step(scene.dt);
    if (step % 10 != 0) continue;
    const hail::RecordingFrame frame = reader.frame(std::size_t(step / 10));
    CHECK(frame.step == std::uint64_t(step));
    const hail::Vec3 p = scene.world->position(scene.ids[17]), v = scene.world->velocity(scene.ids[17]);
    CHECK(frame.positions[3 * 17 + 1] == p.y());
    CHECK(frame.velocities[3 * 17 + 2] == v.z());
    CHECK(frame == hail::recording_frame(*scene.world, h, std::uint64_t(step)));
  }
  CHECK_THROWS_AS(bench::run_command({"terrain-rain", "--spheres", "200", "--steps", "5", "--every", "2"}),
                  std::invalid_argument);
  std::filesystem::remove_all(dir);
}
