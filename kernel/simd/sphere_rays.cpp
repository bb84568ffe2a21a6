// World::raycast_batch's sphere part (SimdKernels::closest_sphere_rays), compiled once per SIMD
// path (kernel/dispatch/simd_arch.h): the walk of kernel/bvh/sphere_ray_walk.h with each leaf's
// spheres tested in lanes. The scalar reference is closest_sphere_scalar beside the walk.
//
// Why leaves in lanes: the batch's rays start anywhere and point anywhere, so a packet of rays
// would share few nodes, while one ray's leaf holds kLeafSize spheres side by side in BVH order.
// Four lanes on every path (a leaf holds at most four spheres; eight-lane registers would hold
// half padding). What pays is less the four tests at once than the branches gone: the scalar
// test's early outs (outside, moving away, passing by) go either way at random.

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

/// ray_overlaps (kernel/geometry/aabb.h, grow 0) of one node, its three axes in lanes: the
/// same products, swaps and rounding allowance per axis, so the same answer. The scalar code
/// folds the entries into t0 (from 0) and the exits into t1 (from t_max), a NaN leaving either
/// unchanged, and asks t0 <= t1: here every entry (NaN as 0) against every exit (NaN as
/// t_max), by rotating the exits. Lane 3 holds the node's skip and leaf words: it is set to
/// (0, t_max), which changes nothing.
bool ray_overlaps_lanes(const FlatNode& n, __m128 origin, __m128 inv_dir, float t_max) {
  constexpr float kTwoGamma3 = 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);  // as ray_overlaps
  const __m128 zero = _mm_setzero_ps(), limit = _mm_set1_ps(t_max);
  const __m128 near = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.min), origin), inv_dir);
  const __m128 far = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.max), origin), inv_dir);
  const __m128 swap = _mm_cmpgt_ps(near, far);
  __m128 entry = _mm_blendv_ps(near, far, swap);
  __m128 exit = _mm_blendv_ps(far, near, swap);
  const __m128 magnitude = _mm_andnot_ps(_mm_set1_ps(-0.0f), exit);
  exit = _mm_add_ps(exit, _mm_mul_ps(magnitude, _mm_set1_ps(kTwoGamma3)));
  entry = _mm_and_ps(entry, _mm_cmpgt_ps(entry, zero));          // t0 = near > t0 ? near : t0
  exit = _mm_blendv_ps(limit, exit, _mm_cmplt_ps(exit, limit));  // t1 = far < t1 ? far : t1
  entry = _mm_blend_ps(entry, zero, 0x8);
  exit = _mm_blend_ps(exit, limit, 0x8);
  __m128 ok = _mm_cmple_ps(entry, exit);
  ok = _mm_and_ps(ok, _mm_cmple_ps(entry, _mm_shuffle_ps(exit, exit, _MM_SHUFFLE(0, 3, 2, 1))));
  ok = _mm_and_ps(ok, _mm_cmple_ps(entry, _mm_shuffle_ps(exit, exit, _MM_SHUFFLE(1, 0, 3, 2))));
  ok = _mm_and_ps(ok, _mm_cmple_ps(entry, _mm_shuffle_ps(exit, exit, _MM_SHUFFLE(2, 1, 0, 3))));
  return _mm_movemask_ps(ok) == 0xF;
}

}  // namespace

void closest_sphere_rays(const SphereQueryBvh& s, const UnitRay* rays, std::size_t count, const QueryFilter& filter,
                         SphereRayHit* hits) {
  for (std::size_t i = 0; i < count; ++i) {
    const UnitRay& r = rays[i];
    const __m128 origin = _mm_setr_ps(r.o[0], r.o[1], r.o[2], 0.0f);
    const __m128 inv_dir = _mm_setr_ps(1.0f / r.d[0], 1.0f / r.d[1], 1.0f / r.d[2], 0.0f);
    hits[i] = walk_sphere_ray(
        s, r.max, [&](const FlatNode& n, float best_t) { return ray_overlaps_lanes(n, origin, inv_dir, best_t); },
        [&](std::uint32_t first, std::uint32_t count, SphereRayHit& best) {
          test_leaf_lanes(s, r, filter, first, count, best);
        });
  }
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
