// Builds the per-triangle SoA of a heightmap and classifies each edge as internal or active.

#include "kernel/terrain/terrain_triangles.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hail/errors.h"

namespace hail {
namespace {

/// One triangle in double: set-up precision is free, and the fold test below compares nearly
/// equal normals.
struct Geometry {
  double v[3][3];
  double n[3];
};

Geometry triangle_geometry(const Heightmap& h, std::size_t t) {
  const std::size_t cells_x = h.cols() - 1, cell = t / 2;
  const auto i = static_cast<std::uint32_t>(cell % cells_x), j = static_cast<std::uint32_t>(cell / cells_x);
  // Vertex grid offsets (di, dj) of v0, v1, v2; see the layout in the header.
  static constexpr std::uint32_t kCorners[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
  Geometry g;
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t vi = i + kCorners[t % 2][k][0], vj = j + kCorners[t % 2][k][1];
    g.v[k][0] = h.x_of(vi);
    g.v[k][1] = h.h(vi, vj);
    g.v[k][2] = h.z_of(vj);
  }
  double a[3], b[3];
  for (int c = 0; c < 3; ++c) {
    a[c] = g.v[1][c] - g.v[0][c];
    b[c] = g.v[2][c] - g.v[0][c];
  }
  const double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  // n[1] = cell_x * cell_z > 0 whatever the heights, so the length is never zero.
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int c = 0; c < 3; ++c) g.n[c] = n[c] / len;
  return g;
}

struct Across {
  std::int64_t triangle;  ///< -1: edge on the map's boundary
  int edge;               ///< the shared edge's index in that triangle
};

/// The triangle on the other side of edge e of triangle t.
/// Even (v00, v01, v10): e0 (west) - odd of (i-1, j) e2; e1 (diagonal) - odd of (i, j) e0;
/// e2 (north, z = j) - odd of (i, j-1) e1. Odd (v10, v01, v11) mirrors it.
Across across(const Heightmap& h, std::size_t t, int e) {
  const std::int64_t cells_x = h.cols() - 1, cells_z = h.rows() - 1;
  const std::int64_t cell = static_cast<std::int64_t>(t / 2), i = cell % cells_x, j = cell / cells_x;
  auto at = [&](std::int64_t ci, std::int64_t cj, int odd, int edge) -> Across {
    if (ci < 0 || cj < 0 || ci >= cells_x || cj >= cells_z) return {-1, 0};
    return {2 * (cj * cells_x + ci) + odd, edge};
  };
  if (t % 2 == 0) return e == 0 ? at(i - 1, j, 1, 2) : e == 1 ? at(i, j, 1, 0) : at(i, j - 1, 1, 1);
  return e == 0 ? at(i, j, 0, 1) : e == 1 ? at(i, j + 1, 0, 2) : at(i + 1, j, 0, 0);
}

/// Internal unless the fold is convex and sharper than kInternalEdgeCosine. Concave folds are
/// internal too (as Jolt): in a valley the neighbour's face already stops the sphere, and an
/// edge normal there would only tilt the contact.
bool edge_is_internal(const Geometry& self, const Geometry& other, int other_edge) {
  const double cosine = self.n[0] * other.n[0] + self.n[1] * other.n[1] + self.n[2] * other.n[2];
  if (cosine >= double{kInternalEdgeCosine}) return true;
  const double* far = other.v[(other_edge + 2) % 3];  // the neighbour's vertex off the shared edge
  double above = 0.0;
  for (int c = 0; c < 3; ++c) above += self.n[c] * (far[c] - self.v[0][c]);
  return above > 0.0;  // neighbour rises above this plane: concave
}

}  // namespace

std::size_t terrain_triangle_count(const Heightmap& heightmap) {
  return 2 * std::size_t(heightmap.cols() - 1) * (heightmap.rows() - 1);
}

