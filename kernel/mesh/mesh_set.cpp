#include "kernel/mesh/mesh_set.h"

#include <algorithm>
#include <string>

#include "hail/errors.h"

namespace hail {

std::size_t MeshSet::add(const TriangleMesh& mesh, const MeshTransform& transform, float restitution, float friction) {
  if (std::uint64_t{triangles_} + mesh.triangle_count() > (std::uint64_t{1} << 30))
    throw InvalidArgument("World::add_mesh: the world's meshes would hold " +
                          std::to_string(std::uint64_t{triangles_} + mesh.triangle_count()) +
                          " triangles, more than 2^30 (what a contact's feature can number)");
  auto collider =
      std::make_shared<const MeshCollider>(build_mesh_collider(mesh, transform, restitution, friction, triangles_));
  meshes_.reserve(meshes_.size() + 1);
  triangles_ += static_cast<std::uint32_t>(collider->triangles.size());
  meshes_.push_back(std::move(collider));
  return meshes_.size() - 1;
}

std::uint32_t MeshSet::mesh_of(std::uint32_t feature) const {
  const std::uint32_t triangle = feature & ~kMeshFeature;
  const auto after = std::upper_bound(meshes_.begin(), meshes_.end(), triangle,
                                      [](std::uint32_t t, const auto& m) { return t < m->first_feature; });
  return static_cast<std::uint32_t>(std::max<std::ptrdiff_t>(after - meshes_.begin() - 1, 0));
}

float MeshSet::penetration(float x, float y, float z, float r) const {
  float deepest = 0.0f;
  for (const auto& m : meshes_) deepest = std::max(deepest, m->penetration(x, y, z, r));
  return deepest;
}

std::size_t MeshSet::memory_bytes() const {
  std::size_t bytes = meshes_.capacity() * sizeof(meshes_[0]);
  for (const auto& m : meshes_) bytes += m->memory_bytes();
  return bytes;
}

}  // namespace hail
