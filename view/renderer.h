#pragma once
// Draws a Frame: spheres instanced (one unit-sphere mesh, a centre, radius, speed and colour per
// instance), lit by one directional light and coloured by speed from blue (still) through
// purple to red (max_speed and over), or by island or sleep state (colour_mode); the terrain as a shaded mesh (green), planes as large
// grey quads. Colours are chosen so that a picture's pixels tell what they show (the headless
// test counts them): spheres have less green than red or blue, the terrain more green than
// either, the sky is grey. Debug lines (debug_lines.h) are unlit, in pure hues.

#include <epoxy/gl.h>

#include <Eigen/Core>
#include <span>
#include <vector>

#include "hail/heightmap.h"
#include "hail/plane.h"
#include "hail/terrain.h"
#include "view/camera.h"
#include "view/debug_lines.h"
#include "view/draw_choices.h"
#include "view/frame.h"

namespace hail::view {

inline constexpr float kSkyGrey[3] = {0.13f, 0.14f, 0.15f};

class Renderer {
 public:
  /// Needs a current OpenGL 3.3 core context; builds the terrain mesh (every vertex up to
  /// about a million, else every k-th) and the plane quads around `centre`.
  Renderer(const Heightmap* terrain, std::span<const Plane> planes, std::span<const TerrainTriangle> meshes,
           const Eigen::Vector3f& centre, float extent);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Uploads the frame's spheres (when `changed` or the colour mode changed) and draws
  /// everything into the bound framebuffer, and the debug lines over it when given.
  void draw(const Frame& frame, bool changed, const OrbitCamera& camera, int width, int height,
            const DebugLines* lines = nullptr);

  float max_speed = 10.0f;  ///< m/s drawn red
  /// How spheres are coloured; Island needs Frame::island, else they are drawn by speed.
  ColourMode colour_mode = ColourMode::Speed;

 private:
  void build_sphere_mesh(int subdivisions);
  void build_static_mesh(const Heightmap* terrain, std::span<const Plane> planes,
                         std::span<const TerrainTriangle> meshes, const Eigen::Vector3f& centre, float extent);
  void draw_lines(const LineList& lines);  // line program and uniforms set

  GLuint sphere_program_ = 0, mesh_program_ = 0;
  GLuint sphere_vao_ = 0, sphere_vertices_ = 0, sphere_indices_ = 0, instances_ = 0;
  GLsizei sphere_index_count_ = 0;
  std::size_t instance_capacity_ = 0, instance_count_ = 0;
  std::vector<float> instance_data_;  // centre x y z, radius, speed, own colour r g b a per sphere
  ColourMode uploaded_mode_ = ColourMode::Speed;
  GLuint line_program_ = 0, line_vao_ = 0, line_vertices_ = 0;
  GLuint mesh_vao_ = 0, mesh_vertices_ = 0, mesh_indices_ = 0;
  GLsizei terrain_index_count_ = 0, plane_index_count_ = 0, mesh_index_count_ = 0;
};

/// An offscreen colour + depth framebuffer of a fixed size (headless pictures).
class OffscreenTarget {
 public:
  OffscreenTarget(int width, int height);
  ~OffscreenTarget();
  void bind() const;
  /// The pixels, RGB, top row first.
  [[nodiscard]] std::vector<unsigned char> read_rgb() const;

 private:
  int width_, height_;
  GLuint framebuffer_ = 0, colour_ = 0, depth_ = 0;
};

}  // namespace hail::view
