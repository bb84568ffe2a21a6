#pragma once
// Static terrain: a heightmap's triangles with their per-triangle data computed once at load
// (kernel/terrain/terrain_triangles.h: vertices, edges, unit normal, plane offset, internal-edge
// mask), stored SoA in BVH order so that a
// leaf's triangles are contiguous, and the flat BVH over them.
//
// Ownership and threads: a Terrain owns its heightmap, triangles and BVH and never changes after
// construction, so every const member may be called from any number of threads at once, and one
// Terrain may be shared by several Worlds (World::set_terrain takes a shared_ptr<const Terrain>).
// Allocation: only the constructor allocates (about 140 bytes per triangle kept, two triangles
// per heightmap cell, and about twice that at its peak); queries allocate nothing, and
// find_contacts only grows its output vector.

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <memory>

#include "hail/contact.h"
#include "hail/heightmap.h"
#include "hail/sphere_soa.h"
#include "hail/vec3.h"

namespace hail {

// The triangles' data, the BVH and the triangle boxes are the kernel's internal types
// (kernel/terrain/terrain_triangles.h, kernel/bvh/flat_bvh.h, kernel/geometry/aabb.h): held by
// pointer so that this header needs none of them.
struct TerrainTriangles;
struct FlatBvh;
struct Aabb;

/// Where a ray met the terrain (Terrain::raycast).
struct TerrainRayHit {
  float t;                 ///< distance along the ray, in units of |dir| (metres for a unit dir)
  Vec3 point;              ///< origin + t * dir, m
  Vec3 normal;             ///< the triangle's unit face normal, pointing up (+y) out of the ground
  std::uint32_t triangle;  ///< index into triangles() (BVH order)
};

/// One terrain triangle (Terrain::triangle): its corners, counter-clockwise seen from above, and
/// its unit face normal, pointing up (+y) out of the ground. m.
struct TerrainTriangle {
  Vec3 a, b, c;
  Vec3 normal;
};

/// Immutable terrain built from a heightmap; see the top of this file for threads and allocation.
class Terrain {
 public:
  /// Triangles per BVH leaf unless the constructor is told otherwise. 8, not 4: the packet
  /// walk tests a leaf's triangle boxes for all lanes at once, so larger leaves cost little
  /// there and save node tests, so terrain-rain's detect-terrain is faster with 8 (`hail-bench
  /// query --leaf 4` and `--leaf 8`: docs/benchmarks.md, "Figures behind the code's choices").
  static constexpr std::uint32_t kDefaultLeafSize = 8;

  /// Builds triangles and BVH (leaf_size 1..8; InvalidArgument otherwise), on the calling
  /// thread. The BVH build is O(n log n) in the triangles: a large map takes seconds
  /// (timings in docs/benchmarks.md, `hail-bench bvh-build`).
  explicit Terrain(Heightmap heightmap, std::uint32_t leaf_size = kDefaultLeafSize);
  Terrain(Terrain&&) noexcept;
  Terrain& operator=(Terrain&&) noexcept;
  ~Terrain();

  /// The same terrain moved by `by` (m): built from heightmap().moved(by) with the same leaf
  /// size, so its triangles are the same grid of the same heights with the origin moved (bit
  /// for bit the old vertices plus `by` where that sum is exact, e.g. `by` a multiple of a
  /// power of two no finer than the vertices' spacing). Costs a full build, as the constructor
  /// (the BVH rebuilt); World::shift_origin uses it. Throws InvalidArgument as
  /// Heightmap::moved.
  [[nodiscard]] Terrain moved(const Vec3& by) const { return Terrain(heightmap_.moved(by), leaf_size_); }

  /// The heightmap it was built from; surface_height(x, z) is the ground height under a point.
  [[nodiscard]] const Heightmap& heightmap() const { return heightmap_; }
  /// Triangles kept (two per heightmap cell); TerrainRayHit::triangle and a terrain
  /// Contact::feature are below it.
  [[nodiscard]] std::size_t triangle_count() const;
  /// Triangle `index` (BVH order, as TerrainRayHit::triangle and Contact::feature name it).
  /// Throws InvalidArgument unless index < triangle_count().
  [[nodiscard]] TerrainTriangle triangle(std::uint32_t index) const;
  /// Per-triangle data in BVH order, SoA (kernel/terrain/terrain_triangles.h, inside the library).
  [[nodiscard]] const TerrainTriangles& triangles() const { return *triangles_; }
  /// The flat BVH over triangles(), for custom queries with kernel/bvh/flat_bvh.h's walks.
  [[nodiscard]] const FlatBvh& bvh() const { return *bvh_; }
  /// Bytes the terrain holds: its heights, per-triangle data, BVH nodes and triangle boxes
  /// (capacities, as allocated), for memory budgets; hail-bench run prints it beside what the
  /// whole run holds (terrain-rain's map: docs/benchmarks.md, "Figures behind the code's choices").
  [[nodiscard]] std::size_t memory_bytes() const;
  /// Per triangle, BVH order: its box, which the packet walk tests for all lanes at once.
  [[nodiscard]] const std::vector<Aabb>& triangle_bounds() const { return *triangle_bounds_; }

