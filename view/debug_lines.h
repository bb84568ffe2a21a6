#pragma once
// The debug lines hail-view can draw over a scene (the panel's toggles, --draw-normals,
// --draw-bvh DEPTH, --draw-grid): each contact's normal, the terrain BVH's boxes at a depth,
// the pair grid's occupied cells. Built here as plain vertex lists (no OpenGL: hail-view-tests
// checks them); the renderer draws them as GL lines.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "hail/debug_draw.h"
#include "view/draw_choices.h"
#include "view/frame.h"

namespace hail::view {

using Rgb = std::array<float, 3>;

/// The lines' colours: pure hues no sphere, terrain or sky pixel has, so that a picture's
/// lines can be counted (the headless test counts the BVH's cyan).
inline constexpr Rgb kNormalYellow = {1.0f, 1.0f, 0.0f};
inline constexpr Rgb kBvhCyan = {0.0f, 1.0f, 1.0f};
inline constexpr Rgb kGridWhite = {1.0f, 1.0f, 1.0f};

/// Segments, two vertices each, a vertex x y z r g b.
struct LineList {
  std::vector<float> vertices;
  void add(const Vec3& a, const Vec3& b, const Rgb& colour);
  /// The 12 edges of the box.
  void add_box(const DebugBox& box, const Rgb& colour);
  [[nodiscard]] std::size_t segments() const { return vertices.size() / 12; }
  [[nodiscard]] bool empty() const { return vertices.empty(); }
  void clear() { vertices.clear(); }
};

/// The nodes of `nodes` (terrain_bvh_boxes, depth-first) drawn at `depth`: those at that depth,
/// and the leaves above it, so that the boxes cover the whole terrain at every depth.
[[nodiscard]] std::vector<DebugBox> bvh_level(std::span<const BvhNodeBox> nodes, int depth);

/// The lines drawn with the depth test (the BVH boxes and grid cells, which the terrain and
/// spheres hide) and those drawn over everything (contact normals, most inside a pile): each
/// contact's normal from its point on sphere a, one radius of a long, out of the surface it
/// meets (against the normal, so up from the ground).
struct DebugLines {
  LineList tested, overlay;
};
void build_debug_lines(const Frame& frame, std::span<const BvhNodeBox> terrain_bvh, const DebugDraw& draw,
                       DebugLines& out);

}  // namespace hail::view
