#pragma once
// The SIMD kernels of one path as a table of plain function pointers. kernel/simd/*.cpp are
// compiled once per path (SSE4.2, AVX2, AVX-512: kernel/CMakeLists.txt), each copy in its own
// namespace (kernel/dispatch/simd_arch.h), and kernel/simd/kernel_table.cpp fills one table per copy.
// simd_kernels() is the active path's table (kernel/dispatch/simd_dispatch.h picks it); callers call
// through it once per block of work (a row block, a contact chunk, a sphere block, one path
// scan), never per sphere.
//
// What a kernel produces goes out through the small non-inline functions below, compiled at
// the base level: the per-path code never grows a std::vector or sorts one itself, because
// those templates would be compiled with the path's instructions and could be merged with the
// base copies by the linker (the trap kernel/dispatch/simd_arch.h describes).
//
// The scalar references stay beside the kernels' callers (find_sphere_pairs_scalar,
// SphereGrid::find_pairs_scalar,
// solve_*_run_scalar, soft_run_scalar, Terrain::find_contacts_scalar, scan_path_boxes_scalar, query_sphere,
// integrate_free_scalar,
// closest_sphere_scalar,
// closest_point_on_triangle), and
// tests/test_simd_dispatch.cpp compares every path with them.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hail/contact.h"
#include "kernel/dispatch/simd_dispatch.h"

namespace hail {

// Declared only: the table sits below the layers that define them (kernel/geometry/aabb.h,
// kernel/solver/contact_impulse.h).
struct Aabb;
enum FrictionWork : std::uint8_t;
class SphereSoA;
class Terrain;
struct MeshCollider;
struct FlatBvh;
struct PathBox;
struct SolverBody;
struct SpherePair;
struct SortedAxisPairsView;
struct SphereGridView;
struct ContactBatchArrays;
struct DepenetrationArrays;
struct SoftPass;
struct IntegrationParams;
struct SphereQueryBvh;
struct UnitRay;
struct SphereRayHit;
struct QueryFilter;

/// Where a kernel hands a run of sphere slots: fn(context, slots, count), in slot order.
struct SlotSink {
  void (*fn)(void* context, const std::uint32_t* slots, std::size_t count);
  void* context;
};

/// A SlotSink that calls visit(slot) for each slot (visit must outlive the call).
template <class Visit>
[[nodiscard]] SlotSink slot_sink(Visit& visit) {
  return {[](void* context, const std::uint32_t* slots, std::size_t count) {
            Visit& v = *static_cast<Visit*>(context);
            for (std::size_t k = 0; k < count; ++k) v(slots[k]);
          },
          &visit};
}

/// What count_packet_hits counts.
enum class PacketLeafTest : std::uint8_t {
  LeafCandidates,  ///< the packet walk hands each touched leaf to its lanes; each (lane, primitive) is box-tested in scalar code
  LeafBoxes,  ///< the leaf's primitive boxes are tested for all lanes at once (query_sphere_packet_exact)
};

/// Points and triangles (a, b, c), SoA: closest_points' input.
struct TriangleQueries {
  const float* q[3];
  const float *a[3], *b[3], *c[3];
};

struct SimdKernels {
  SimdPath path;
  std::size_t width;  ///< floats per batch: contacts per staged batch, spheres per packet

