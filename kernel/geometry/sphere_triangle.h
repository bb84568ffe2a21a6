#pragma once
// Sphere-triangle contact by the closest point on the triangle (Ericson, "Real-Time Collision
// Detection" 5.1.5: face, edge and vertex regions), with the internal-edge rule that removes
// ghost collisions: where the closest point lies on an edge (or vertex) that is internal to a
// smooth surface, the contact takes the triangle's face normal instead of the direction to that
// point, so a sphere rolling across a finely triangulated flat or gently curved surface never
// meets an edge sticking up out of it (the idea of Jolt's "active edges").

#include <cmath>
#include <cstdint>

#include "kernel/dispatch/simd_namespace.h"

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

struct SphereTriangleContact {
  float n[3];       ///< unit normal from the sphere's centre into the surface
  float gap;        ///< signed distance from the sphere's surface to the triangle (< 0: overlapping)
  float surface_d;  ///< n . (point on the surface): the contact plane, for depenetration
};

// Inline, in the namespace of the SIMD path that compiles them (kernel/dispatch/simd_namespace.h): the
// terrain kernels of every path call them once per candidate triangle, and inlined there they
// cost fewer instructions than as calls into base code; the scalar reference and the other
// callers in base code compile the same float operations (-ffp-contract=off), so the bits agree.
inline namespace HAIL_SIMD_NS {

namespace triangle_detail {

inline float dot3(const float* u, const float* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }
inline void sub3(const float* u, const float* v, float* out) {
  out[0] = u[0] - v[0];
  out[1] = u[1] - v[1];
  out[2] = u[2] - v[2];
}
inline TrianglePoint along(const float* from, const float* dir, float t, TriangleRegion region) {
  return {{from[0] + t * dir[0], from[1] + t * dir[1], from[2] + t * dir[2]}, region};
}

/// Whether q lies over the triangle's footprint on the ground (its x, z inside the projection
/// of a, b, c along y), edges included up to rounding, so that a point over an edge shared by
/// two triangles belongs to at least one of them. Terrain triangles come from a heightfield
/// (y up), so their footprints tile the map and none is vertical.
inline bool over_footprint(const float q[3], const float a[3], const float b[3], const float c[3]) {
  const float e0 = (b[0] - a[0]) * (q[2] - a[2]) - (b[2] - a[2]) * (q[0] - a[0]);
  const float e1 = (c[0] - b[0]) * (q[2] - b[2]) - (c[2] - b[2]) * (q[0] - b[0]);
  const float e2 = (a[0] - c[0]) * (q[2] - c[2]) - (a[2] - c[2]) * (q[0] - c[0]);
  const float twice_area = e0 + e1 + e2;  // its sign is the winding's
  const float slack = 1e-5f * std::fabs(twice_area);
  return twice_area >= 0.0f ? (e0 >= -slack && e1 >= -slack && e2 >= -slack)
                            : (e0 <= slack && e1 <= slack && e2 <= slack);
}

/// Whether the closest point lies on an edge or vertex internal to a smooth surface.
inline bool region_is_internal(TriangleRegion region, std::uint8_t internal) {
  switch (region) {
    case TriangleRegion::Face:
      return true;
    case TriangleRegion::Edge0:
      return internal & kEdge0Internal;
    case TriangleRegion::Edge1:
      return internal & kEdge1Internal;
    case TriangleRegion::Edge2:
      return internal & kEdge2Internal;
    // A vertex is internal when both of this triangle's edges through it are.
    case TriangleRegion::Vertex0:
      return (internal & kEdge0Internal) && (internal & kEdge2Internal);
    case TriangleRegion::Vertex1:
      return (internal & kEdge0Internal) && (internal & kEdge1Internal);
    case TriangleRegion::Vertex2:
      return (internal & kEdge1Internal) && (internal & kEdge2Internal);
  }
  return false;
}

}  // namespace triangle_detail

/// Closest point of triangle (a, b, c) to point q, and the region it lies in.
inline TrianglePoint closest_point_on_triangle(const float q[3], const float a[3], const float b[3], const float c[3]) {
  float ab[3], ac[3], ap[3], bp[3], cp[3];
  triangle_detail::sub3(b, a, ab);
  triangle_detail::sub3(c, a, ac);
  triangle_detail::sub3(q, a, ap);
  const float d1 = triangle_detail::dot3(ab, ap), d2 = triangle_detail::dot3(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return {{a[0], a[1], a[2]}, TriangleRegion::Vertex0};
  triangle_detail::sub3(q, b, bp);
  const float d3 = triangle_detail::dot3(ab, bp), d4 = triangle_detail::dot3(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return {{b[0], b[1], b[2]}, TriangleRegion::Vertex1};
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f)
    return triangle_detail::along(a, ab, d1 / (d1 - d3), TriangleRegion::Edge0);
  triangle_detail::sub3(q, c, cp);
  const float d5 = triangle_detail::dot3(ab, cp), d6 = triangle_detail::dot3(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return {{c[0], c[1], c[2]}, TriangleRegion::Vertex2};
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f)
    return triangle_detail::along(a, ac, d2 / (d2 - d6), TriangleRegion::Edge2);
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    float bc[3];
    triangle_detail::sub3(c, b, bc);
    return triangle_detail::along(b, bc, (d4 - d3) / ((d4 - d3) + (d5 - d6)), TriangleRegion::Edge1);
  }
  const float denom = va + vb + vc;
  if (!(denom > 0.0f)) return {{a[0], a[1], a[2]}, TriangleRegion::Vertex0};  // zero-area triangle
  const float v = vb / denom, w = vc / denom;
  return {{a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w},
          TriangleRegion::Face};
}

/// The second half of sphere_triangle_contact, once the closest point is known and within
/// reach: `d` = closest.p - centre, `distance` = |d| (sqrt of its dot3), `height` = the signed
/// distance of the centre to the face plane. Picks the normal; false where another triangle
/// owns the contact. The SIMD terrain kernels compute the first half for a batch of candidates
/// (kernel/simd/sphere_triangle_lanes.h) and finish here, so both give the same bits.
///
/// Below the plane, the heightfield decides: a centre behind the plane and over this
/// triangle's footprint is under the surface (sunk), and goes out along the face normal, never
/// through. A centre behind the plane but over another triangle's footprint is not inside the
/// terrain because of this triangle: on steep ground such a plane passes metres above the
/// surface the sphere is over (beside a cliff, or beyond a ridge), and its depth was a ghost
/// contact that threw spheres through ridges (issue 28). The triangle under the centre, or
/// the ones the sphere faces, own its contacts.
inline bool contact_from_closest_point(const float centre[3], float radius, const TrianglePoint& closest,
                                       const float d[3], float distance, float height, const float face_normal[3],
                                       float face_d, std::uint8_t internal_edges, const float a[3], const float b[3],
                                       const float c[3], SphereTriangleContact& out) {
  const bool behind = height <= 0.0f;
  if (behind ? triangle_detail::over_footprint(centre, a, b, c)
             : (closest.region == TriangleRegion::Face || distance <= 1e-12f)) {
    // Over the face, or sunk below it: along the face normal, the distance to the plane.
    out.n[0] = -face_normal[0];
    out.n[1] = -face_normal[1];
    out.n[2] = -face_normal[2];
    out.gap = height - radius;
    out.surface_d = -face_d;
    return true;
  }
  if (behind) return false;
  if (triangle_detail::region_is_internal(closest.region, internal_edges)) {
    // Smooth fold: the true distance, but the face normal, so the edge cannot stick up.
    out.n[0] = -face_normal[0];
    out.n[1] = -face_normal[1];
    out.n[2] = -face_normal[2];
    out.gap = distance - radius;
    // The contact plane sits `distance` ahead of the centre along n, so depenetration sees the
    // same gap as detection did.
    out.surface_d = triangle_detail::dot3(out.n, centre) + distance;
    return true;
  }
  const float inv = 1.0f / distance;
  out.n[0] = d[0] * inv;
  out.n[1] = d[1] * inv;
  out.n[2] = d[2] * inv;
  out.gap = distance - radius;
  out.surface_d = triangle_detail::dot3(out.n, closest.p);
  return true;
}

/// Contact of sphere (centre, radius) with the triangle whose unit face normal is `face_normal`
/// (pointing out of the solid) and plane offset face_d = face_normal . a. Returns false when
/// the gap exceeds max_gap. A centre below the plane and over the triangle's footprint gets the
/// face normal, so a sphere that sank is pushed out upwards, never through; one below the plane
/// and beside the footprint gets no contact from it (contact_from_closest_point).
inline bool sphere_triangle_contact(const float centre[3], float radius, const float a[3], const float b[3],
                                    const float c[3], const float face_normal[3], float face_d,
                                    std::uint8_t internal_edges, float max_gap, SphereTriangleContact& out) {
  const float height =
      triangle_detail::dot3(face_normal, centre) - face_d;  // signed distance of the centre to the plane
  if (height - radius > max_gap) return false;              // plane test first: cheap rejection
  const TrianglePoint closest = closest_point_on_triangle(centre, a, b, c);
  float d[3];
  triangle_detail::sub3(closest.p, centre, d);
  const float distance = std::sqrt(triangle_detail::dot3(d, d));  // depth before normalising
  if (distance - radius > max_gap) return false;
  return contact_from_closest_point(centre, radius, closest, d, distance, height, face_normal, face_d, internal_edges,
                                    a, b, c, out);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
