#include "kernel/mesh/mesh_collider.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hail/errors.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/mesh/mesh_contact.h"
#include "kernel/mesh/mesh_edges.h"
#include "kernel/terrain/terrain_contacts.h"

namespace hail {
namespace {

struct Face {
  double n[3];  ///< unit normal from the winding
  bool kept;    ///< not degenerate
};

/// Whether the edge of triangle t at `corner` (to the next corner) is internal: the fold to its
/// neighbour u is within kInternalEdgeCosine of flat, or (closed meshes: solids) concave, as on
/// terrain (kernel/terrain/terrain_triangles.cpp's edge_is_internal).
bool edge_is_internal(const std::vector<Vec3>& v, const std::vector<std::uint32_t>& idx,
                      const std::vector<std::uint32_t>& welded, const std::vector<Face>& faces, std::size_t t,
                      std::uint32_t corner, std::uint32_t u, bool flipped, bool solid) {
  const double sign = flipped ? -1.0 : 1.0;  // wound the other way: its normal faces the other way
  double cosine = 0.0;
  for (int c = 0; c < 3; ++c) cosine += faces[t].n[c] * sign * faces[u].n[c];
  if (cosine >= double{kInternalEdgeCosine}) return true;
  if (!solid) return false;
  const std::uint32_t p = welded[idx[3 * t + corner]], q = welded[idx[3 * t + (corner + 1) % 3]];
  std::uint32_t far = idx[3 * u];
  for (std::uint32_t k = 0; k < 3; ++k)
    if (welded[idx[3 * u + k]] != p && welded[idx[3 * u + k]] != q) far = idx[3 * u + k];
  const Vec3& a = v[idx[3 * t]];
  const double above = faces[t].n[0] * (double(v[far].x()) - a.x()) + faces[t].n[1] * (double(v[far].y()) - a.y()) +
                       faces[t].n[2] * (double(v[far].z()) - a.z());
  return above > 0.0;  // the neighbour rises above this face: concave
}

}  // namespace

MeshCollider build_mesh_collider(const TriangleMesh& mesh, const MeshTransform& transform, float restitution,
                                 float friction, std::uint32_t first_feature, std::uint32_t leaf_size) {
  transform.validate();
  std::vector<Vec3> world(mesh.vertices().size());
  for (std::size_t k = 0; k < world.size(); ++k) world[k] = transform.apply(mesh.vertices()[k]);
  const std::vector<std::uint32_t>& idx = mesh.indices();
  const std::size_t count = mesh.triangle_count();

  std::vector<Face> faces(count);
  std::size_t kept = 0;
  for (std::size_t t = 0; t < count; ++t) {
    const Vec3 &a = world[idx[3 * t]], &b = world[idx[3 * t + 1]], &c = world[idx[3 * t + 2]];
    const double u[3] = {double(b.x()) - a.x(), double(b.y()) - a.y(), double(b.z()) - a.z()};
    const double w[3] = {double(c.x()) - a.x(), double(c.y()) - a.y(), double(c.z()) - a.z()};
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    faces[t].kept = length > 0.0 && std::isfinite(length);
    for (double& x : n) x = faces[t].kept ? x / length : 0.0;
    std::copy(n, n + 3, faces[t].n);
    kept += faces[t].kept;
  }
  if (kept == 0)
    throw InvalidArgument("World::add_mesh: every one of the mesh's " + std::to_string(count) +
                          " triangles has zero area where it is placed");

  const bool solid = mesh.closed();
  const std::vector<std::uint32_t> welded = weld_vertices(world);
  std::vector<std::uint8_t> same_direction;
  const std::vector<std::uint32_t> neighbour = edge_neighbours(world, idx, welded, &same_direction);

  TerrainTriangles in_mesh_order;
  AlignedArray<float>* vertex[3][3] = {{&in_mesh_order.v0x, &in_mesh_order.v0y, &in_mesh_order.v0z},
                                       {&in_mesh_order.v1x, &in_mesh_order.v1y, &in_mesh_order.v1z},
                                       {&in_mesh_order.v2x, &in_mesh_order.v2y, &in_mesh_order.v2z}};
  AlignedArray<float>* edge[3][3] = {{&in_mesh_order.e0x, &in_mesh_order.e0y, &in_mesh_order.e0z},
                                     {&in_mesh_order.e1x, &in_mesh_order.e1y, &in_mesh_order.e1z},
                                     {&in_mesh_order.e2x, &in_mesh_order.e2y, &in_mesh_order.e2z}};
  AlignedArray<float>* normal[3] = {&in_mesh_order.nx, &in_mesh_order.ny, &in_mesh_order.nz};
  for (auto& row : vertex)
    for (auto* a : row) a->resize(kept);
  for (auto& row : edge)
    for (auto* a : row) a->resize(kept);
  for (auto* a : normal) a->resize(kept);
  in_mesh_order.d.resize(kept);
  in_mesh_order.internal_edges.resize(kept);
  std::size_t out = 0;
  for (std::size_t t = 0; t < count; ++t) {
    if (!faces[t].kept) continue;
    const Vec3* corner[3] = {&world[idx[3 * t]], &world[idx[3 * t + 1]], &world[idx[3 * t + 2]]};
    double d = 0.0;
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) {
        (*vertex[k][c])[out] = (*corner[k])[c];
        (*edge[k][c])[out] = static_cast<float>(double((*corner[(k + 1) % 3])[c]) - (*corner[k])[c]);
      }
      (*normal[c])[out] = static_cast<float>(faces[t].n[c]);
      d += faces[t].n[c] * (*corner[0])[c];
    }
    in_mesh_order.d[out] = static_cast<float>(d);
    std::uint8_t internal = 0;
    for (std::uint32_t e = 0; e < 3; ++e) {
      const std::uint32_t u = neighbour[3 * t + e];
      if (u == kNoNeighbour) continue;  // a boundary or non-manifold edge is a real edge
      if (edge_is_internal(world, idx, welded, faces, t, e, u, same_direction[3 * t + e] != 0, solid))
        internal |= static_cast<std::uint8_t>(1u << e);
    }
    in_mesh_order.internal_edges[out] = internal;
    ++out;
  }

  MeshCollider m;
  std::vector<Aabb> bounds(kept);
  for (std::size_t t = 0; t < kept; ++t) terrain_triangle_bounds(in_mesh_order, t, bounds[t].min, bounds[t].max);
  m.bvh = build_flat_bvh(bounds, leaf_size);
  m.triangles = reorder_terrain_triangles(in_mesh_order, m.bvh.primitive_order);
  m.bounds.resize(kept);
  for (std::size_t k = 0; k < kept; ++k) m.bounds[k] = bounds[m.bvh.primitive_order[k]];
  m.two_sided = !solid;
  m.restitution = restitution;
  m.friction = friction;
  m.first_feature = first_feature;
  m.degenerate = count - kept;
  return m;
}

