#pragma once
// What is drawn besides the scene itself, chosen on the command line (--colour, --draw-normals,
// --draw-bvh DEPTH, --draw-grid) or in the panel: how spheres are coloured, which debug lines
// are on, and so what the simulation thread must copy into each frame (Capture).

#include <array>
#include <string_view>

namespace hail::view {

/// How spheres are coloured.
enum class ColourMode {
  Speed,   ///< blue at rest through purple to red at the panel's "red at" speed (the default)
  Island,  ///< by island (island_labels): a hue from a hash of its label; immovable spheres grey
  Sleep,   ///< asleep grey-blue, awake by speed (WorldSettings::sleep: --sleep on|off, the panel's checkbox)
};
inline constexpr std::array<std::string_view, 3> kColourModeNames = {"speed", "island", "sleep"};

/// Which debug lines are on.
struct DebugDraw {
  bool normals = false;  ///< each contact's normal (Frame::contacts)
  int bvh_depth = -1;    ///< the terrain BVH's boxes at this depth (bvh_level); < 0: none
  bool grid = false;     ///< the pair grid's occupied cells (Frame::grid_cells)
  [[nodiscard]] bool any() const { return normals || bvh_depth >= 0 || grid; }
  friend bool operator==(const DebugDraw&, const DebugDraw&) = default;
};

/// What capture_frame copies besides the spheres and their sleep states: each costs O(spheres)
/// or O(contacts) a step, so only what is shown.
struct Capture {
  bool islands = false;   ///< Frame::island (island_labels)
  bool contacts = false;  ///< Frame::contacts
  bool grid = false;      ///< Frame::grid_cells
  friend bool operator==(const Capture&, const Capture&) = default;
};

/// What a frame must carry to be drawn with `colour` and `draw`.
[[nodiscard]] inline Capture capture_for(ColourMode colour, const DebugDraw& draw) {
  return {.islands = colour == ColourMode::Island, .contacts = draw.normals, .grid = draw.grid};
}

}  // namespace hail::view
