// Terrain::push_out: the last guard against a sphere ending a step inside the terrain.
//
// A sphere's terrain contacts are gathered at the start of a step out to the distance it could
// travel (|v| dt). A collision with another sphere can send it further, or towards ground it had
// no contact with: the rain scenes' worst ground penetrations (0.038 to 0.067 of a radius in
// hail-bench stress) were all of spheres with no terrain contact at all in that step. Such
// spheres are few (World flags those whose displacement exceeded their reach), so they are
// moved out by a direct query here rather than by widening every sphere's contact search.

#include <algorithm>

#include "kernel/geometry/sphere_triangle.h"
#include "kernel/terrain/terrain_parts.h"

namespace hail {

bool Terrain::push_out(float& x, float& y, float& z, float r, int rounds) const {
  const TerrainTriangles& t = triangles();
  bool moved = false;
  for (int round = 0; round < rounds; ++round) {
    const float centre[3] = {x, y, z};
    SphereTriangleContact deepest{};
    deepest.gap = 0.0f;
    query_sphere(bvh(), x, y, z, r, [&](std::uint32_t k) {
      const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]};
      const float c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
      const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
      SphereTriangleContact st;
      // Strictly deeper wins, so the first of equal triangles in BVH order is kept: the result
      // does not depend on anything but the terrain and the sphere.
      if (sphere_triangle_contact(centre, r, a, b, c, n, t.d[k], t.internal_edges[k], 0.0f, st) && st.gap < deepest.gap)
        deepest = st;
    });
    if (!(deepest.gap < 0.0f)) break;
    // n points from the centre into the surface: move against it by the overlap.
    x += deepest.n[0] * deepest.gap;
    y += deepest.n[1] * deepest.gap;
    z += deepest.n[2] * deepest.gap;
    moved = true;
  }
  return moved;
}

}  // namespace hail