TerrainTriangles build_terrain_triangles(const Heightmap& heightmap) {
  const std::size_t count = terrain_triangle_count(heightmap);
  TerrainTriangles s;
  AlignedArray<float>* vertex[3][3] = {{&s.v0x, &s.v0y, &s.v0z}, {&s.v1x, &s.v1y, &s.v1z}, {&s.v2x, &s.v2y, &s.v2z}};
  AlignedArray<float>* edge[3][3] = {{&s.e0x, &s.e0y, &s.e0z}, {&s.e1x, &s.e1y, &s.e1z}, {&s.e2x, &s.e2y, &s.e2z}};
  AlignedArray<float>* normal[3] = {&s.nx, &s.ny, &s.nz};
  for (auto& row : vertex)
    for (auto* a : row) a->resize(count);
  for (auto& row : edge)
    for (auto* a : row) a->resize(count);
  for (auto* a : normal) a->resize(count);
  s.d.resize(count);
  s.internal_edges.resize(count);

  for (std::size_t t = 0; t < count; ++t) {
    const Geometry g = triangle_geometry(heightmap, t);
    double d = 0.0;
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) {
        (*vertex[k][c])[t] = static_cast<float>(g.v[k][c]);
        (*edge[k][c])[t] = static_cast<float>(g.v[(k + 1) % 3][c] - g.v[k][c]);
      }
      (*normal[c])[t] = static_cast<float>(g.n[c]);
      d += g.n[c] * g.v[0][c];
    }
    s.d[t] = static_cast<float>(d);
    std::uint8_t internal = 0;
    for (int e = 0; e < 3; ++e) {
      const Across other = across(heightmap, t, e);
      if (other.triangle < 0) continue;  // the map's boundary is a real edge
      if (edge_is_internal(g, triangle_geometry(heightmap, static_cast<std::size_t>(other.triangle)), other.edge))
        internal |= static_cast<std::uint8_t>(1u << e);
    }
    s.internal_edges[t] = internal;
  }
  return s;
}

void terrain_triangle_bounds(const TerrainTriangles& s, std::size_t t, float min[3], float max[3]) {
  const float v[3][3] = {
      {s.v0x[t], s.v0y[t], s.v0z[t]}, {s.v1x[t], s.v1y[t], s.v1z[t]}, {s.v2x[t], s.v2y[t], s.v2z[t]}};
  for (int c = 0; c < 3; ++c) {
    min[c] = std::min({v[0][c], v[1][c], v[2][c]});
    max[c] = std::max({v[0][c], v[1][c], v[2][c]});
  }
}

TerrainTriangles reorder_terrain_triangles(const TerrainTriangles& in, std::span<const std::uint32_t> order) {
  for (std::size_t k = 0; k < order.size(); ++k)
    if (order[k] >= in.size())
      throw InvalidArgument("hail: reorder_terrain_triangles: order[" + std::to_string(k) + "] = " +
                            std::to_string(order[k]) + " but there are " + std::to_string(in.size()) + " triangles");
  TerrainTriangles out;
  auto gather = [&](AlignedArray<float> TerrainTriangles::*member) {
    const AlignedArray<float>& from = in.*member;
    AlignedArray<float>& to = out.*member;
    to.resize(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) to[k] = from[order[k]];
  };
  for (auto member : {&TerrainTriangles::v0x, &TerrainTriangles::v0y, &TerrainTriangles::v0z, &TerrainTriangles::v1x,
                      &TerrainTriangles::v1y, &TerrainTriangles::v1z, &TerrainTriangles::v2x, &TerrainTriangles::v2y,
                      &TerrainTriangles::v2z, &TerrainTriangles::e0x, &TerrainTriangles::e0y, &TerrainTriangles::e0z,
                      &TerrainTriangles::e1x, &TerrainTriangles::e1y, &TerrainTriangles::e1z, &TerrainTriangles::e2x,
                      &TerrainTriangles::e2y, &TerrainTriangles::e2z, &TerrainTriangles::nx,  &TerrainTriangles::ny,
                      &TerrainTriangles::nz,  &TerrainTriangles::d})
    gather(member);
  out.internal_edges.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) out.internal_edges[k] = in.internal_edges[order[k]];
  return out;
}

}  // namespace hail
