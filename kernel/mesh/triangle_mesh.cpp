#include "hail/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "hail/errors.h"
#include "kernel/mesh/mesh_edges.h"

namespace hail {
namespace {

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

void MeshTransform::validate() const {
  auto finite = [](const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); };
  if (!finite(position)) throw InvalidArgument("MeshTransform: position is not finite");
  if (!finite(axis)) throw InvalidArgument("MeshTransform: axis is not finite");
  if (!std::isfinite(degrees)) throw InvalidArgument("MeshTransform: degrees is not finite");
  if (!(scale > 0.0f) || !std::isfinite(scale))
    throw InvalidArgument("MeshTransform: scale " + number(scale) + " is not a finite number > 0");
  if (degrees != 0.0f && axis.squaredNorm() == 0.0f)
    throw InvalidArgument("MeshTransform: a rotation of " + number(degrees) + " degrees about a zero axis");
}

Vec3 MeshTransform::apply(const Vec3& p) const {
  // Rodrigues' formula in double, rounded once: a mesh placed with a whole-degree turn lands
  // within half a float spacing of where it should.
  const double s = scale;
  double q[3] = {s * p.x(), s * p.y(), s * p.z()};
  if (degrees != 0.0f) {
    const double len =
        std::sqrt(double(axis.x()) * axis.x() + double(axis.y()) * axis.y() + double(axis.z()) * axis.z());
    const double k[3] = {axis.x() / len, axis.y() / len, axis.z() / len};
    const double angle = double(degrees) * (3.14159265358979323846 / 180.0);
    const double c = std::cos(angle), sn = std::sin(angle);
    const double kq = k[0] * q[0] + k[1] * q[1] + k[2] * q[2];
    const double cross[3] = {k[1] * q[2] - k[2] * q[1], k[2] * q[0] - k[0] * q[2], k[0] * q[1] - k[1] * q[0]};
    double r[3];
    for (int d = 0; d < 3; ++d) r[d] = q[d] * c + cross[d] * sn + k[d] * kq * (1.0 - c);
    std::copy(r, r + 3, q);
  }
  return Vec3(static_cast<float>(q[0] + position.x()), static_cast<float>(q[1] + position.y()),
              static_cast<float>(q[2] + position.z()));
}

TriangleMesh::TriangleMesh(std::vector<Vec3> vertices, std::vector<std::uint32_t> indices)
    : vertices_(std::move(vertices)), indices_(std::move(indices)) {
  if (indices_.empty()) throw InvalidArgument("TriangleMesh: no triangles (the index list is empty)");
  if (indices_.size() % 3 != 0)
    throw InvalidArgument("TriangleMesh: " + std::to_string(indices_.size()) +
                          " indices, not a multiple of 3 (three per triangle)");
  if (indices_.size() / 3 > kMaxMeshTriangles)
    throw InvalidArgument("TriangleMesh: " + std::to_string(indices_.size() / 3) + " triangles, more than " +
                          std::to_string(kMaxMeshTriangles) + " (kMaxMeshTriangles)");
  for (std::size_t v = 0; v < vertices_.size(); ++v) {
    const Vec3& p = vertices_[v];
    if (!(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z())))
      throw InvalidArgument("TriangleMesh: vertex " + std::to_string(v) + " is not finite");
  }
  for (std::size_t k = 0; k < indices_.size(); ++k)
    if (indices_[k] >= vertices_.size())
      throw InvalidArgument("TriangleMesh: index " + std::to_string(k) + " (triangle " + std::to_string(k / 3) +
                            ") is " + std::to_string(indices_[k]) + ", not below the vertex count " +
                            std::to_string(vertices_.size()));
  closed_ = mesh_is_closed(vertices_, indices_);
}

}  // namespace hail
