#pragma once
// Where hail-view's scene comes from: a built-in scene or a scene file (live), and for a
// recording the built-in scene it names or the scene file given with it, built again for its
// terrain and planes only.

#include <string>

#include "hail/recording.h"
#include "scenes/scenes.h"
#include "view/live_simulation.h"
#include "view/view_options.h"

namespace hail::view {

/// Builds the scene of `options` (--scene FILE.json, or the named built-in with --spheres).
SceneFactory scene_factory(const ViewOptions& options);

/// The scene drawn under a recording, for its terrain and planes (with as few spheres as it
/// can be built with): `scene_file` (--scene) where given, else the built-in scene the
/// recording names. The recorded name is data from the file, so it is only ever looked up
/// among the built-in scenes, never opened as a path (a FIFO would hang the viewer, /dev/zero
/// read without end). `note` says why the terrain is left out: the recorded scene is not
/// built in and no scene file was given, it cannot be built here, or its terrain's content
/// hash differs from the one recorded (the spheres are still drawn). A `scene_file` that
/// cannot be read or built is an error (std::invalid_argument naming it), as in a live run.
bench::Scene scene_of_recording(const RecordingHeader& header, const std::string& scene_file, std::string& note);

}  // namespace hail::view
