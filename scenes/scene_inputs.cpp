#include "scenes/scene_inputs.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <system_error>

namespace hail::bench {

std::vector<std::string> scene_file_inputs(const std::string& scene_file) {
  if (scene_file.empty()) return {};
  std::vector<std::string> inputs{scene_file};
  std::error_code error;
  if (!std::filesystem::is_regular_file(scene_file, error)) return inputs;
  std::ifstream in(scene_file, std::ios::binary);
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false, /*ignore_comments=*/true);
  if (doc.is_object() && doc.contains("terrain") && doc["terrain"].is_object()) {
    const nlohmann::json& terrain = doc["terrain"];
    if (terrain.contains("heightmap") && terrain["heightmap"].is_string())
      inputs.push_back(
          (std::filesystem::path(scene_file).parent_path() / terrain["heightmap"].get<std::string>()).string());
  }
  return inputs;
}

}  // namespace hail::bench
