#include "view/renderer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include "view/gl_program.h"
#include "view/islands.h"

namespace hail::view {
namespace {

constexpr const char* kSphereVertex = R"(#version 330 core
layout(location = 0) in vec3 unit;          // a unit-sphere vertex, also its normal
layout(location = 1) in vec4 centre_radius; // per instance
layout(location = 2) in float speed;        // per instance
layout(location = 3) in vec4 own_colour;    // per instance: rgb, and a = 1 to use it (else by speed)
uniform mat4 view_projection;
uniform float max_speed;
out vec3 normal;
out vec3 colour;
void main() {
  normal = unit;
  float t = clamp(speed / max_speed, 0.0, 1.0);
  colour = own_colour.a > 0.5 ? own_colour.rgb : mix(vec3(0.15, 0.35, 1.0), vec3(1.0, 0.2, 0.1), t);
  gl_Position = view_projection * vec4(centre_radius.xyz + centre_radius.w * unit, 1.0);
}
)";

constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 vertex_normal;
uniform mat4 view_projection;
uniform vec3 base_colour;
out vec3 normal;
out vec3 colour;
void main() {
  normal = vertex_normal;
  colour = base_colour;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

// Debug lines: their own colour, unlit.
constexpr const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 line_colour;
uniform mat4 view_projection;
out vec3 colour;
void main() {
  colour = line_colour;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

constexpr const char* kLineFragment = R"(#version 330 core
in vec3 colour;
out vec4 pixel;
void main() { pixel = vec4(colour, 1.0); }
)";

// Lambert with an ambient floor: brightness changes, the hue (which channel leads) does not.
constexpr const char* kLitFragment = R"(#version 330 core
in vec3 normal;
in vec3 colour;
out vec4 pixel;
uniform float light_back_faces;  // 1: a back face is lit by its own side's normal (meshes)
void main() {
  vec3 light = normalize(vec3(0.4, 1.0, 0.3));
  vec3 n = normalize(normal);
  if (light_back_faces > 0.5 && !gl_FrontFacing) n = -n;
  float lambert = max(dot(n, light), 0.0);
  pixel = vec4(colour * (0.35 + 0.65 * lambert), 1.0);
}
)";

const Eigen::Vector3f kTerrainGreen(0.36f, 0.58f, 0.26f);
const Eigen::Vector3f kPlaneGrey(0.55f, 0.55f, 0.57f);
const Eigen::Vector3f kMeshSand(0.72f, 0.62f, 0.45f);
/// Asleep, in ColourMode::Sleep: grey with a little blue, darker than any speed's colour.
constexpr std::array<float, 3> kAsleepGrey = {0.42f, 0.45f, 0.55f};
constexpr std::size_t kInstanceFloats = 9;  // centre x y z, radius, speed, own colour r g b a

/// An icosahedron split `subdivisions` times, on the unit sphere.
void icosphere(int subdivisions, std::vector<float>& vertices, std::vector<unsigned>& indices) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<Eigen::Vector3f> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<unsigned> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                             6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<unsigned, unsigned>, unsigned> middle;
    auto mid = [&](unsigned a, unsigned b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = middle.try_emplace(key, static_cast<unsigned>(v.size()));
      if (added) v.push_back((v[a] + v[b]).normalized());
      return it->second;
    };
    std::vector<unsigned> g;
    for (std::size_t k = 0; k < f.size(); k += 3) {
      const unsigned a = f[k], b = f[k + 1], c = f[k + 2], ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(g);
  }
  for (const auto& p : v) vertices.insert(vertices.end(), {p.x(), p.y(), p.z()});
  indices = std::move(f);
}

/// A new buffer bound to `target` (an index buffer so joins the bound vertex array) holding `data`.
template <class T>
GLuint static_buffer(GLenum target, const std::vector<T>& data) {
  GLuint buffer = 0;
  glGenBuffers(1, &buffer);
  glBindBuffer(target, buffer);
  glBufferData(target, GLsizeiptr(data.size() * sizeof(T)), data.data(), GL_STATIC_DRAW);
  return buffer;
}

}  // namespace

