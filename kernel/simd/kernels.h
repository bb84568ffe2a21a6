#pragma once
// The kernels of one SIMD path, declared in that path's namespace (kernel/dispatch/simd_arch.h), which
// kernel/simd/kernel_table.cpp collects into its SimdKernels table. Only the translation units
// of kernel/simd/, compiled once per path by kernel/CMakeLists.txt (HAIL_SIMD_PATH_* defined),
// include this; elsewhere it declares functions of namespace simd_base that nothing defines.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernel/dispatch/kernel_table.h"
#include "kernel/dispatch/simd_arch.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

void find_sphere_pairs(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                       std::vector<SpherePair>& out);
void sorted_axis_find_pairs(const SortedAxisPairsView& sweep, const SphereSoA& spheres, std::size_t first,
                            std::size_t last, float margin, std::vector<SpherePair>& out,
                            std::vector<std::uint32_t>& row);
void grid_find_pairs(const SphereGridView& grid, const SphereSoA& spheres, std::size_t first, std::size_t last,
                     float margin, std::vector<SpherePair>& out, std::vector<std::uint32_t>& row);
bool contact_collision(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                       std::size_t body_count, float dt, float restitution_threshold, std::uint32_t pass,
                       FrictionWork work, const float* gravity_dt);
void contact_warm_start(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                        std::size_t body_count, FrictionWork work);
void contact_resting(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                     std::size_t body_count, float inv_dt, FrictionWork work);
void contact_soft(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                  std::size_t body_count, const SoftPass& pass, FrictionWork work);
bool contact_depenetrate(const ContactBatchArrays& batches, std::size_t first, std::size_t last,
                         const DepenetrationArrays& spheres, std::uint32_t now, std::uint32_t previous);
void terrain_contacts(const Terrain& terrain, const SphereSoA& spheres, std::size_t first, std::size_t last, float dt,
                      float restitution, float friction, std::vector<Contact>& out, float fast_fraction,
                      bool sweep_fast);
void mesh_contacts(const MeshCollider& mesh, const SphereSoA& spheres, std::size_t first, std::size_t last, float dt,
                   std::vector<Contact>& out, float fast_fraction, bool sweep_fast);
std::size_t terrain_push_out(const Terrain& terrain, SphereSoA& spheres, const std::uint32_t* slots, std::size_t count);
void integrate_free(SphereSoA& spheres, std::size_t first, std::size_t last, const IntegrationParams& params,
                    const std::uint8_t* skip);
void scan_path_boxes(const SphereSoA& spheres, const PathBox& box, float t0, float t1, SlotSink sink);
void closest_points(const TriangleQueries& queries, std::size_t count, float* const p[3], std::uint8_t* region);
std::uint64_t count_packet_hits(const FlatBvh& bvh, const Aabb* bounds, const float* x, const float* y, const float* z,
                                const float* r, std::size_t count, PacketLeafTest test, std::uint64_t* nodes_tested);
void closest_sphere_rays(const SphereQueryBvh& spheres, const UnitRay* rays, std::size_t count,
                         const QueryFilter& filter, SphereRayHit* hits);

}  // namespace HAIL_SIMD_NS
}  // namespace hail