  /// Appends the contacts of spheres [first, last) with the terrain, in sphere order: every
  /// triangle whose gap is below the sphere's travel this step (|v| dt, speculative), reduced
  /// so that triangles giving the same normal (a flat area split into many triangles) yield one
  /// contact. Spheres walk the BVH in packets (kernel/bvh/bvh_packet_walk.h) on the active SIMD path
  /// (kernel/dispatch/simd_dispatch.h; the contacts do not depend on the path). No allocation beyond
  /// `out`'s growth.
  /// `restitution` and `friction` are the terrain's material, combined with each sphere's.
  /// Spheres that are fast (is_fast with `fast_fraction`, kernel/ccd/continuous_collision.h) reach
  /// no further than fast_fraction of their radius; with `sweep_fast` they get only the
  /// contacts they touch already, since what they meet later in the step is swept.
  void find_contacts(const SphereSoA& spheres, std::size_t first, std::size_t last, float dt, float restitution,
                     float friction, std::vector<Contact>& out, float fast_fraction = 0.0f,
                     bool sweep_fast = false) const;
  /// find_contacts with one scalar BVH walk per sphere: the reference, same contacts in the same order.
  void find_contacts_scalar(const SphereSoA& spheres, std::size_t first, std::size_t last, float dt, float restitution,
                            float friction, std::vector<Contact>& out, float fast_fraction = 0.0f,
                            bool sweep_fast = false) const;

  /// Deepest penetration (m, >= 0) of a sphere into the terrain: for error reports.
  [[nodiscard]] float penetration(float x, float y, float z, float r) const;

  /// Nearest hit of the ray origin + t dir, t in [0, max_t), with the terrain's triangles (both
  /// faces count; a ray through a shared edge or vertex reports one of the triangles), or
  /// nullopt for a miss. `dir` need not be unit: t is in units of |dir|. max_t may be infinite.
  /// The flat BVH's stackless nearest-hit walk (kernel/bvh/flat_bvh.h, query_ray) with exact
  /// Moller-Trumbore tests (kernel/geometry/ray_triangle.h). hail-micro measures its rate on
  /// terrain-rain's map (docs/benchmarks.md, "Figures behind the code's choices"); a longer ray
  /// visits more nodes.
  /// No allocation; thread-safe. Throws InvalidArgument (naming the value) for a non-finite
  /// origin or dir, a zero dir, or a NaN or negative max_t.
  [[nodiscard]] std::optional<TerrainRayHit> raycast(const Vec3& origin, const Vec3& dir,
                                                     float max_t = std::numeric_limits<float>::infinity()) const;

  /// Moves the centre of a sphere of radius r out of the terrain: the deepest overlapping
  /// triangle first, along its contact normal by its overlap, then again for what still
  /// overlaps, at most `rounds` times. Returns whether it moved. For spheres that travelled
  /// further in a step than their contacts reached (kernel/terrain/terrain_push_out.cpp).
  bool push_out(float& x, float& y, float& z, float r, int rounds = kPushOutRounds) const;
  static constexpr int kPushOutRounds = 4;  ///< push_out's default

  /// A centre below the surface at its x, z (inside the solid, where push_out's query finds no
  /// triangle once it is a radius deep) is put a radius above the surface there: touching flat
  /// ground, overlapping a slope by r (1 - cos slope) with the centre on the outer side, so
  /// that push_out then moves it out along the right normal. Returns whether it moved y; a
  /// point outside the heightmap's extent is left alone.
  bool lift_above_surface(float x, float& y, float z, float r) const {
    const float surface = heightmap_.surface_height(x, z);  // NaN outside: the test fails
    if (!(y < surface)) return false;
    y = surface + r;
    return true;
  }

  /// push_out (default rounds) for each sphere of `spheres` named in `slots`, their walks a
  /// packet of spheres at a time on the active SIMD path (kernel/simd/terrain_push_out.cpp):
  /// the same moves as push_out sphere by sphere, which stays the reference. Returns how many
  /// moved. No allocation; disjoint slot lists may run in parallel.
  std::size_t push_out_spheres(SphereSoA& spheres, std::span<const std::uint32_t> slots) const;

 private:
  Heightmap heightmap_;
  std::uint32_t leaf_size_;  ///< triangles per BVH leaf, for moved()
  std::unique_ptr<TerrainTriangles> triangles_;
  std::unique_ptr<FlatBvh> bvh_;
  std::unique_ptr<std::vector<Aabb>> triangle_bounds_;  ///< per triangle, BVH order: the packet walk's leaf filter
};

}  // namespace hail
