#include "scenes/scene_filters.h"

#include <stdexcept>

namespace hail::bench {

const std::vector<std::string>& scene_filter_names() {
  static const std::vector<std::string> names{"none", "accept-all", "teams"};
  return names;
}

SceneFilters scene_filters_named(const std::string& name) {
  if (name == "accept-all") return SceneFilters::AcceptAll;
  if (name == "teams") return SceneFilters::Teams;
  if (name == "none") return SceneFilters::None;
  throw std::invalid_argument("--filters must be none, accept-all, teams or compare, got '" + name + "'");
}

void give_filters(Scene& scene, SceneFilters filters) {
  if (filters == SceneFilters::None) return;
  constexpr std::uint32_t kTeamBits[2] = {0x2u, 0x4u};
  for (std::size_t k = 0; k < scene.ids.size(); ++k) {
    const std::uint32_t team = kTeamBits[k % 2], other = kTeamBits[1 - k % 2];
    // Neither is the default (category 1), so the world takes its filtered path either way.
    const CollisionFilter filter =
        filters == SceneFilters::Teams ? CollisionFilter{team, ~other} : CollisionFilter{team, kAllCategories};
    scene.world->set_collision_filter(scene.ids[k], filter);
  }
}

}  // namespace hail::bench
