#pragma once
// Which triangles of a mesh share which edges: whether the mesh is closed (a solid) and, per
// triangle edge, its neighbour across it. Vertices at equal positions count as one (a soup from
// an STL file or a mesh given with its vertices repeated per triangle still shares its edges),
// and degenerate triangles (zero area) are left out.

#include <cstdint>
#include <span>
#include <vector>

#include "hail/vec3.h"

namespace hail {

/// No neighbour across an edge: a boundary edge, or one shared by three or more triangles.
inline constexpr std::uint32_t kNoNeighbour = 0xFFFFFFFFu;

/// Per vertex, the lowest index of a vertex at exactly the same position.
[[nodiscard]] std::vector<std::uint32_t> weld_vertices(std::span<const Vec3> vertices);

/// Whether triangle t (indices 3t..3t+2 into `vertices`) has zero area, in double.
[[nodiscard]] bool degenerate_triangle(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices,
                                       std::size_t t);

/// Per triangle t and edge k (from corner k to corner k + 1 mod 3), at 3t + k: the one other
/// non-degenerate triangle with that edge, or kNoNeighbour. `welded`: weld_vertices' result.
/// `same_direction` (optional, same size): 1 where that neighbour runs along the edge in the same
/// direction (the two are wound inconsistently).
[[nodiscard]] std::vector<std::uint32_t> edge_neighbours(std::span<const Vec3> vertices,
                                                         std::span<const std::uint32_t> indices,
                                                         std::span<const std::uint32_t> welded,
                                                         std::vector<std::uint8_t>* same_direction = nullptr);

/// Whether every edge of every non-degenerate triangle has exactly one neighbour that runs along
/// it in the opposite direction (include/hail/triangle_mesh.h's "closed").
[[nodiscard]] bool mesh_is_closed(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices);

}  // namespace hail
