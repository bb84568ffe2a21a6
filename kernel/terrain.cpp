#include "kernel/terrain.h"

#include <algorithm>
#include <cmath>

#include "kernel/bvh_packet_walk.h"
#include "kernel/continuous_collision.h"
#include "kernel/sphere_pairs.h"
#include "kernel/sphere_triangle.h"

namespace hail {
namespace {

constexpr int kMaxContactsPerSphere = 8;

/// One sphere's terrain contacts while its candidates come in, reduced to one contact per
/// distinct normal (a flat area split into triangles, or the two triangles sharing an internal
/// edge, would otherwise push twice); when full, the deepest are kept.
struct ContactReduction {
  Contact found[kMaxContactsPerSphere];
  int count = 0;

  /// `centre`: the sphere's, which the contact planes are measured from.
  void add(const Contact& contact, const float centre[3]) {
    for (int m = 0; m < count; ++m) {
      Contact& kept = found[m];
      const float same = kept.nx * contact.nx + kept.ny * contact.ny + kept.nz * contact.nz;
      if (same > 0.99999f) {
        if (contact.gap < kept.gap) {
          kept.gap = contact.gap;
          // The kept normal with the new contact's plane offset would put the plane elsewhere
          // by (n_kept - n_new) . x: up to 0.5% of the distance from the origin, tens of metres
          // at 1e4 m (depenetration then threw spheres). Shift the offset so that the plane
          // sits at the new gap along the kept normal; exact (a no-op) for equal normals.
          kept.surface_d = contact.surface_d + ((kept.nx - contact.nx) * centre[0] + (kept.ny - contact.ny) * centre[1] +
                                                (kept.nz - contact.nz) * centre[2]);
        }
        return;
      }
    }
    if (count < kMaxContactsPerSphere) {
      found[count++] = contact;
      return;
    }
    int worst = 0;
    for (int m = 1; m < count; ++m)
      if (found[m].gap > found[worst].gap) worst = m;
    if (contact.gap < found[worst].gap) found[worst] = contact;
  }
};

}  // namespace

Terrain::Terrain(Heightmap heightmap, std::uint32_t leaf_size) : heightmap_(std::move(heightmap)) {
  TerrainTriangles in_grid_order = build_terrain_triangles(heightmap_);
  std::vector<Aabb> bounds(in_grid_order.size());
  for (std::size_t t = 0; t < bounds.size(); ++t) terrain_triangle_bounds(in_grid_order, t, bounds[t].min, bounds[t].max);
  bvh_ = build_flat_bvh(bounds, leaf_size);
  // Permuted into BVH order so that a leaf's triangles are contiguous.
  triangles_ = reorder_terrain_triangles(in_grid_order, bvh_.primitive_order);
  triangle_bounds_.resize(bounds.size());
  for (std::size_t k = 0; k < bounds.size(); ++k) triangle_bounds_[k] = bounds[bvh_.primitive_order[k]];
}

void Terrain::find_contacts(const SphereSoA& s, std::size_t first, std::size_t last, float dt, float restitution,
                            float friction, std::vector<Contact>& out, float fast_fraction, bool sweep_fast) const {
  const TerrainTriangles& t = triangles_;
  // Spheres go through the BVH a packet at a time (kernel/bvh_packet_walk.h): neighbours in the
  // SoA share most of their walk. Each lane gets the triangles whose box its sphere touches in
  // the order a single walk gives, and the lanes are emitted in sphere order, so the contacts
  // do not depend on the packet width.
  SpherePacket packet;
  ContactReduction lanes[kSpherePacketWidth];
  float margin[kSpherePacketWidth];
  for (std::size_t p0 = first; p0 < last; p0 += kSpherePacketWidth) {
    const std::size_t p1 = std::min(last, p0 + kSpherePacketWidth);
    packet.clear();
    for (std::size_t i = p0; i < p1; ++i) {
      const float speed2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
      const float speed = std::sqrt(speed2);
      const bool fast = s.inv_mass[i] > 0.0f && is_fast(speed2, dt, s.radius[i], fast_fraction);
      // Capped for fast spheres: a reach of hundreds of metres would gather hundreds of
      // triangles the sphere is not heading for, and bounce it from the nearest one at once.
      const float reach = fast ? (sweep_fast ? 0.0f : fast_fraction * s.radius[i]) : speed * dt;
      const std::uint32_t lane = packet.add(s.px[i], s.py[i], s.pz[i], s.radius[i] + reach);
      margin[lane] = reach;
      lanes[lane].count = 0;
    }
    query_sphere_packet_exact(bvh_, triangle_bounds_, packet, [&](std::uint32_t lane, std::uint32_t k) {
      const std::size_t i = p0 + lane;
      const float centre[3] = {s.px[i], s.py[i], s.pz[i]};
      const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]}, c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
      const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
      SphereTriangleContact st;
      if (!sphere_triangle_contact(centre, s.radius[i], a, b, c, n, t.d[k], t.internal_edges[k], margin[lane], st)) return;
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
      contact.feature = k;  // the first triangle of a merged normal names it
      lanes[lane].add(contact, centre);
    });
    for (std::uint32_t lane = 0; lane < packet.count; ++lane)
      out.insert(out.end(), lanes[lane].found, lanes[lane].found + lanes[lane].count);
  }
}

float Terrain::penetration(float x, float y, float z, float r) const {
  const TerrainTriangles& t = triangles_;
  const float centre[3] = {x, y, z};
  float deepest = 0.0f;
  query_sphere(bvh_, x, y, z, r, [&](std::uint32_t k) {
    const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]}, c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
    const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
    SphereTriangleContact st;
    if (sphere_triangle_contact(centre, r, a, b, c, n, t.d[k], t.internal_edges[k], 0.0f, st))
      deepest = std::max(deepest, -st.gap);
  });
  return deepest;
}

}  // namespace hail
