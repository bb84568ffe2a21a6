#include "kernel/terrain.h"

#include <algorithm>
#include <cmath>

#include "kernel/sphere_pairs.h"
#include "kernel/sphere_triangle.h"

namespace hail {
namespace {

struct Tri {
  float v[3][3];
  float n[3];
};

/// Triangle t of the heightmap: cell k = t / 2 at (i, j); t even: (v00, v01, v10), odd:
/// (v10, v01, v11), both wound so that (b - a) x (c - a) points up.
Tri heightmap_triangle(const Heightmap& h, std::uint32_t t) {
  const std::uint32_t cells_x = h.cols() - 1, cell = t / 2, i = cell % cells_x, j = cell / cells_x;
  auto vertex = [&](std::uint32_t vi, std::uint32_t vj, float* out) {
    out[0] = h.x_of(vi);
    out[1] = h.height(vi, vj);
    out[2] = h.z_of(vj);
  };
  Tri tri;
  if (t % 2 == 0) {
    vertex(i, j, tri.v[0]);
    vertex(i, j + 1, tri.v[1]);
    vertex(i + 1, j, tri.v[2]);
  } else {
    vertex(i + 1, j, tri.v[0]);
    vertex(i, j + 1, tri.v[1]);
    vertex(i + 1, j + 1, tri.v[2]);
  }
  const float e1[3] = {tri.v[1][0] - tri.v[0][0], tri.v[1][1] - tri.v[0][1], tri.v[1][2] - tri.v[0][2]};
  const float e2[3] = {tri.v[2][0] - tri.v[0][0], tri.v[2][1] - tri.v[0][1], tri.v[2][2] - tri.v[0][2]};
  float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int a = 0; a < 3; ++a) tri.n[a] = n[a] / len;  // cells have positive area: len > 0
  return tri;
}

/// The triangle across edge e of triangle t, or -1 on the map's boundary.
/// Even (v00, v01, v10): e0 v00-v01 -> odd of cell (i-1, j); e1 the diagonal -> odd of this
/// cell; e2 v10-v00 -> odd of cell (i, j-1). Odd (v10, v01, v11): e0 the diagonal -> even of
/// this cell; e1 v01-v11 -> even of (i, j+1); e2 v11-v10 -> even of (i+1, j).
std::int64_t neighbour(const Heightmap& h, std::uint32_t t, int e) {
  const std::int64_t cells_x = h.cols() - 1, cells_z = h.rows() - 1, cell = t / 2, i = cell % cells_x, j = cell / cells_x;
  auto tri = [&](std::int64_t ci, std::int64_t cj, int odd) -> std::int64_t {
    if (ci < 0 || cj < 0 || ci >= cells_x || cj >= cells_z) return -1;
    return 2 * (cj * cells_x + ci) + odd;
  };
  if (t % 2 == 0) return e == 0 ? tri(i - 1, j, 1) : e == 1 ? tri(i, j, 1) : tri(i, j - 1, 1);
  return e == 0 ? tri(i, j, 0) : e == 1 ? tri(i, j + 1, 0) : tri(i + 1, j, 0);
}

constexpr int kMaxContactsPerSphere = 8;

}  // namespace

Terrain::Terrain(Heightmap heightmap, std::uint32_t leaf_size) : heightmap_(std::move(heightmap)) {
  const std::uint32_t count = 2 * (heightmap_.cols() - 1) * (heightmap_.rows() - 1);
  std::vector<Aabb> bounds(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const Tri tri = heightmap_triangle(heightmap_, t);
    for (int a = 0; a < 3; ++a) {
      bounds[t].min[a] = std::min({tri.v[0][a], tri.v[1][a], tri.v[2][a]});
      bounds[t].max[a] = std::max({tri.v[0][a], tri.v[1][a], tri.v[2][a]});
    }
  }
  bvh_ = build_flat_bvh(bounds, leaf_size);
  TerrainTriangles& s = triangles_;
  for (auto* a : {&s.ax, &s.ay, &s.az, &s.bx, &s.by, &s.bz, &s.cx, &s.cy, &s.cz, &s.nx, &s.ny, &s.nz, &s.d}) a->resize(count);
  s.internal_edges.resize(count);
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t t = bvh_.primitive_order[k];
    const Tri tri = heightmap_triangle(heightmap_, t);
    s.ax[k] = tri.v[0][0]; s.ay[k] = tri.v[0][1]; s.az[k] = tri.v[0][2];
    s.bx[k] = tri.v[1][0]; s.by[k] = tri.v[1][1]; s.bz[k] = tri.v[1][2];
    s.cx[k] = tri.v[2][0]; s.cy[k] = tri.v[2][1]; s.cz[k] = tri.v[2][2];
    s.nx[k] = tri.n[0]; s.ny[k] = tri.n[1]; s.nz[k] = tri.n[2];
    s.d[k] = tri.n[0] * tri.v[0][0] + tri.n[1] * tri.v[0][1] + tri.n[2] * tri.v[0][2];
    std::uint8_t internal = 0;
    for (int e = 0; e < 3; ++e) {
      const std::int64_t other = neighbour(heightmap_, t, e);
      if (other < 0) continue;  // the map's boundary is a real edge
      const Tri o = heightmap_triangle(heightmap_, static_cast<std::uint32_t>(other));
      const float cosine = tri.n[0] * o.n[0] + tri.n[1] * o.n[1] + tri.n[2] * o.n[2];
      if (cosine >= kInternalEdgeCosine) internal |= static_cast<std::uint8_t>(1u << e);
    }
    s.internal_edges[k] = internal;
  }
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
      const float a[3] = {t.ax[k], t.ay[k], t.az[k]}, b[3] = {t.bx[k], t.by[k], t.bz[k]}, c[3] = {t.cx[k], t.cy[k], t.cz[k]};
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
    const float a[3] = {t.ax[k], t.ay[k], t.az[k]}, b[3] = {t.bx[k], t.by[k], t.bz[k]}, c[3] = {t.cx[k], t.cy[k], t.cz[k]};
    const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
    SphereTriangleContact st;
    if (sphere_triangle_contact(centre, r, a, b, c, n, t.d[k], t.internal_edges[k], 0.0f, st))
      deepest = std::max(deepest, -st.gap);
  });
  return deepest;
}

}  // namespace hail
