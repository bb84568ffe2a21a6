#pragma once
// The GLFW window and OpenGL 3.3 core context every mode draws in (hidden when headless), and
// the box the camera first frames.

#include <Eigen/Core>
#include <string>

#include "view/frame.h"
#include "view/static_geometry.h"

struct GLFWwindow;

namespace hail::view {

/// glfwInit and a window with an OpenGL 3.3 core context, made current; throws
/// std::runtime_error (naming the DISPLAY problem, the usual one) if either fails.
GLFWwindow* open_window(int width, int height, bool visible, const std::string& title);
/// glfwDestroyWindow and glfwTerminate.
void close_window(GLFWwindow* window);

/// The box around the scene's terrain (or the spheres, without one) and the frame's spheres
/// (but for outliers: the 2nd to 98th percentile of the centres on each axis).
struct Bounds {
  Eigen::Vector3f min, max;
  [[nodiscard]] Eigen::Vector3f centre() const { return 0.5f * (min + max); }
  [[nodiscard]] float extent() const { return (max - min).maxCoeff(); }
};
Bounds scene_bounds(const StaticGeometry& geometry, const Frame& frame);
/// What the camera first frames: the spheres' box, grown about its centre to at least a third
/// of `scene`'s (so a pile on a large terrain is seen close, with the ground around it).
Bounds focus_bounds(const Bounds& scene, const Frame& frame);

}  // namespace hail::view
