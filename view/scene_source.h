#pragma once
// Where hail-view's scene comes from: a built-in scene or a scene file (live), and for a
// recording the scene it names, built again for its terrain and planes only.

#include <string>

#include "bench/scenes/scenes.h"
#include "hail/recording.h"
#include "view/live_simulation.h"
#include "view/view_options.h"

namespace hail::view {

/// Builds the scene of `options` (--scene FILE.json, or the named built-in with --spheres).
SceneFactory scene_factory(const ViewOptions& options);

/// The scene a recording names, with one sphere, for its terrain and planes; `note` says why
/// the terrain is left out when it cannot be rebuilt or its content hash differs from the one
/// recorded (the spheres are still drawn).
bench::Scene scene_of_recording(const RecordingHeader& header, std::string& note);

}  // namespace hail::view
