#pragma once
// A triangle mesh placed in a world, ready to collide (World::add_mesh): its triangles in world
// coordinates with everything about them that never changes (the terrain's SoA layout,
// kernel/terrain/terrain_triangles.h; normals from the winding, any direction), in BVH order so
// that a leaf's triangles are contiguous, and the flat BVH over them. Built once; immutable after,
// so any number of threads may query it at once.

#include <cstdint>
#include <vector>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "hail/triangle_mesh.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/geometry/aabb.h"
#include "kernel/terrain/terrain_triangles.h"

namespace hail {

struct MeshCollider {
  TerrainTriangles triangles;  ///< world coordinates, BVH order, degenerate triangles left out
  FlatBvh bvh;
  std::vector<Aabb> bounds;  ///< per triangle, BVH order
  bool two_sided = false;    ///< a shell (the mesh is not closed): both faces collide
  float restitution = 0.5f, friction = 0.5f;
  /// Contact::feature of triangle k (BVH order) is kMeshFeature | (first_feature + k): the
  /// world's meshes number their triangles one after another.
  std::uint32_t first_feature = 0;
  std::size_t degenerate = 0;  ///< triangles of the mesh left out (zero area)

  /// Appends the contacts of spheres [first, last) with this mesh, in sphere order, with the
  /// terrain's reach and reduction (kernel/terrain/terrain_contacts.h: one contact per distinct
  /// normal, speculative up to the sphere's travel this step), by the terrain's packet walk on the
  /// active SIMD path (kernel/simd/terrain_contacts.cpp; the contacts do not depend on the path).
  /// No allocation beyond `out`.
  void find_contacts(const SphereSoA& spheres, std::size_t first, std::size_t last, float dt, std::vector<Contact>& out,
                     float fast_fraction, bool sweep_fast) const;
  /// find_contacts with one scalar BVH walk per sphere: the reference, same contacts in the same order.
  void find_contacts_scalar(const SphereSoA& spheres, std::size_t first, std::size_t last, float dt,
                            std::vector<Contact>& out, float fast_fraction, bool sweep_fast) const;
  /// Deepest overlap (m, >= 0) of a sphere with the mesh: for error reports and tests.
  [[nodiscard]] float penetration(float x, float y, float z, float r) const;
  /// Heap bytes held (capacities).
  [[nodiscard]] std::size_t memory_bytes() const;
};

/// Builds the collider of `mesh` placed by `transform` (checked: MeshTransform::validate), with
/// internal edges from the mesh's own adjacency (kernel/mesh/mesh_edges.h): an edge shared by
/// exactly two triangles is internal where the fold is within 5 degrees of flat
/// (kInternalEdgeCosine), and on a closed mesh also where it is concave. O(n log n), allocates.
/// Throws InvalidArgument when no triangle is left (all degenerate) or the material is bad.
[[nodiscard]] MeshCollider build_mesh_collider(const TriangleMesh& mesh, const MeshTransform& transform,
                                               float restitution, float friction, std::uint32_t first_feature,
                                               std::uint32_t leaf_size = 8);

}  // namespace hail
