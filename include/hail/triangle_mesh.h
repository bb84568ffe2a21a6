#pragma once
// A triangle mesh as a static collider: a soup of triangles (vertices and index triples), from
// memory or an OBJ or STL file, placed in a World with World::add_mesh (docs/meshes.md).
//
// A TriangleMesh is a value: it owns its vertices and indices, and its const members may be
// called from any number of threads at once. The constructor and the loaders check everything
// and either return a whole mesh or throw: InvalidArgument for bad values passed in, FileError
// ("hail: <path>:<line>: <problem>") for a malformed or unreadable file.
//
// Sides: a mesh that is closed (every edge shared by exactly two triangles that run along it in
// opposite directions, i.e. a consistently wound watertight surface) is a solid, colliding on
// the side its triangles' normals face ((v1 - v0) x (v2 - v0), counter-clockwise seen from
// outside); a sphere whose centre sank behind a face is pushed back out along it. Any other
// mesh (open, as a hopper's funnel or a drum's shell; non-manifold; wound inconsistently) is a
// thin shell that collides on both faces; a sphere whose centre crosses one of its triangles is
// on the other side from then on, so fast spheres are swept against it (continuous collision).

#include <cstdint>
#include <string>
#include <vector>

#include "hail/vec3.h"

namespace hail {

/// Largest mesh accepted (triangles), checked before a loader allocates for a file's claim:
/// 2^26 triangles, about 9 GiB of collider data.
inline constexpr std::uint64_t kMaxMeshTriangles = std::uint64_t{1} << 26;

/// Where a mesh sits in the world: each vertex p becomes position + R (scale p), R the rotation
/// by `degrees` about `axis` (right-handed). `axis` need not be unit, and may be zero only with
/// a zero angle.
struct MeshTransform {
  Vec3 position{0.0f, 0.0f, 0.0f};  ///< m
  Vec3 axis{0.0f, 1.0f, 0.0f};
  float degrees = 0.0f;
  float scale = 1.0f;  ///< uniform, > 0

  /// Throws InvalidArgument (naming the field) for a non-finite value, a scale <= 0, or a zero
  /// axis with a non-zero angle.
  void validate() const;
  /// The transformed point, in double and rounded once to float.
  [[nodiscard]] Vec3 apply(const Vec3& p) const;
};

class TriangleMesh {
 public:
  /// Triangle t is vertices[indices[3t]], [3t + 1], [3t + 2]. Throws InvalidArgument for no
  /// triangles, an index count that is not a multiple of 3, an index out of range, a non-finite
  /// vertex, or more than kMaxMeshTriangles triangles. Degenerate triangles (zero area, or two
  /// equal indices) are kept here and left out of the collider (World::add_mesh).
  TriangleMesh(std::vector<Vec3> vertices, std::vector<std::uint32_t> indices);

  /// By extension (case-insensitive): load_obj for ".obj", load_stl for ".stl"; FileError
  /// otherwise.
  [[nodiscard]] static TriangleMesh load(const std::string& path);
  /// Wavefront OBJ: `v x y z` vertices and `f` faces of 3 or more vertices (fanned into
  /// triangles), each index as `i`, `i/t`, `i//n` or `i/t/n`, 1-based or negative (relative).
  /// Other statements (vn, vt, o, g, s, usemtl, mtllib, comments) are skipped.
  [[nodiscard]] static TriangleMesh load_obj(const std::string& path);
  /// STL, binary or ASCII (a file whose length is exactly 84 + 50 n bytes for the count n in its
  /// header is binary). Vertices with equal coordinates are merged, so that triangles share
  /// edges; the facet normals in the file are ignored (the winding decides).
  [[nodiscard]] static TriangleMesh load_stl(const std::string& path);

  [[nodiscard]] const std::vector<Vec3>& vertices() const { return vertices_; }
  [[nodiscard]] const std::vector<std::uint32_t>& indices() const { return indices_; }
  [[nodiscard]] std::size_t triangle_count() const { return indices_.size() / 3; }
  /// Whether the mesh is closed, as the top of this file defines it (a solid, one-sided).
  [[nodiscard]] bool closed() const { return closed_; }

 private:
  std::vector<Vec3> vertices_;
  std::vector<std::uint32_t> indices_;
  bool closed_ = false;
};

}  // namespace hail
