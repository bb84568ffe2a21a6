#include "kernel/mesh/mesh_set.h"

#include <algorithm>
#include <string>

#include "hail/errors.h"
#include "kernel/mesh/mesh_contact.h"

namespace hail {

std::size_t MeshSet::add(const TriangleMesh& mesh, const MeshTransform& transform, float restitution, float friction) {
  if (std::uint64_t{triangles_} + mesh.triangle_count() > (std::uint64_t{1} << 30))
    throw InvalidArgument("World::add_mesh: the world's meshes would hold " +
                          std::to_string(std::uint64_t{triangles_} + mesh.triangle_count()) +
                          " triangles, more than 2^30 (what a contact's feature can number)");
  auto collider =
      std::make_shared<const MeshCollider>(build_mesh_collider(mesh, transform, restitution, friction, triangles_));
  Source source{std::make_shared<const TriangleMesh>(mesh), transform, restitution, friction};
  meshes_.reserve(meshes_.size() + 1);
  sources_.reserve(sources_.size() + 1);
  triangles_ += static_cast<std::uint32_t>(collider->triangles.size());
  meshes_.push_back(std::move(collider));
  sources_.push_back(std::move(source));
  return meshes_.size() - 1;
}

MeshSet MeshSet::moved(const Vec3& by) const {
  MeshSet out;
  for (std::size_t m = 0; m < sources_.size(); ++m) {
    const Source& s = sources_[m];
    MeshTransform transform = s.transform;
    transform.position += by;
    if (!transform.position.allFinite())
      throw InvalidArgument("World::shift_origin: mesh " + std::to_string(m) + " would be placed where floats end");
    auto collider = std::make_shared<const MeshCollider>(
        build_mesh_collider(*s.mesh, transform, s.restitution, s.friction, out.triangles_));
    out.triangles_ += static_cast<std::uint32_t>(collider->triangles.size());
    out.meshes_.push_back(std::move(collider));
    out.sources_.push_back({s.mesh, transform, s.restitution, s.friction});
  }
  return out;
}

bool MeshSet::same_order(const MeshSet& other) const {
  if (other.meshes_.size() != meshes_.size()) return false;
  for (std::size_t m = 0; m < meshes_.size(); ++m)
    if (meshes_[m]->bvh.primitive_order != other.meshes_[m]->bvh.primitive_order ||
        meshes_[m]->first_feature != other.meshes_[m]->first_feature)
      return false;
  return true;
}

std::uint32_t MeshSet::mesh_of(std::uint32_t feature) const {
  const std::uint32_t triangle = feature & ~kMeshFeature;
  const auto after = std::upper_bound(meshes_.begin(), meshes_.end(), triangle,
                                      [](std::uint32_t t, const auto& m) { return t < m->first_feature; });
  return static_cast<std::uint32_t>(std::max<std::ptrdiff_t>(after - meshes_.begin() - 1, 0));
}

bool MeshSet::push_out(float& x, float& y, float& z, float r, const float from[3], int rounds) const {
  bool moved = false;
  for (int round = 0; round < rounds; ++round) {
    const float centre[3] = {x, y, z};
    SphereTriangleContact deepest{};
    deepest.gap = 0.0f;
    for (const auto& m : meshes_) {
      const TerrainTriangles& t = m->triangles;
      query_sphere(m->bvh, x, y, z, r, [&](std::uint32_t k) {
        const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]},
                    c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
        float n[3] = {t.nx[k], t.ny[k], t.nz[k]}, d = t.d[k];
        const float* first = b;  // a shell met from behind: its corners reversed with its normal
        const float* second = c;
        if (m->two_sided && n[0] * from[0] + n[1] * from[1] + n[2] * from[2] < d) {
          n[0] = -n[0], n[1] = -n[1], n[2] = -n[2], d = -d;
          first = c, second = b;
        }
        // As a solid's face from the start's side, every edge a real edge: the move is out of
        // what the sphere overlaps, whatever the smooth surface around it.
        SphereTriangleContact st;
        if (sphere_mesh_triangle_contact(centre, r, a, first, second, n, d, 0, false, 0.0f, st) && st.gap < deepest.gap)
          deepest = st;
      });
    }
    if (!(deepest.gap < 0.0f)) break;
    x += deepest.gap * deepest.n[0], y += deepest.gap * deepest.n[1], z += deepest.gap * deepest.n[2];
    moved = true;
  }
  return moved;
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
