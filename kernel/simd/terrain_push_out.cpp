// Terrain::push_out_spheres (include/hail/terrain.h): the terrain guard's spheres pushed out of the
// ground a packet at a time. The first round of Terrain::push_out (the scalar reference) is a
// BVH walk per sphere; here the packet walk (kernel/bvh/bvh_packet_walk.h) serves a packet of them,
// each lane seeing the same triangles in the same order as its own walk would, so each finds
// the same deepest triangle. The few spheres that move then finish their later rounds with the
// scalar push_out, exactly as its loop would have continued. Compiled once per SIMD path
// (kernel/dispatch/simd_arch.h).
//
// Why packets: the guard's spheres (those that moved further than their contacts reached, a
// few in each step) walked the tree one by one, and that walk's node loads missed the cache
// (perf: docs/benchmarks.md, "Figures behind the code's choices").

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "hail/sphere_soa.h"
#include "kernel/bvh/bvh_packet_walk.h"
#include "kernel/geometry/sphere_triangle.h"
#include "kernel/simd/kernels.h"
#include "kernel/terrain/terrain_parts.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

std::size_t terrain_push_out(const Terrain& terrain, SphereSoA& s, const std::uint32_t* slots, std::size_t count) {
  const TerrainTriangles& t = terrain.triangles();
  constexpr std::uint32_t W = kSpherePacketWidth;
  std::size_t moved = 0;
  SpherePacket packet;
  for (std::size_t p0 = 0; p0 < count; p0 += W) {
    const std::size_t n = count - p0 < W ? count - p0 : W;
    packet.clear();
    for (std::size_t l = 0; l < n; ++l) {
      const std::uint32_t i = slots[p0 + l];
      packet.add(s.px[i], s.py[i], s.pz[i], s.radius[i]);
    }
    // Round 1 of push_out for every lane: the deepest overlapping triangle, strictly deeper
    // winning, so the first of equals in the lane's walk order is kept, as there.
    SphereTriangleContact deepest[W];
    for (std::size_t l = 0; l < n; ++l) deepest[l].gap = 0.0f;
    query_sphere_packet(terrain.bvh(), packet, [&](std::uint32_t lane, std::uint32_t k) {
      const float centre[3] = {packet.cx[lane], packet.cy[lane], packet.cz[lane]};
      const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]};
      const float c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
      const float normal[3] = {t.nx[k], t.ny[k], t.nz[k]};
      SphereTriangleContact st;
      if (sphere_triangle_contact(centre, s.radius[slots[p0 + lane]], a, b, c, normal, t.d[k], t.internal_edges[k],
                                  0.0f, st) &&
          st.gap < deepest[lane].gap)
        deepest[lane] = st;
    });
    for (std::size_t l = 0; l < n; ++l) {
      if (!(deepest[l].gap < 0.0f)) continue;
      const std::uint32_t i = slots[p0 + l];
      // push_out's move, then its remaining rounds from there.
      s.px[i] += deepest[l].n[0] * deepest[l].gap;
      s.py[i] += deepest[l].n[1] * deepest[l].gap;
      s.pz[i] += deepest[l].n[2] * deepest[l].gap;
      terrain.push_out(s.px[i], s.py[i], s.pz[i], s.radius[i], Terrain::kPushOutRounds - 1);
      ++moved;
    }
  }
  return moved;
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