Renderer::Renderer(const Heightmap* terrain, std::span<const Plane> planes, std::span<const TerrainTriangle> meshes,
                   const Eigen::Vector3f& centre, float extent) {
  sphere_program_ = link_program(kSphereVertex, kLitFragment);
  mesh_program_ = link_program(kMeshVertex, kLitFragment);
  line_program_ = link_program(kLineVertex, kLineFragment);
  build_sphere_mesh(2);
  glGenVertexArrays(1, &line_vao_);
  glBindVertexArray(line_vao_);
  glGenBuffers(1, &line_vertices_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vertices_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  build_static_mesh(terrain, planes, meshes, centre, extent);
}

Renderer::~Renderer() {
  const GLuint buffers[] = {sphere_vertices_, sphere_indices_, instances_,
                            mesh_vertices_,   mesh_indices_,   line_vertices_};
  glDeleteBuffers(6, buffers);
  const GLuint arrays[] = {sphere_vao_, mesh_vao_, line_vao_};
  glDeleteVertexArrays(3, arrays);
  glDeleteProgram(sphere_program_);
  glDeleteProgram(mesh_program_);
  glDeleteProgram(line_program_);
}

void Renderer::build_sphere_mesh(int subdivisions) {
  std::vector<float> vertices;
  std::vector<unsigned> indices;
  icosphere(subdivisions, vertices, indices);
  sphere_index_count_ = static_cast<GLsizei>(indices.size());
  glGenVertexArrays(1, &sphere_vao_);
  glBindVertexArray(sphere_vao_);
  sphere_vertices_ = static_buffer(GL_ARRAY_BUFFER, vertices);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  sphere_indices_ = static_buffer(GL_ELEMENT_ARRAY_BUFFER, indices);
  glGenBuffers(1, &instances_);
  glBindBuffer(GL_ARRAY_BUFFER, instances_);
  constexpr GLsizei kStride = kInstanceFloats * sizeof(float);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, kStride, nullptr);
  glVertexAttribDivisor(1, 1);
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, kStride, reinterpret_cast<const void*>(4 * sizeof(float)));
  glVertexAttribDivisor(2, 1);
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, kStride, reinterpret_cast<const void*>(5 * sizeof(float)));
  glVertexAttribDivisor(3, 1);
  glBindVertexArray(0);
}

