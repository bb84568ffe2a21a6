#pragma once
// The static meshes of a World (World::add_mesh), in the order added: their colliders, and
// which mesh a contact's feature names. Colliders are immutable and shared, so copying a set
// copies pointers.

#include <cstdint>
#include <memory>
#include <vector>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "hail/triangle_mesh.h"
#include "kernel/mesh/mesh_collider.h"

namespace hail {

class MeshSet {
 public:
  /// Builds and appends the collider of `mesh` placed by `transform`; returns its index. The set
  /// is unchanged when it throws (build_mesh_collider's errors; InvalidArgument when the world's
  /// mesh triangles would pass 2^30, what Contact::feature can number).
  std::size_t add(const TriangleMesh& mesh, const MeshTransform& transform, float restitution, float friction);

  /// The same meshes, each placed `by` further (its transform's position + by) and rebuilt from
  /// its source mesh: World::shift_origin's move. Throws InvalidArgument (this set unchanged)
  /// where a position would not be finite. A triangle lands where the transform puts it, rounded
  /// once: by whole metres, exactly the old one moved, as the terrain moves (Terrain::moved).
  [[nodiscard]] MeshSet moved(const Vec3& by) const;
  /// Whether every mesh of `other` numbers its triangles in the same BVH order as this one's
  /// (warm-start impulses name triangles by that order).
  [[nodiscard]] bool same_order(const MeshSet& other) const;

  [[nodiscard]] bool empty() const { return meshes_.empty(); }
  [[nodiscard]] std::size_t size() const { return meshes_.size(); }
  [[nodiscard]] const MeshCollider& operator[](std::size_t i) const { return *meshes_[i]; }
  /// The mesh whose triangle a kMeshFeature contact or impact names.
  [[nodiscard]] std::uint32_t mesh_of(std::uint32_t feature) const;

  /// Every mesh's contacts with spheres [first, last): mesh by mesh, each in sphere order
  /// (MeshCollider::find_contacts).
  void find_contacts(const SphereSoA& spheres, std::size_t first, std::size_t last, float dt, std::vector<Contact>& out,
                     float fast_fraction, bool sweep_fast) const {
    for (const auto& m : meshes_) m->find_contacts(spheres, first, last, dt, out, fast_fraction, sweep_fast);
  }
  /// The guard's move for meshes (Terrain::push_out's for terrain): the centre of a sphere of
  /// radius r goes out of the deepest overlapping triangle along its contact normal by its
  /// overlap, then again for what still overlaps, at most `rounds` times. A shell's triangle is
  /// met from the side `from` (the centre at the step's start) is on, so a sphere pushed across
  /// a shell within the step comes back to its side. Returns whether it moved. No allocation.
  bool push_out(float& x, float& y, float& z, float r, const float from[3], int rounds = 4) const;
  /// Deepest overlap of a sphere with any mesh (m, >= 0).
  [[nodiscard]] float penetration(float x, float y, float z, float r) const;
  [[nodiscard]] std::size_t memory_bytes() const;

 private:
  /// What a mesh was built from, for moved(): the mesh (shared with the set's copies), where it
  /// was placed and its material.
  struct Source {
    std::shared_ptr<const TriangleMesh> mesh;
    MeshTransform transform;
    float restitution, friction;
  };
  std::vector<std::shared_ptr<const MeshCollider>> meshes_;
  std::vector<Source> sources_;
  std::uint32_t triangles_ = 0;  ///< all meshes' triangles: the next mesh's first_feature
};

}  // namespace hail
