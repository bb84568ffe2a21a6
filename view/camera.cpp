#include "view/camera.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace hail::view {

void OrbitCamera::frame_box(const Eigen::Vector3f& min, const Eigen::Vector3f& max) {
  target = 0.5f * (min + max);
  const float radius = std::max(0.5f * (max - min).norm(), 1.0f);
  distance = radius / std::sin(0.5f * fov_y) * 0.8f;
}

void OrbitCamera::orbit(float dx, float dy) {
  yaw -= 0.005f * dx;
  pitch = std::clamp(pitch + 0.005f * dy, -1.5f, 1.5f);
}

void OrbitCamera::pan(float dx, float dy, float viewport_height) {
  const Eigen::Matrix4f v = view();
  const Eigen::Vector3f right = v.block<1, 3>(0, 0).transpose(), up = v.block<1, 3>(1, 0).transpose();
  const float metres_per_pixel = 2.0f * distance * std::tan(0.5f * fov_y) / std::max(viewport_height, 1.0f);
  target += (-dx * right + dy * up) * metres_per_pixel;
}

void OrbitCamera::zoom(float wheel_steps) { distance = std::clamp(distance * std::pow(0.9f, wheel_steps), 0.1f, 1e6f); }

std::pair<Eigen::Vector3f, Eigen::Vector3f> OrbitCamera::ray_through(double x, double y, int width, int height) const {
  const Eigen::Matrix4f inverse = (projection(float(width) / float(std::max(height, 1))) * view()).inverse();
  const float nx = float(2.0 * x / std::max(width, 1) - 1.0), ny = float(1.0 - 2.0 * y / std::max(height, 1));
  auto unproject = [&](float z) {
    const Eigen::Vector4f p = inverse * Eigen::Vector4f(nx, ny, z, 1.0f);
    return Eigen::Vector3f(p.head<3>() / p.w());
  };
  const Eigen::Vector3f near_point = unproject(-1.0f), far_point = unproject(1.0f);
  return {near_point, (far_point - near_point).normalized()};
}

Eigen::Vector3f OrbitCamera::eye() const {
  return target +
         distance * Eigen::Vector3f(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
}

Eigen::Matrix4f OrbitCamera::view() const {
  const Eigen::Vector3f e = eye();
  const Eigen::Vector3f f = (target - e).normalized();
  const Eigen::Vector3f s = f.cross(Eigen::Vector3f::UnitY()).normalized();
  const Eigen::Vector3f u = s.cross(f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(e), m(1, 3) = -u.dot(e), m(2, 3) = f.dot(e);
  return m;
}

Eigen::Matrix4f OrbitCamera::projection(float aspect) const {
  const float near_plane = std::max(distance * 1e-3f, 0.01f), far_plane = distance * 20.0f + 1000.0f;
  const float t = 1.0f / std::tan(0.5f * fov_y);
  Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
  p(0, 0) = t / aspect;
  p(1, 1) = t;
  p(2, 2) = (far_plane + near_plane) / (near_plane - far_plane);
  p(2, 3) = 2.0f * far_plane * near_plane / (near_plane - far_plane);
  p(3, 2) = -1.0f;
  return p;
}

}  // namespace hail::view