void Renderer::build_static_mesh(const Heightmap* terrain, std::span<const Plane> planes,
                                 std::span<const TerrainTriangle> meshes, const Eigen::Vector3f& centre, float extent) {
  std::vector<float> v;  // position, normal
  std::vector<unsigned> idx;
  if (terrain) {
    const std::uint32_t cols = terrain->cols(), rows = terrain->rows();
    const auto stride = static_cast<std::uint32_t>(std::max(1.0, std::ceil(std::sqrt(double(cols) * rows / 1e6))));
    auto take = [&](std::uint32_t n) {
      std::vector<std::uint32_t> at;
      for (std::uint32_t k = 0; k < n; k += stride) at.push_back(k);
      if (at.back() != n - 1) at.push_back(n - 1);
      return at;
    };
    const std::vector<std::uint32_t> is = take(cols), js = take(rows);
    for (const std::uint32_t j : js)
      for (const std::uint32_t i : is) {
        const Vec3 p = terrain->vertex(i, j);
        const std::uint32_t i0 = i > 0 ? i - 1 : i, i1 = std::min(i + 1, cols - 1);
        const std::uint32_t j0 = j > 0 ? j - 1 : j, j1 = std::min(j + 1, rows - 1);
        const Vec3 dx = terrain->vertex(i1, j) - terrain->vertex(i0, j),
                   dz = terrain->vertex(i, j1) - terrain->vertex(i, j0);
        const Vec3 n = dz.cross(dx).normalized();
        v.insert(v.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
      }
    const auto w = static_cast<unsigned>(is.size());
    for (unsigned b = 0; b + 1 < js.size(); ++b)
      for (unsigned a = 0; a + 1 < w; ++a) {
        const unsigned k = b * w + a;
        idx.insert(idx.end(), {k, k + w, k + 1, k + 1, k + w, k + w + 1});
      }
  }
  terrain_index_count_ = static_cast<GLsizei>(idx.size());
  for (const Plane& plane : planes) {
    // A square of side 2 extent around the point of the plane nearest the scene's centre.
    const Eigen::Vector3f n(plane.nx, plane.ny, plane.nz);
    const Eigen::Vector3f o = centre - (n.dot(centre) - plane.offset) * n;
    const Eigen::Vector3f a =
        (std::abs(n.y()) < 0.9f ? n.cross(Eigen::Vector3f::UnitY()) : n.cross(Eigen::Vector3f::UnitX())).normalized();
    const Eigen::Vector3f b = n.cross(a);
    const auto base = static_cast<unsigned>(v.size() / 6);
    for (const auto& [sa, sb] : {std::pair{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}}) {
      const Eigen::Vector3f p = o + extent * (sa * a + sb * b);
      v.insert(v.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
    }
    idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  plane_index_count_ = static_cast<GLsizei>(idx.size()) - terrain_index_count_;
  for (const TerrainTriangle& t : meshes) {  // flat shaded: each triangle its own corners
    const auto base = static_cast<unsigned>(v.size() / 6);
    for (const Vec3& p : {t.a, t.b, t.c})
      v.insert(v.end(), {p.x(), p.y(), p.z(), t.normal.x(), t.normal.y(), t.normal.z()});
    idx.insert(idx.end(), {base, base + 1, base + 2});
  }
  mesh_index_count_ = static_cast<GLsizei>(idx.size()) - terrain_index_count_ - plane_index_count_;
  glGenVertexArrays(1, &mesh_vao_);
  glBindVertexArray(mesh_vao_);
  mesh_vertices_ = static_buffer(GL_ARRAY_BUFFER, v);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
  mesh_indices_ = static_buffer(GL_ELEMENT_ARRAY_BUFFER, idx);
  glBindVertexArray(0);
}

void Renderer::draw(const Frame& frame, bool changed, const OrbitCamera& camera, int width, int height,
                    const DebugLines* lines) {
  if (changed || colour_mode != uploaded_mode_) {
    const std::size_t n = frame.size();
    instance_data_.resize(kInstanceFloats * n);
    const bool islands = colour_mode == ColourMode::Island && frame.island.size() == n;
    const bool sleep = colour_mode == ColourMode::Sleep && frame.sleeping.size() == n;
    for (std::size_t k = 0; k < n; ++k) {
      float* d = &instance_data_[kInstanceFloats * k];
      d[0] = frame.centre[3 * k], d[1] = frame.centre[3 * k + 1], d[2] = frame.centre[3 * k + 2];
      d[3] = frame.radius[k], d[4] = frame.speed[k];
      std::array<float, 3> own{0.0f, 0.0f, 0.0f};
      float use_own = 0.0f;  // by speed
      if (islands) own = island_colour(frame.island[k]), use_own = 1.0f;
      if (sleep && frame.sleeping[k] != 0) own = kAsleepGrey, use_own = 1.0f;
      d[5] = own[0], d[6] = own[1], d[7] = own[2], d[8] = use_own;
    }
    uploaded_mode_ = colour_mode;
    glBindBuffer(GL_ARRAY_BUFFER, instances_);
    if (n > instance_capacity_) {
      instance_capacity_ = n;
      glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(instance_data_.size() * sizeof(float)), instance_data_.data(),
                   GL_DYNAMIC_DRAW);
    } else {
      glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(instance_data_.size() * sizeof(float)), instance_data_.data());
    }
    instance_count_ = n;
  }
  glViewport(0, 0, width, height);
  glClearColor(kSkyGrey[0], kSkyGrey[1], kSkyGrey[2], 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  const Eigen::Matrix4f view_projection = camera.projection(float(width) / float(std::max(height, 1))) * camera.view();

  glUseProgram(mesh_program_);
  set_uniform(mesh_program_, "view_projection", view_projection);
  glBindVertexArray(mesh_vao_);
  glDisable(GL_CULL_FACE);  // the terrain, planes and meshes are seen from both sides
  if (terrain_index_count_ > 0) {
    set_uniform(mesh_program_, "base_colour", kTerrainGreen);
    glDrawElements(GL_TRIANGLES, terrain_index_count_, GL_UNSIGNED_INT, nullptr);
  }
  if (plane_index_count_ > 0) {
    set_uniform(mesh_program_, "base_colour", kPlaneGrey);
    glDrawElements(GL_TRIANGLES, plane_index_count_, GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(std::size_t(terrain_index_count_) * sizeof(unsigned)));
  }
  if (mesh_index_count_ > 0) {
    set_uniform(mesh_program_, "base_colour", kMeshSand);
    set_uniform(mesh_program_, "light_back_faces", 1.0f);
    glDrawElements(
        GL_TRIANGLES, mesh_index_count_, GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(std::size_t(terrain_index_count_ + plane_index_count_) * sizeof(unsigned)));
    set_uniform(mesh_program_, "light_back_faces", 0.0f);
  }
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  if (instance_count_ > 0) {
    glUseProgram(sphere_program_);
    set_uniform(sphere_program_, "view_projection", view_projection);
    set_uniform(sphere_program_, "max_speed", std::max(max_speed, 1e-3f));
    glBindVertexArray(sphere_vao_);
    glDrawElementsInstanced(GL_TRIANGLES, sphere_index_count_, GL_UNSIGNED_INT, nullptr,
                            static_cast<GLsizei>(instance_count_));
  }
  glDisable(GL_CULL_FACE);
  if (lines) {
    glUseProgram(line_program_);
    set_uniform(line_program_, "view_projection", view_projection);
    draw_lines(lines->tested);  // boxes: hidden behind the terrain and spheres
    glDisable(GL_DEPTH_TEST);
    draw_lines(lines->overlay);  // normals, most inside a pile: over everything
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
}

void Renderer::draw_lines(const LineList& lines) {
  if (lines.empty()) return;
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vertices_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines.vertices.size() * sizeof(float)), lines.vertices.data(),
               GL_STREAM_DRAW);
  glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(2 * lines.segments()));
}

OffscreenTarget::OffscreenTarget(int width, int height) : width_(width), height_(height) {
  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glGenRenderbuffers(1, &colour_);
  glBindRenderbuffer(GL_RENDERBUFFER, colour_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("hail-view: the offscreen framebuffer is not complete");
}

OffscreenTarget::~OffscreenTarget() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteRenderbuffers(1, &colour_);
  glDeleteRenderbuffers(1, &depth_);
}

void OffscreenTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_); }

std::vector<unsigned char> OffscreenTarget::read_rgb() const {
  std::vector<unsigned char> pixels(std::size_t(width_) * height_ * 3);
  bind();
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // GL's first row is the bottom one.
  const std::size_t row = std::size_t(width_) * 3;
  for (int y = 0; y < height_ / 2; ++y)
    std::swap_ranges(pixels.begin() + std::ptrdiff_t(y * row), pixels.begin() + std::ptrdiff_t((y + 1) * row),
                     pixels.begin() + std::ptrdiff_t((height_ - 1 - y) * row));
  return pixels;
}

}  // namespace hail::view