  /// find_sphere_pairs_simd (kernel/broadphase/sphere_pairs.h).
  void (*find_sphere_pairs)(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                            std::vector<SpherePair>& out);
  /// SortedAxisPairs::find_pairs (kernel/broadphase/sorted_axis_pairs.h); `row` comes in empty and leaves empty.
  void (*sorted_axis_find_pairs)(const SortedAxisPairsView& sweep, const SphereSoA& spheres, std::size_t first,
                                 std::size_t last, float margin, std::vector<SpherePair>& out,
                                 std::vector<std::uint32_t>& row);
  /// SphereGrid::find_pairs (kernel/broadphase/sphere_grid.h); `row` comes in empty and leaves empty.
  void (*grid_find_pairs)(const SphereGridView& grid, const SphereSoA& spheres, std::size_t first, std::size_t last,
                          float margin, std::vector<SpherePair>& out, std::vector<std::uint32_t>& row);
  /// ContactBatches::solve_collision, warm_start, solve_resting (kernel/solver/contact_solve_simd.h);
  /// `bodies` holds body_count bodies, the last of them the static one.
  bool (*contact_collision)(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                            std::size_t body_count, float dt, float restitution_threshold, std::uint32_t pass,
                            FrictionWork work, const float* gravity_dt);
  void (*contact_warm_start)(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                             std::size_t body_count, FrictionWork work);
  void (*contact_resting)(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                          std::size_t body_count, float inv_dt, FrictionWork work);
  /// ContactBatches::solve_soft (kernel/solver/contact_solve_simd.h): one pass of the soft step.
  void (*contact_soft)(const ContactBatchArrays& batches, std::size_t first, std::size_t last, SolverBody* bodies,
                       std::size_t body_count, const SoftPass& pass, FrictionWork work);
  /// ContactBatches::depenetrate (kernel/solver/contact_solve_simd.h).
  bool (*contact_depenetrate)(const ContactBatchArrays& batches, std::size_t first, std::size_t last,
                              const DepenetrationArrays& spheres, std::uint32_t now, std::uint32_t previous);
  /// Terrain::find_contacts (include/hail/terrain.h): the packet walk and the sphere-triangle tests.
  void (*terrain_contacts)(const Terrain& terrain, const SphereSoA& spheres, std::size_t first, std::size_t last,
                           float dt, float restitution, float friction, std::vector<Contact>& out, float fast_fraction,
                           bool sweep_fast);
  /// MeshCollider::find_contacts (kernel/mesh/mesh_collider.h): the terrain's packet walk with a
  /// mesh's contact rule (kernel/mesh/mesh_contact.h).
  void (*mesh_contacts)(const MeshCollider& mesh, const SphereSoA& spheres, std::size_t first, std::size_t last,
                        float dt, std::vector<Contact>& out, float fast_fraction, bool sweep_fast);
  /// Terrain::push_out_spheres (include/hail/terrain.h): the spheres at slots[0, count).
  std::size_t (*terrain_push_out)(const Terrain& terrain, SphereSoA& spheres, const std::uint32_t* slots,
                                  std::size_t count);
  /// integrate_positions without planes (kernel/solver/integrate.h), spheres [first, last) in
  /// batches; skip[i] != 0: moved already (null: none). The same bits as integrate_free_scalar.
  void (*integrate_free)(SphereSoA& spheres, std::size_t first, std::size_t last, const IntegrationParams& params,
                         const std::uint8_t* skip);
  /// scan_path_boxes_simd (kernel/ccd/path_box_scan.h): the slots go to `sink`, in slot order.
  void (*scan_path_boxes)(const SphereSoA& spheres, const PathBox& box, float t0, float t1, SlotSink sink);
  /// The packet walk for hail-bench query, hail-micro and the tests: spheres [0, count) in
  /// packets of `width`; returns how many (sphere, primitive) pairs pass the box test
  /// sphere_overlaps(bounds[k], ...) (bounds in BVH order), and adds the nodes tested, once
  /// per packet, to *nodes_tested when it is not null.
  std::uint64_t (*count_packet_hits)(const FlatBvh& bvh, const Aabb* bounds, const float* x, const float* y,
                                     const float* z, const float* r, std::size_t count, PacketLeafTest test,
                                     std::uint64_t* nodes_tested);
  /// For the tests: closest_point_on_triangle (kernel/geometry/sphere_triangle.h) of queries [0, count)
  /// by the batch code of the terrain kernel (kernel/simd/sphere_triangle_lanes.h): the point
  /// into p[0..2], the TriangleRegion into region.
  void (*closest_points)(const TriangleQueries& queries, std::size_t count, float* const p[3], std::uint8_t* region);
  /// World::raycast_batch's sphere part (kernel/bvh/sphere_ray_walk.h): the closest sphere of
  /// each of rays[0, count), each leaf's spheres tested in lanes; the same bits as
  /// closest_sphere_scalar.
  void (*closest_sphere_rays)(const SphereQueryBvh& spheres, const UnitRay* rays, std::size_t count,
                              const QueryFilter& filter, SphereRayHit* hits);
};

/// The active path's kernels (active_simd_path()); InvalidArgument as active_simd_path.
[[nodiscard]] const SimdKernels& simd_kernels();
/// The kernels of `path`, active or not (tests compare the paths); InvalidArgument if this CPU
/// lacks it.
[[nodiscard]] const SimdKernels& simd_kernels(SimdPath path);

/// The per-path tables (kernel/simd/kernel_table.cpp; the implementations in kernel/simd/kernels.h); call only on a CPU that supports the path.
const SimdKernels& simd_kernels_sse4_2();
const SimdKernels& simd_kernels_avx2();
const SimdKernels& simd_kernels_avx512();

/// Output helpers for the kernels, compiled at the base level (see the top of this file).
void append_pairs(std::vector<SpherePair>& out, const SpherePair* pairs, std::size_t count);
void append_slots(std::vector<std::uint32_t>& out, const std::uint32_t* slots, std::size_t count);
void append_contacts(std::vector<Contact>& out, const Contact* contacts, std::size_t count);
/// Sorts `row` (partner slots of sphere i), appends the pairs (i, j) in that order, empties it.
void append_sorted_row(std::uint32_t i, std::vector<std::uint32_t>& row, std::vector<SpherePair>& out);
/// The same for rows that may hold a partner twice (SphereGrid): sorted, repeats dropped.
void append_sorted_unique_row(std::uint32_t i, std::vector<std::uint32_t>& row, std::vector<SpherePair>& out);

}  // namespace hail
