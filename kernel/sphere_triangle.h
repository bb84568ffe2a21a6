#pragma once
// Sphere-triangle contact by the closest point on the triangle (Ericson, "Real-Time Collision
// Detection" 5.1.5: face, edge and vertex regions), with the internal-edge rule that removes
// ghost collisions: where the closest point lies on an edge (or vertex) that is internal to a
// smooth surface, the contact takes the triangle's face normal instead of the direction to that
// point, so a sphere rolling across a finely triangulated flat or gently curved surface never
// meets an edge sticking up out of it (the idea of Jolt's "active edges").

#include <cstdint>

namespace hail {

/// Which feature of a triangle the closest point lies on.
enum class TriangleRegion : std::uint8_t { Face, Edge0, Edge1, Edge2, Vertex0, Vertex1, Vertex2 };

/// Bit k set in an internal-edge mask: edge k (e0 = v0->v1, e1 = v1->v2, e2 = v2->v0) is shared
/// with a neighbour across a smooth (nearly flat) fold, so it must not produce edge normals.
inline constexpr std::uint8_t kEdge0Internal = 1, kEdge1Internal = 2, kEdge2Internal = 4;

struct TrianglePoint {
  float p[3];
  TriangleRegion region;
};

/// Closest point of triangle (a, b, c) to point q, and the region it lies in.
TrianglePoint closest_point_on_triangle(const float q[3], const float a[3], const float b[3], const float c[3]);

struct SphereTriangleContact {
  float n[3];  ///< unit normal from the sphere's centre into the surface
  float gap;   ///< signed distance from the sphere's surface to the triangle (< 0: overlapping)
  float surface_d;  ///< n . (point on the surface): the contact plane, for depenetration
};

/// Contact of sphere (centre, radius) with the triangle whose unit face normal is `face_normal`
/// (pointing out of the solid) and plane offset face_d = face_normal . a. Returns false when
/// the gap exceeds max_gap. Centres below the triangle's plane always get the face normal, so a
/// sphere that sank is pushed out upwards, never through.
bool sphere_triangle_contact(const float centre[3], float radius, const float a[3], const float b[3], const float c[3],
                             const float face_normal[3], float face_d, std::uint8_t internal_edges, float max_gap,
                             SphereTriangleContact& out);

}  // namespace hail
