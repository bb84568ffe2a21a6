// Terrain::find_contacts (include/hail/terrain.h) by the packet walk (kernel/bvh/bvh_packet_walk.h): a
// batch of spheres goes down the stackless walk together, each leaf's triangle boxes and then
// planes tested for all lanes at once; the (sphere, triangle) candidates that pass are then
// tested a batch at a time (kernel/simd/sphere_triangle_lanes.h). Compiled once per SIMD path (kernel/dispatch/simd_arch.h);
// the scalar reference is Terrain::find_contacts_scalar, and both share kernel/terrain/terrain_contacts.h.
// Meshes (MeshCollider::find_contacts) take the same walk with their own contact rule
// (kernel/mesh/mesh_contact.h); their scalar reference is MeshCollider::find_contacts_scalar.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include <algorithm>

#include "kernel/bvh/bvh_packet_walk.h"
#include "kernel/mesh/mesh_collider.h"
#include "kernel/mesh/mesh_contact.h"
#include "kernel/simd/compress_lanes.h"
#include "kernel/simd/gather.h"
#include "kernel/simd/kernels.h"
#include "kernel/simd/sphere_triangle_lanes.h"
#include "kernel/terrain/terrain_contacts.h"
#include "kernel/terrain/terrain_parts.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

namespace {

using batch = xsimd::batch<float, simd_arch>;
using index_batch = xsimd::batch<std::int32_t, simd_arch>;
constexpr std::uint32_t W = kSpherePacketWidth;
static_assert(W < 32, "lane masks are uint32");

/// One packet's (lane, triangle) candidates from the walk, in the walk's order, tested a batch at
/// a time: per lane, the triangles come in query_sphere's order, as the scalar reference sees them.
struct TerrainCandidates {
  static constexpr std::uint32_t kCapacity = 16 * W;  // a multiple of W; a full buffer is tested at once
  static_assert(kCapacity >= kMaxLeafSize * W, "an empty buffer must hold a whole leaf (PacketWalkExact)");
  alignas(64) std::int32_t lane[kCapacity];
  alignas(64) std::int32_t triangle[kCapacity];
  alignas(64) float height[kCapacity];  ///< the sphere centre's height over the triangle's plane
  std::uint32_t count = 0;
};

/// Appends (lane, k, height[lane]) for each set lane of `lanes`, lowest lane first, at
/// candidate `at` of c, which must have room for W; returns how many. No branch on the lanes
/// (kernel/simd/compress_lanes.h).
[[gnu::always_inline]] inline std::uint32_t append_candidates(TerrainCandidates& c, std::uint32_t at,
                                                              std::uint32_t lanes, std::uint32_t k,
                                                              const batch& height) {
  alignas(64) float by_lane[W];
  height.store_aligned(by_lane);
  index_batch(static_cast<std::int32_t>(k)).store_unaligned(c.triangle + at);
  compress_lanes(reinterpret_cast<std::int32_t*>(c.height + at), reinterpret_cast<const std::int32_t*>(by_lane), lanes);
  return compress_lanes(c.lane + at, kLaneNumbers, lanes);
}

/// What the candidates' tests read of a packet's spheres beside SpherePacket's centres, by lane.
struct PacketSpheres {
  alignas(64) float radius[W] = {};  // lanes past a packet's spheres: read, never used
  alignas(64) float margin[W] = {};
  std::size_t first_sphere = 0;  ///< lane l is sphere first_sphere + l
};

/// Tests candidates [0, c.count) and empties the buffer: sphere_triangle_contact's first half for
/// a batch at a time (kernel/simd/sphere_triangle_lanes.h; its plane test was done by the walk,
/// which kept the heights), then, for the lanes within reach, its second half and the contact
/// into the lane's reduction, in candidate order.
template <class Rule>
void test_candidates(TerrainCandidates& c, const SpherePacket& packet, const PacketSpheres& p, const Rule& rule,
                     const SphereSoA& s, ContactReduction* lanes) {
  const TerrainTriangles& t = rule.triangles;
  alignas(64) float px[W], py[W], pz[W], region[W], distance[W], height[W];
  for (std::uint32_t o = 0; o < c.count; o += W) {
    std::uint32_t valid = (1u << std::min(W, c.count - o)) - 1u;
    if (c.count - o < W)  // inert lanes: sphere 0 against triangle 0, masked out below
      for (std::uint32_t l = c.count - o; l < W; ++l) c.lane[o + l] = 0, c.triangle[o + l] = 0, c.height[o + l] = 0.0f;
    const index_batch lane = index_batch::load_aligned(c.lane + o), k = index_batch::load_aligned(c.triangle + o);
    const batch q[3] = {pick_lanes(packet.cx, lane), pick_lanes(packet.cy, lane), pick_lanes(packet.cz, lane)};
    const batch radius = pick_lanes(p.radius, lane), max_gap = pick_lanes(p.margin, lane);
    const batch h = batch::load_aligned(c.height + o);
    const batch a[3] = {gather_floats(t.v0x.data(), k), gather_floats(t.v0y.data(), k), gather_floats(t.v0z.data(), k)};
    const batch b[3] = {gather_floats(t.v1x.data(), k), gather_floats(t.v1y.data(), k), gather_floats(t.v1z.data(), k)};
    const batch v2[3] = {gather_floats(t.v2x.data(), k), gather_floats(t.v2y.data(), k),
                         gather_floats(t.v2z.data(), k)};
    const ClosestPointLanes closest = closest_points_on_triangles(q, a, b, v2);
    const batch d[3] = {closest.p[0] - q[0], closest.p[1] - q[1], closest.p[2] - q[2]};
    const batch dist = xsimd::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    valid &= lane_bits(!(dist - radius > max_gap));
    if (valid == 0) continue;
    closest.p[0].store_aligned(px), closest.p[1].store_aligned(py), closest.p[2].store_aligned(pz);
    closest.region.store_aligned(region), dist.store_aligned(distance), h.store_aligned(height);
    for (; valid != 0; valid &= valid - 1) {
      const std::uint32_t l = lowest_lane(valid);
      const std::uint32_t sphere_lane = static_cast<std::uint32_t>(c.lane[o + l]);
      const std::uint32_t tri = static_cast<std::uint32_t>(c.triangle[o + l]);
      const std::size_t i = p.first_sphere + sphere_lane;
      const float centre[3] = {packet.cx[sphere_lane], packet.cy[sphere_lane], packet.cz[sphere_lane]};
      const TrianglePoint at{{px[l], py[l], pz[l]}, static_cast<TriangleRegion>(static_cast<int>(region[l]))};
      const float to[3] = {at.p[0] - centre[0], at.p[1] - centre[1], at.p[2] - centre[2]};
      const float normal[3] = {t.nx[tri], t.ny[tri], t.nz[tri]};
      const float corner0[3] = {t.v0x[tri], t.v0y[tri], t.v0z[tri]}, corner1[3] = {t.v1x[tri], t.v1y[tri], t.v1z[tri]},
                  corner2[3] = {t.v2x[tri], t.v2y[tri], t.v2z[tri]};
      SphereTriangleContact st;
      if (rule.finish(centre, s.radius[i], at, to, distance[l], height[l], normal, t.d[tri], t.internal_edges[tri],
                      corner0, corner1, corner2, st))
        add_terrain_contact(s, i, st, rule.feature(tri), rule.restitution, rule.friction, lanes[sphere_lane]);
    }
  }
  c.count = 0;
}

/// The terrain's rule: a heightfield, solid below (kernel/geometry/sphere_triangle.h).
struct TerrainRule {
  const TerrainTriangles& triangles;
  float restitution, friction;
  /// Lanes whose centre's height h over the triangle's plane leaves the triangle within reach.
  [[nodiscard]] std::uint32_t within_reach(const batch& h, const batch& radius, const batch& max_gap) const {
    return lane_bits(!(h - radius > max_gap));
  }
  [[nodiscard]] bool finish(const float centre[3], float radius, const TrianglePoint& at, const float to[3],
                            float distance, float height, const float normal[3], float d, std::uint8_t internal,
                            const float a[3], const float b[3], const float c[3], SphereTriangleContact& st) const {
    return contact_from_closest_point(centre, radius, at, to, distance, height, normal, d, internal, a, b, c, st);
  }
  [[nodiscard]] std::uint32_t feature(std::uint32_t k) const { return k; }
};

/// A mesh's rule (sphere_mesh_triangle_contact, kernel/mesh/mesh_contact.h): a shell meets the
/// face the centre is in front of; a solid pushes a centre out from up to a radius behind.
struct MeshRule {
  const TerrainTriangles& triangles;
  float restitution, friction;
  bool two_sided;
  std::uint32_t first_feature;
  [[nodiscard]] std::uint32_t within_reach(const batch& h, const batch& radius, const batch& max_gap) const {
    const batch height = two_sided ? xsimd::abs(h) : h;
    return lane_bits(!(height - radius > max_gap)) & lane_bits(!(height < -radius));
  }
  [[nodiscard]] bool finish(const float centre[3], float radius, const TrianglePoint& at, const float to[3],
                            float distance, float height, const float normal[3], float d, std::uint8_t internal,
                            const float a[3], const float b[3], const float c[3], SphereTriangleContact& st) const {
    return mesh_contact_from_closest_point(centre, radius, at, to, distance, height, normal, d, internal, two_sided, a,
                                           b, c, st);
  }
  [[nodiscard]] std::uint32_t feature(std::uint32_t k) const { return kMeshFeature | (first_feature + k); }
};

/// Spheres [first, last) through the BVH a packet at a time, each candidate by `rule`.
template <class Rule>
void packet_contacts(const FlatBvh& bvh, std::span<const Aabb> bounds, const Rule& rule, const SphereSoA& s,
                     std::size_t first, std::size_t last, float dt, std::vector<Contact>& out, float fast_fraction,
                     bool sweep_fast) {
  const TerrainTriangles& t = rule.triangles;
  SpherePacket packet;
  PacketSpheres spheres;
  TerrainCandidates candidates;
  ContactReduction lanes[W];
  Contact found[W * kMaxTerrainContactsPerSphere];
  for (std::size_t p0 = first; p0 < last; p0 += W) {
    const std::size_t p1 = last - p0 < W ? last : p0 + W;
    packet.clear();
    spheres.first_sphere = p0;
    for (std::size_t i = p0; i < p1; ++i) {
      const float reach = terrain_contact_reach(s, i, dt, fast_fraction, sweep_fast);
      const std::uint32_t lane = packet.add(s.px[i], s.py[i], s.pz[i], s.radius[i] + reach);
      spheres.radius[lane] = s.radius[i], spheres.margin[lane] = reach;
      lanes[lane].count = 0;
    }
    // sphere_triangle_contact's plane test, for all lanes against each triangle its box test
    // passes: the triangle's plane is one broadcast here, where a candidate's is four gathers,
    // and about a third of the box hits end at it. The same float operations as the scalar
    // reference's sphere_triangle_contact, so the same candidates pass.
    const batch cx = batch::load_aligned(packet.cx), cy = batch::load_aligned(packet.cy),
                cz = batch::load_aligned(packet.cz);
    const batch radius = batch::load_aligned(spheres.radius), max_gap = batch::load_aligned(spheres.margin);
    // The walk stops when the buffer could overflow at the next leaf; the buffer is tested and
    // emptied here, outside the walk's loop (PacketWalkExact).
    PacketWalkExact walk(bvh, bounds, packet);
    while (!walk.done()) {
      walk.run_masks(
          [&](std::uint32_t lanes, std::uint32_t k) {
            const batch h = (batch(t.nx[k]) * cx + batch(t.ny[k]) * cy + batch(t.nz[k]) * cz) - batch(t.d[k]);
            lanes &= rule.within_reach(h, radius, max_gap);
            candidates.count += append_candidates(candidates, candidates.count, lanes, k, h);
          },
          [&] { return TerrainCandidates::kCapacity - candidates.count; });
      if (candidates.count > 0) test_candidates(candidates, packet, spheres, rule, s, lanes);
    }
    // In sphere order, as the scalar walk gives them.
    std::size_t count = 0;
    for (std::uint32_t lane = 0; lane < packet.count; ++lane)
      for (int m = 0; m < lanes[lane].count; ++m) found[count++] = lanes[lane].found[m];
    if (count > 0) append_contacts(out, found, count);
  }
}

}  // namespace

