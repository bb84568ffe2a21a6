#pragma once
// `hail-bench run --filters`: collision filters given to a built scene's spheres, to measure
// what filtering costs (accept-all: every sphere filtered, nothing rejected) and what it saves
// (teams: two teams that pass through each other) against the same scene without filters.

#include <string>
#include <vector>

#include "scenes/scenes.h"

namespace hail::bench {

enum class SceneFilters {
  None,       ///< the scene as built (every filter the default)
  AcceptAll,  ///< every sphere a non-default filter that still collides with everything
  Teams,      ///< spheres alternate between two teams that do not collide with each other
};

/// The --filters names, in the order `--filters compare` runs them.
const std::vector<std::string>& scene_filter_names();
SceneFilters scene_filters_named(const std::string& name);

/// Gives every sphere of `scene` (scene.ids, in the order added) the filter `filters` asks for.
void give_filters(Scene& scene, SceneFilters filters);

}  // namespace hail::bench