void MeshCollider::find_contacts(const SphereSoA& s, std::size_t first, std::size_t last, float dt,
                                 std::vector<Contact>& out, float fast_fraction, bool sweep_fast) const {
  if (first < last) simd_kernels().mesh_contacts(*this, s, first, last, dt, out, fast_fraction, sweep_fast);
}

void MeshCollider::find_contacts_scalar(const SphereSoA& s, std::size_t first, std::size_t last, float dt,
                                        std::vector<Contact>& out, float fast_fraction, bool sweep_fast) const {
  const TerrainTriangles& t = triangles;
  for (std::size_t i = first; i < last; ++i) {
    const float margin = terrain_contact_reach(s, i, dt, fast_fraction, sweep_fast);
    const float reach = s.radius[i] + margin;
    const float centre[3] = {s.px[i], s.py[i], s.pz[i]};
    ContactReduction reduction;
    query_sphere(bvh, centre[0], centre[1], centre[2], reach, [&](std::uint32_t k) {
      if (!sphere_overlaps(bounds[k], centre[0], centre[1], centre[2], reach)) return;
      const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]},
                  c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]}, n[3] = {t.nx[k], t.ny[k], t.nz[k]};
      SphereTriangleContact st;
      if (sphere_mesh_triangle_contact(centre, s.radius[i], a, b, c, n, t.d[k], t.internal_edges[k], two_sided, margin,
                                       st))
        add_terrain_contact(s, i, st, kMeshFeature | (first_feature + k), restitution, friction, reduction);
    });
    out.insert(out.end(), reduction.found, reduction.found + reduction.count);
  }
}

float MeshCollider::penetration(float x, float y, float z, float r) const {
  const TerrainTriangles& t = triangles;
  const float centre[3] = {x, y, z};
  float deepest = 0.0f;
  query_sphere(bvh, x, y, z, r, [&](std::uint32_t k) {
    const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]},
                c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]}, n[3] = {t.nx[k], t.ny[k], t.nz[k]};
    SphereTriangleContact st;
    if (sphere_mesh_triangle_contact(centre, r, a, b, c, n, t.d[k], t.internal_edges[k], two_sided, 0.0f, st))
      deepest = std::max(deepest, -st.gap);
  });
  return deepest;
}

std::size_t MeshCollider::memory_bytes() const {
  const TerrainTriangles& t = triangles;
  std::size_t bytes = 0;
  for (const AlignedArray<float>* a :
       {&t.v0x, &t.v0y, &t.v0z, &t.v1x, &t.v1y, &t.v1z, &t.v2x, &t.v2y, &t.v2z, &t.e0x, &t.e0y,
        &t.e0z, &t.e1x, &t.e1y, &t.e1z, &t.e2x, &t.e2y, &t.e2z, &t.nx,  &t.ny,  &t.nz,  &t.d})
    bytes += a->capacity() * sizeof(float);
  bytes += t.internal_edges.capacity();
  bytes += bvh.nodes.capacity() * sizeof(FlatNode) + bvh.primitive_order.capacity() * sizeof(std::uint32_t);
  return bytes + bounds.capacity() * sizeof(Aabb);
}

}  // namespace hail
