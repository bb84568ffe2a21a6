#include "kernel/terrain/terrain_parts.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hail/errors.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/sphere_triangle.h"
#include "kernel/terrain/terrain_contacts.h"
#include "kernel/terrain/terrain_triangles.h"

namespace hail {

Terrain::Terrain(Heightmap heightmap, std::uint32_t leaf_size)
    : heightmap_(std::move(heightmap)), leaf_size_(leaf_size) {
  TerrainTriangles in_grid_order = build_terrain_triangles(heightmap_);
  std::vector<Aabb> bounds(in_grid_order.size());
  for (std::size_t t = 0; t < bounds.size(); ++t)
    terrain_triangle_bounds(in_grid_order, t, bounds[t].min, bounds[t].max);
  bvh_ = std::make_unique<FlatBvh>(build_flat_bvh(bounds, leaf_size));
  // Permuted into BVH order so that a leaf's triangles are contiguous.
  triangles_ = std::make_unique<TerrainTriangles>(reorder_terrain_triangles(in_grid_order, bvh_->primitive_order));
  triangle_bounds_ = std::make_unique<std::vector<Aabb>>(bounds.size());
  for (std::size_t k = 0; k < bounds.size(); ++k) (*triangle_bounds_)[k] = bounds[bvh_->primitive_order[k]];
}

Terrain::Terrain(Terrain&&) noexcept = default;
Terrain& Terrain::operator=(Terrain&&) noexcept = default;
Terrain::~Terrain() = default;

std::size_t Terrain::triangle_count() const { return triangles_->size(); }

TerrainTriangle Terrain::triangle(std::uint32_t index) const {
  const TerrainTriangles& t = *triangles_;
  if (index >= t.size())
    throw InvalidArgument("Terrain::triangle: index " + std::to_string(index) + " is not below the triangle count " +
                          std::to_string(t.size()));
  return {Vec3(t.v0x[index], t.v0y[index], t.v0z[index]), Vec3(t.v1x[index], t.v1y[index], t.v1z[index]),
          Vec3(t.v2x[index], t.v2y[index], t.v2z[index]), Vec3(t.nx[index], t.ny[index], t.nz[index])};
}

std::size_t Terrain::memory_bytes() const {
  const TerrainTriangles& t = triangles();
  std::size_t bytes = heightmap_.heights().size() * sizeof(float);
  for (const AlignedArray<float>* a :
       {&t.v0x, &t.v0y, &t.v0z, &t.v1x, &t.v1y, &t.v1z, &t.v2x, &t.v2y, &t.v2z, &t.e0x, &t.e0y,
        &t.e0z, &t.e1x, &t.e1y, &t.e1z, &t.e2x, &t.e2y, &t.e2z, &t.nx,  &t.ny,  &t.nz,  &t.d})
    bytes += a->capacity() * sizeof(float);
  bytes += t.internal_edges.capacity();
  bytes += bvh().nodes.capacity() * sizeof(FlatNode) + bvh().primitive_order.capacity() * sizeof(std::uint32_t);
  return bytes + triangle_bounds().capacity() * sizeof(Aabb);
}

void Terrain::find_contacts(const SphereSoA& s, std::size_t first, std::size_t last, float dt, float restitution,
                            float friction, std::vector<Contact>& out, float fast_fraction, bool sweep_fast) const {
  // Spheres go through the BVH a packet at a time (kernel/simd/terrain_contacts.cpp):
  // neighbours in the SoA share most of their walk. Each lane gets the triangles whose box its
  // sphere touches in the order a single walk gives, and the lanes are emitted in sphere order,
  // so the contacts do not depend on the packet width (the SIMD path).
  if (first >= last) return;
  simd_kernels().terrain_contacts(*this, s, first, last, dt, restitution, friction, out, fast_fraction, sweep_fast);
}

void Terrain::find_contacts_scalar(const SphereSoA& s, std::size_t first, std::size_t last, float dt, float restitution,
                                   float friction, std::vector<Contact>& out, float fast_fraction,
                                   bool sweep_fast) const {
  for (std::size_t i = first; i < last; ++i) {
    const float margin = terrain_contact_reach(s, i, dt, fast_fraction, sweep_fast);
    const float r = s.radius[i] + margin;
    ContactReduction reduction;
    query_sphere(bvh(), s.px[i], s.py[i], s.pz[i], r, [&](std::uint32_t k) {
      if (sphere_overlaps(triangle_bounds()[k], s.px[i], s.py[i], s.pz[i], r))
        add_terrain_contact(s, i, triangles(), k, margin, restitution, friction, reduction);
    });
    out.insert(out.end(), reduction.found, reduction.found + reduction.count);
  }
}

std::size_t Terrain::push_out_spheres(SphereSoA& s, std::span<const std::uint32_t> slots) const {
  if (slots.empty()) return 0;
  return simd_kernels().terrain_push_out(*this, s, slots.data(), slots.size());
}

float Terrain::penetration(float x, float y, float z, float r) const {
  const TerrainTriangles& t = triangles();
  const float centre[3] = {x, y, z};
  float deepest = 0.0f;
  query_sphere(bvh(), x, y, z, r, [&](std::uint32_t k) {
    const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]},
                c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
    const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
    SphereTriangleContact st;
    if (sphere_triangle_contact(centre, r, a, b, c, n, t.d[k], t.internal_edges[k], 0.0f, st))
      deepest = std::max(deepest, -st.gap);
  });
  return deepest;
}

}  // namespace hail
