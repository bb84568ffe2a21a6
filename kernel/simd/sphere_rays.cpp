// World::raycast_batch's sphere part (SimdKernels::closest_sphere_rays), compiled once per SIMD
// path (kernel/dispatch/simd_arch.h): the walk of kernel/bvh/sphere_ray_walk.h, nodes tested as
// the scalar walk does (ray_overlaps), each leaf's spheres in lanes. The scalar reference is
// closest_sphere_scalar beside the walk.
//
// Why one ray's leaf in lanes rather than a packet of rays: the batch's rays start anywhere and
// point anywhere, so a packet would share few nodes, while a leaf holds kLeafSize spheres side by
// side in BVH order. Four lanes on every path (a leaf holds at most four spheres; eight-lane
// registers would hold half padding). The node's three slabs in lanes were tried and lost (0.71x
// of the scalar walk: the lanes' select and all-pairs compare chain is longer than the scalar
// axes' independent chains). The gain by sphere count, small because the walk's node tests take
// most of the time, is in docs/benchmarks.md (hail-bench rays, simd_gain).

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "kernel/bvh/sphere_ray_walk.h"
#include "kernel/simd/kernels.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

using leaf_batch = xsimd::batch<float, xsimd::sse4_2>;
constexpr std::uint32_t kLanes = leaf_batch::size;
static_assert(SphereQueryBvh::kLeafSize <= static_cast<int>(kLanes), "a leaf must fit the lanes");

/// test_leaf_scalar for a ray (grow 0): ray_sphere (kernel/geometry/ray_sphere.h) of the spheres
/// [first, first + kLanes) in lanes, with its operations in its order (a lane's distance has
/// its bits); the lanes that may be kept are offered in sphere order, as the scalar loop does.
void test_leaf_lanes(const SphereQueryBvh& s, const UnitRay& r, const QueryFilter& filter, std::uint32_t first,
                     std::uint32_t count, SphereRayHit& best) {
  // The last leaves may end less than kLanes before the arrays do: too few to load.
  if (first + kLanes > s.size()) return test_leaf_scalar(s, r, 0.0f, filter, first, count, best);
  const leaf_batch zero(0.0f);
  const leaf_batch ox = leaf_batch(r.o[0]) - leaf_batch::load_unaligned(&s.x[first]);
  const leaf_batch oy = leaf_batch(r.o[1]) - leaf_batch::load_unaligned(&s.y[first]);
  const leaf_batch oz = leaf_batch(r.o[2]) - leaf_batch::load_unaligned(&s.z[first]);
  const leaf_batch radius = leaf_batch::load_unaligned(&s.r[first]);
  const leaf_batch c = ox * ox + oy * oy + oz * oz - radius * radius;
  const leaf_batch b = ox * leaf_batch(r.d[0]) + oy * leaf_batch(r.d[1]) + oz * leaf_batch(r.d[2]);
  const leaf_batch disc = b * b - c;
  const leaf_batch entry = -b - xsimd::sqrt(disc);
  const auto inside = c <= zero;
  const auto enters = (b < zero) && (disc >= zero);
  const leaf_batch t = xsimd::select(inside, zero, xsimd::select(entry >= zero, entry, zero));
  // A prefilter only (best.t shrinks as lanes are kept): offer_sphere decides.
  const auto near = (inside || enters) && (t < leaf_batch(r.max)) && (t <= leaf_batch(best.t));
  std::uint32_t lanes = lane_bits(near) & ((1u << count) - 1u);
  if (lanes == 0) return;
  alignas(16) float distance[kLanes];
  t.store_aligned(distance);
  for (; lanes != 0; lanes &= lanes - 1) {
    const std::uint32_t lane = lowest_lane(lanes), k = first + lane;
    if (sphere_passes(s, k, filter)) offer_sphere(s, k, distance[lane], r.max, best);
  }
}

}  // namespace

void closest_sphere_rays(const SphereQueryBvh& s, const UnitRay* rays, std::size_t count, const QueryFilter& filter,
                         SphereRayHit* hits) {
  for (std::size_t i = 0; i < count; ++i) {
    const UnitRay& r = rays[i];
    const float inv[3] = {1.0f / r.d[0], 1.0f / r.d[1], 1.0f / r.d[2]};
    hits[i] = walk_sphere_ray(
        s, r.max, [&](const FlatNode& n, float best_t) { return ray_overlaps(n, r.o, inv, best_t, 0.0f); },
        [&](std::uint32_t first, std::uint32_t count, SphereRayHit& best) {
          test_leaf_lanes(s, r, filter, first, count, best);
        });
  }
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
