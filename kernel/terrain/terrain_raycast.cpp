// Terrain::raycast: the embedder's ray query (picking, line of sight, "where is the ground under
// this point"), the flat BVH's nearest-hit walk over the terrain's triangles in BVH order.

#include <cmath>
#include <string>

#include "hail/errors.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/geometry/ray_triangle.h"
#include "kernel/terrain/terrain_parts.h"

namespace hail {
namespace {

void require_finite(const Vec3& v, const char* what) {
  if (!v.allFinite())
    throw InvalidArgument(std::string("Terrain::raycast: ") + what + " must be finite, got (" + std::to_string(v.x()) +
                          ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) + ")");
}

}  // namespace

std::optional<TerrainRayHit> Terrain::raycast(const Vec3& origin, const Vec3& dir, float max_t) const {
  require_finite(origin, "origin");
  require_finite(dir, "dir");
  if (dir.x() == 0.0f && dir.y() == 0.0f && dir.z() == 0.0f)
    throw InvalidArgument("Terrain::raycast: dir must not be zero");
  if (!(max_t >= 0.0f))
    throw InvalidArgument("Terrain::raycast: max_t must be >= 0 (infinity allowed), got " + std::to_string(max_t));

  const float o[3] = {origin.x(), origin.y(), origin.z()};
  const float d[3] = {dir.x(), dir.y(), dir.z()};
  const TerrainTriangles& tri = triangles();
  const RayHit hit = query_ray(bvh(), o, d, max_t, [&](std::uint32_t k) {
    const float a[3] = {tri.v0x[k], tri.v0y[k], tri.v0z[k]};
    const float b[3] = {tri.v1x[k], tri.v1y[k], tri.v1z[k]};
    const float c[3] = {tri.v2x[k], tri.v2y[k], tri.v2z[k]};
    return ray_triangle(o, d, a, b, c);
  });
  if (hit.primitive == kNoPrimitive) return std::nullopt;
  const std::uint32_t k = hit.primitive;
  return TerrainRayHit{hit.t, origin + hit.t * dir, Vec3(tri.nx[k], tri.ny[k], tri.nz[k]), k};
}

}  // namespace hail
