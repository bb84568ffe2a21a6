#pragma once
// Draws a Frame: spheres instanced (one unit-sphere mesh, a centre, radius and speed per
// instance), lit by one directional light and coloured by speed from blue (still) through
// purple to red (max_speed and over); the terrain as a shaded mesh (green), planes as large
// grey quads. Colours are chosen so that a picture's pixels tell what they show (the headless
// test counts them): spheres have less green than red or blue, the terrain more green than
// either, the sky is grey.

#include <epoxy/gl.h>

#include <Eigen/Core>
#include <span>
#include <vector>

#include "hail/heightmap.h"
#include "hail/plane.h"
#include "view/camera.h"
#include "view/frame.h"

namespace hail::view {

inline constexpr float kSkyGrey[3] = {0.13f, 0.14f, 0.15f};

class Renderer {
 public:
  /// Needs a current OpenGL 3.3 core context; builds the terrain mesh (every vertex up to
  /// about a million, else every k-th) and the plane quads around `centre`.
  Renderer(const Heightmap* terrain, std::span<const Plane> planes, const Eigen::Vector3f& centre, float extent);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Uploads the frame's spheres (when `changed`) and draws everything into the bound framebuffer.
  void draw(const Frame& frame, bool changed, const OrbitCamera& camera, int width, int height);

  float max_speed = 10.0f;  ///< m/s drawn red

 private:
  void build_sphere_mesh(int subdivisions);
  void build_static_mesh(const Heightmap* terrain, std::span<const Plane> planes, const Eigen::Vector3f& centre,
                         float extent);

  GLuint sphere_program_ = 0, mesh_program_ = 0;
  GLuint sphere_vao_ = 0, sphere_vertices_ = 0, sphere_indices_ = 0, instances_ = 0;
  GLsizei sphere_index_count_ = 0;
  std::size_t instance_capacity_ = 0, instance_count_ = 0;
  std::vector<float> instance_data_;  // centre x y z, radius, speed per sphere
  GLuint mesh_vao_ = 0, mesh_vertices_ = 0, mesh_indices_ = 0;
  GLsizei terrain_index_count_ = 0, plane_index_count_ = 0;
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