void terrain_contacts(const Terrain& terrain, const SphereSoA& s, std::size_t first, std::size_t last, float dt,
                      float restitution, float friction, std::vector<Contact>& out, float fast_fraction,
                      bool sweep_fast) {
  const std::span<const Aabb> bounds(terrain.triangle_bounds().data(), terrain.triangle_bounds().size());
  packet_contacts(terrain.bvh(), bounds, TerrainRule{terrain.triangles(), restitution, friction}, s, first, last, dt,
                  out, fast_fraction, sweep_fast);
}

void mesh_contacts(const MeshCollider& mesh, const SphereSoA& s, std::size_t first, std::size_t last, float dt,
                   std::vector<Contact>& out, float fast_fraction, bool sweep_fast) {
  packet_contacts(mesh.bvh, std::span<const Aabb>(mesh.bounds),
                  MeshRule{mesh.triangles, mesh.restitution, mesh.friction, mesh.two_sided, mesh.first_feature}, s,
                  first, last, dt, out, fast_fraction, sweep_fast);
}

namespace {

template <class Count>
std::uint64_t count_hits(const FlatBvh& bvh, const Aabb* bounds, const float* x, const float* y, const float* z,
                         const float* r, std::size_t count, PacketLeafTest test, Count&& count_node) {
  const std::span<const Aabb> boxes(bounds, bvh.primitive_count());
  std::uint64_t hits = 0;
  SpherePacket packet;
  for (std::size_t first = 0; first < count; first += kSpherePacketWidth) {
    const std::size_t n = count - first < kSpherePacketWidth ? count - first : kSpherePacketWidth;
    packet.clear();
    for (std::size_t k = first; k < first + n; ++k) packet.add(x[k], y[k], z[k], r[k]);
    // A counter local to the packet stays in a register through the walk; one outside the loop
    // made every query slower (docs/benchmarks.md, "Figures behind the code's choices").
    std::uint32_t packet_hits = 0;
    if (test == PacketLeafTest::LeafBoxes) {
      // Each primitive's lanes counted at once, as the terrain kernel appends them at once.
      query_sphere_packet_exact_masks(
          bvh, boxes, packet,
          [&](std::uint32_t lanes, std::uint32_t) {
            packet_hits += static_cast<std::uint32_t>(__builtin_popcount(lanes));
          },
          count_node);
    } else {
      query_sphere_packet(
          bvh, packet,
          [&](std::uint32_t lane, std::uint32_t k) {
            const std::size_t q = first + lane;
            packet_hits += sphere_overlaps(bounds[k], x[q], y[q], z[q], r[q]);
          },
          count_node);
    }
    hits += packet_hits;
  }
  return hits;
}

}  // namespace

std::uint64_t count_packet_hits(const FlatBvh& bvh, const Aabb* bounds, const float* x, const float* y, const float* z,
                                const float* r, std::size_t count, PacketLeafTest test, std::uint64_t* nodes_tested) {
  // Without a node count the walk carries none (NoNodeCount compiles to nothing).
  if (nodes_tested == nullptr) return count_hits(bvh, bounds, x, y, z, r, count, test, NoNodeCount{});
  NodeVisitCount visits;
  const std::uint64_t hits = count_hits(bvh, bounds, x, y, z, r, count, test, visits);
  *nodes_tested += visits.visited;
  return hits;
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
