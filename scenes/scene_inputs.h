#pragma once
// The files a scene file reads, for the commands that must never write over them (hail-bench
// run's outputs, hail-view's pictures: output_file.h's check_output_paths).

#include <string>
#include <vector>

namespace hail::bench {

/// The scene file itself and, where it names one, its heightmap (relative to its folder). A
/// file that does not parse, or is no regular file (a FIFO would block here, /dev/zero never
/// end), gives itself alone: the scene loader reports it.
[[nodiscard]] std::vector<std::string> scene_file_inputs(const std::string& scene_file);

}  // namespace hail::bench
