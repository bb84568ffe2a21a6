#pragma once
// The triangles of a heightmap with everything about them that never changes, computed once at
// load and stored structure-of-arrays for the narrowphase: vertices, edge vectors, unit normal,
// plane offset, and which edges are internal to a smooth surface (Jolt's "active edges": a
// sphere rolling over an internal edge must see the face normal, not the edge, or it hops).
//
// Layout: cell (i, j)-(i+1, j+1) is split along the diagonal from vertex (i+1, j) to vertex
// (i, j+1) (Bullet's default). With cell k = j * (cols - 1) + i:
//   triangle 2k     : v0 = (i, j),   v1 = (i, j+1), v2 = (i+1, j)    (the half holding (i, j))
//   triangle 2k + 1 : v0 = (i+1, j), v1 = (i, j+1), v2 = (i+1, j+1)  (the half holding (i+1, j+1))
// Both are wound so that (v1 - v0) x (v2 - v0) points up (+y). Edge k runs from vertex k to
// vertex k+1: in triangle 2k, e1 is the diagonal; in 2k + 1, e0 is.

#include <cstddef>
#include <cstdint>
#include <span>

#include "hail/aligned_array.h"
#include "hail/heightmap.h"
#include "kernel/geometry/sphere_triangle.h"  // kEdge{0,1,2}Internal: the mask bits stored here

namespace hail {

/// A shared edge whose two triangles' unit normals have a dot product at or above this (within
/// 5 degrees, as Jolt) is internal. Larger (closer to 1): more edges active, more ghost bumps on
/// gently curved ground; smaller: real ridges start to act smooth.
inline constexpr float kInternalEdgeCosine = 0.9961947f;  // cos 5 degrees

/// Per-triangle data, one entry per triangle in every array (index as in the layout above, or
/// the order given to reorder_terrain_triangles). Positions in m.
struct TerrainTriangles {
  AlignedArray<float> v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z;  ///< vertices, m
  AlignedArray<float> e0x, e0y, e0z;                                ///< e0 = v1 - v0, m
  AlignedArray<float> e1x, e1y, e1z;                                ///< e1 = v2 - v1, m
  AlignedArray<float> e2x, e2y, e2z;                                ///< e2 = v0 - v2, m
  AlignedArray<float> nx, ny, nz;                                   ///< unit normal, ny > 0 (out of the ground)
  AlignedArray<float> d;                                            ///< plane offset n . v0, m
  /// Bit k (kEdge{k}Internal) set: edge k is shared with a neighbour across a fold that is
  /// concave, or convex by less than acos(kInternalEdgeCosine). Clear: a real edge (the map's
  /// boundary, or a sharp convex ridge).
  AlignedArray<std::uint8_t> internal_edges;

  /// Number of triangles.
  [[nodiscard]] std::size_t size() const { return d.size(); }
};

/// 2 * (cols - 1) * (rows - 1): two triangles per cell.
[[nodiscard]] std::size_t terrain_triangle_count(const Heightmap& heightmap);

/// All triangles of `heightmap` in the layout above. Normals and plane offsets are computed in
/// double and rounded once. O(triangles), allocates only the result.
[[nodiscard]] TerrainTriangles build_terrain_triangles(const Heightmap& heightmap);

/// Axis-aligned bounds (m) of triangle t: min and max of its three vertices per axis (x, y, z).
void terrain_triangle_bounds(const TerrainTriangles& triangles, std::size_t t, float min[3], float max[3]);

/// Triangles permuted so that entry k is input entry order[k] (e.g. into BVH leaf order, so a
/// leaf's triangles are contiguous). Throws InvalidArgument if an index is out of range.
[[nodiscard]] TerrainTriangles reorder_terrain_triangles(const TerrainTriangles& triangles,
                                                         std::span<const std::uint32_t> order);

}  // namespace hail
