#include "kernel/terrain.h"

#include <algorithm>
#include <cmath>

#include "kernel/sphere_pairs.h"
#include "kernel/sphere_triangle.h"

namespace hail {
namespace {

constexpr int kMaxContactsPerSphere = 8;

}  // namespace

Terrain::Terrain(Heightmap heightmap, std::uint32_t leaf_size) : heightmap_(std::move(heightmap)) {
  TerrainTriangles in_grid_order = build_terrain_triangles(heightmap_);
  std::vector<Aabb> bounds(in_grid_order.size());
  for (std::size_t t = 0; t < bounds.size(); ++t) terrain_triangle_bounds(in_grid_order, t, bounds[t].min, bounds[t].max);
  bvh_ = build_flat_bvh(bounds, leaf_size);
  // Permuted into BVH order so that a leaf's triangles are contiguous.
  triangles_ = reorder_terrain_triangles(in_grid_order, bvh_.primitive_order);
}

void Terrain::find_contacts(const SphereSoA& s, std::size_t first, std::size_t last, float dt, float restitution,
                            float friction, std::vector<Contact>& out) const {
  const TerrainTriangles& t = triangles_;
  for (std::size_t i = first; i < last; ++i) {
    const float centre[3] = {s.px[i], s.py[i], s.pz[i]}, r = s.radius[i];
    const float speed = std::sqrt(s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i]);
    const float margin = speed * dt;
    Contact found[kMaxContactsPerSphere];
    int count = 0;
    query_sphere_stackless(bvh_, centre[0], centre[1], centre[2], r + margin, [&](std::uint32_t k) {
      const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]}, c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
      const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
      SphereTriangleContact st;
      if (!sphere_triangle_contact(centre, r, a, b, c, n, t.d[k], t.internal_edges[k], margin, st)) return;
      // Reduction: one contact per distinct normal (a flat area split into triangles, or the
      // two triangles sharing an internal edge, would otherwise push twice).
      for (int m = 0; m < count; ++m) {
        const float same = found[m].nx * st.n[0] + found[m].ny * st.n[1] + found[m].nz * st.n[2];
        if (same > 0.99999f) {
          if (st.gap < found[m].gap) {
            found[m].gap = st.gap;
            found[m].surface_d = st.surface_d;
          }
          return;
        }
      }
      Contact contact;
      contact.a = static_cast<std::uint32_t>(i);
      contact.b = kStaticBody;
      contact.nx = st.n[0];
      contact.ny = st.n[1];
      contact.nz = st.n[2];
      contact.gap = st.gap;
      contact.surface_d = st.surface_d;
      contact.restitution = combine_restitution(s.restitution[i], restitution);
      contact.friction = combine_friction(s.friction[i], friction);
      if (count < kMaxContactsPerSphere) {
        found[count++] = contact;
      } else {  // full: keep the deepest
        int worst = 0;
        for (int m = 1; m < count; ++m)
          if (found[m].gap > found[worst].gap) worst = m;
        if (contact.gap < found[worst].gap) found[worst] = contact;
      }
    });
    for (int m = 0; m < count; ++m) out.push_back(found[m]);
  }
}

float Terrain::penetration(float x, float y, float z, float r) const {
  const TerrainTriangles& t = triangles_;
  const float centre[3] = {x, y, z};
  float deepest = 0.0f;
  query_sphere_stackless(bvh_, x, y, z, r, [&](std::uint32_t k) {
    const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]}, c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
    const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
    SphereTriangleContact st;
    if (sphere_triangle_contact(centre, r, a, b, c, n, t.d[k], t.internal_edges[k], 0.0f, st))
      deepest = std::max(deepest, -st.gap);
  });
  return deepest;
}

}  // namespace hail
