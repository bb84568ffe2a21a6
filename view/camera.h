#pragma once
// An orbit camera: it looks at a target from a distance, turned by yaw and pitch; the mouse
// orbits (left drag), pans (right or middle drag) and zooms (wheel).

#include <Eigen/Core>
#include <utility>

namespace hail::view {

struct OrbitCamera {
  Eigen::Vector3f target{0.0f, 0.0f, 0.0f};
  float distance = 50.0f;  ///< m from the target
  float yaw = 0.6f;        ///< rad about y
  float pitch = 0.45f;     ///< rad above the horizon
  float fov_y = 0.8f;      ///< rad

  /// Frames a box (min, max) from the default angle.
  void frame_box(const Eigen::Vector3f& min, const Eigen::Vector3f& max);
  void orbit(float dx_pixels, float dy_pixels);
  void pan(float dx_pixels, float dy_pixels, float viewport_height);
  void zoom(float wheel_steps);

  /// The ray from the eye through pixel (x, y) of a width x height view (from its top left):
  /// {origin on the near plane, unit direction}.
  [[nodiscard]] std::pair<Eigen::Vector3f, Eigen::Vector3f> ray_through(double x, double y, int width,
                                                                        int height) const;

  [[nodiscard]] Eigen::Vector3f eye() const;
  [[nodiscard]] Eigen::Matrix4f view() const;
  [[nodiscard]] Eigen::Matrix4f projection(float aspect) const;
};

}  // namespace hail::view
