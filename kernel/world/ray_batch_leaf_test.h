#pragma once
// How World::raycast_batch tests a sphere-BVH leaf (kernel/world/world_queries.cpp): in SIMD
// lanes (SimdKernels::closest_sphere_rays, the default) or with the scalar reference
// (closest_sphere_scalar, kernel/bvh/sphere_ray_walk.h). Both give the same bits; the switch
// is for hail-bench rays, which times both in one run, and for the tests. Process-wide, like the
// SIMD path; not part of the public API.

#include <cstdint>

namespace hail {

enum class RayBatchLeafTest : std::uint8_t { Simd, Scalar };

void set_ray_batch_leaf_test(RayBatchLeafTest test);
[[nodiscard]] RayBatchLeafTest ray_batch_leaf_test();

}  // namespace hail
