#include "view/window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

namespace hail::view {

GLFWwindow* open_window(int width, int height, bool visible, const std::string& title) {
  glfwSetErrorCallback(
      [](int code, const char* text) { std::fprintf(stderr, "hail-view: GLFW %d: %s\n", code, text); });
  if (!glfwInit()) throw std::runtime_error("GLFW cannot start: no display? (set DISPLAY, or run under xvfb-run -a)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    throw std::runtime_error("cannot open an OpenGL 3.3 core window (no GL 3.3 driver? Mesa's software GL has one)");
  }
  glfwMakeContextCurrent(window);
  return window;
}

void close_window(GLFWwindow* window) {
  glfwDestroyWindow(window);
  glfwTerminate();
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// The box of the frame's finite sphere centres (empty: min > max), without the outliers: on
/// each axis from the 2nd to the 98th percentile once there are 50 spheres, so that the few
/// spheres that fell off a terrain's edge (hundreds of metres down by then) do not set the
/// framing.
Bounds sphere_box(const Frame& frame) {
  Bounds b{Eigen::Vector3f::Constant(kInf), Eigen::Vector3f::Constant(-kInf)};
  std::vector<float> axis;
  for (int a = 0; a < 3; ++a) {
    axis.clear();
    for (std::size_t k = 0; k < frame.size(); ++k)
      if (Eigen::Vector3f(frame.centre[3 * k], frame.centre[3 * k + 1], frame.centre[3 * k + 2]).allFinite())
        axis.push_back(frame.centre[3 * k + std::size_t(a)]);
    if (axis.empty()) continue;
    const std::size_t cut = axis.size() >= 50 ? axis.size() / 50 : 0;
    std::nth_element(axis.begin(), axis.begin() + std::ptrdiff_t(cut), axis.end());
    b.min[a] = axis[cut];
    std::nth_element(axis.begin(), axis.end() - 1 - std::ptrdiff_t(cut), axis.end());
    b.max[a] = axis[axis.size() - 1 - cut];
  }
  return b;
}

bool finite(const Bounds& b) { return b.min.allFinite() && b.max.allFinite(); }

}  // namespace

Bounds scene_bounds(const StaticGeometry& geometry, const Frame& frame) {
  Bounds b = sphere_box(frame);
  if (const Heightmap* heightmap = geometry.heightmap()) {
    const Heightmap& h = *heightmap;
    b.min = b.min.cwiseMin(Eigen::Vector3f(h.x_of(0), h.min_height(), h.z_of(0)));
    b.max = b.max.cwiseMax(Eigen::Vector3f(h.max_x(), h.max_height(), h.max_z()));
  }
  for (const TerrainTriangle& t : geometry.meshes)
    for (const Vec3& p : {t.a, t.b, t.c}) b.min = b.min.cwiseMin(p), b.max = b.max.cwiseMax(p);
  if (!finite(b)) b = {Eigen::Vector3f::Constant(-10), Eigen::Vector3f::Constant(10)};
  return b;
}

Bounds focus_bounds(const Bounds& scene, const Frame& frame) {
  Bounds b = sphere_box(frame);
  if (!finite(b)) return scene;
  const Eigen::Vector3f centre = b.centre();
  const Eigen::Vector3f half = (0.5f * (b.max - b.min)).cwiseMax(Eigen::Vector3f::Constant(scene.extent() / 6.0f));
  return {centre - half, centre + half};
}

}  // namespace hail::view
