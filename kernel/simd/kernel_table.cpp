// This SIMD path's SimdKernels table (kernel/dispatch/kernel_table.h). Compiled once per path.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "kernel/simd/kernels.h"

namespace hail {
namespace {

#if defined(HAIL_SIMD_PATH_SSE4_2)
constexpr SimdPath kPath = SimdPath::Sse42;
#elif defined(HAIL_SIMD_PATH_AVX2)
constexpr SimdPath kPath = SimdPath::Avx2;
#elif defined(HAIL_SIMD_PATH_AVX512)
constexpr SimdPath kPath = SimdPath::Avx512;
#else
#error "kernel/simd/ is compiled once per SIMD path (cmake/HailSimdPaths.cmake), with HAIL_SIMD_PATH_* defined"
#endif

constexpr SimdKernels kTable{
    .path = kPath,
    .width = xsimd::batch<float, simd_arch>::size,
    .find_sphere_pairs = &HAIL_SIMD_NS::find_sphere_pairs,
    .sorted_axis_find_pairs = &HAIL_SIMD_NS::sorted_axis_find_pairs,
    .grid_find_pairs = &HAIL_SIMD_NS::grid_find_pairs,
    .contact_collision = &HAIL_SIMD_NS::contact_collision,
    .contact_warm_start = &HAIL_SIMD_NS::contact_warm_start,
    .contact_resting = &HAIL_SIMD_NS::contact_resting,
    .contact_soft = &HAIL_SIMD_NS::contact_soft,
    .contact_depenetrate = &HAIL_SIMD_NS::contact_depenetrate,
    .terrain_contacts = &HAIL_SIMD_NS::terrain_contacts,
    .mesh_contacts = &HAIL_SIMD_NS::mesh_contacts,
    .terrain_push_out = &HAIL_SIMD_NS::terrain_push_out,
    .integrate_free = &HAIL_SIMD_NS::integrate_free,
    .scan_path_boxes = &HAIL_SIMD_NS::scan_path_boxes,
    .count_packet_hits = &HAIL_SIMD_NS::count_packet_hits,
    .closest_points = &HAIL_SIMD_NS::closest_points,
    .closest_sphere_rays = &HAIL_SIMD_NS::closest_sphere_rays,
};
static_assert(kTable.width == (kPath == SimdPath::Sse42 ? 4 : kPath == SimdPath::Avx2 ? 8 : 16));

}  // namespace

#if defined(HAIL_SIMD_PATH_SSE4_2)
const SimdKernels& simd_kernels_sse4_2() { return kTable; }
#elif defined(HAIL_SIMD_PATH_AVX2)
const SimdKernels& simd_kernels_avx2() { return kTable; }
#else
const SimdKernels& simd_kernels_avx512() { return kTable; }
#endif

}  // namespace hail
