#pragma once
// `hail-bench compare <scene>`: hail and Bullet on the identical scene in one process run,
// repetitions alternating, one table of ms/step and error figures side by side.

#include <string>
#include <vector>

namespace hail::bench {

/// Parses the options after `compare`; returns the process exit code.
int compare_command(const std::vector<std::string>& args);

}  // namespace hail::bench
