#include "kernel/sphere_triangle.h"

#include <cmath>

namespace hail {
namespace {

inline float dot3(const float* u, const float* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }
inline void sub3(const float* u, const float* v, float* out) {
  out[0] = u[0] - v[0];
  out[1] = u[1] - v[1];
  out[2] = u[2] - v[2];
}
inline TrianglePoint along(const float* from, const float* dir, float t, TriangleRegion region) {
  return {{from[0] + t * dir[0], from[1] + t * dir[1], from[2] + t * dir[2]}, region};
}

/// Whether the closest point lies on an edge or vertex internal to a smooth surface.
bool region_is_internal(TriangleRegion region, std::uint8_t internal) {
  switch (region) {
    case TriangleRegion::Face: return true;
    case TriangleRegion::Edge0: return internal & kEdge0Internal;
    case TriangleRegion::Edge1: return internal & kEdge1Internal;
    case TriangleRegion::Edge2: return internal & kEdge2Internal;
    // A vertex is internal when both of this triangle's edges through it are.
    case TriangleRegion::Vertex0: return (internal & kEdge0Internal) && (internal & kEdge2Internal);
    case TriangleRegion::Vertex1: return (internal & kEdge0Internal) && (internal & kEdge1Internal);
    case TriangleRegion::Vertex2: return (internal & kEdge1Internal) && (internal & kEdge2Internal);
  }
  return false;
}

}  // namespace

TrianglePoint closest_point_on_triangle(const float q[3], const float a[3], const float b[3], const float c[3]) {
  float ab[3], ac[3], ap[3], bp[3], cp[3];
  sub3(b, a, ab);
  sub3(c, a, ac);
  sub3(q, a, ap);
  const float d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return {{a[0], a[1], a[2]}, TriangleRegion::Vertex0};
  sub3(q, b, bp);
  const float d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return {{b[0], b[1], b[2]}, TriangleRegion::Vertex1};
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return along(a, ab, d1 / (d1 - d3), TriangleRegion::Edge0);
  sub3(q, c, cp);
  const float d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return {{c[0], c[1], c[2]}, TriangleRegion::Vertex2};
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return along(a, ac, d2 / (d2 - d6), TriangleRegion::Edge2);
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    float bc[3];
    sub3(c, b, bc);
    return along(b, bc, (d4 - d3) / ((d4 - d3) + (d5 - d6)), TriangleRegion::Edge1);
  }
  const float denom = va + vb + vc;
  if (!(denom > 0.0f)) return {{a[0], a[1], a[2]}, TriangleRegion::Vertex0};  // zero-area triangle
  const float v = vb / denom, w = vc / denom;
  return {{a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w},
          TriangleRegion::Face};
}

bool sphere_triangle_contact(const float centre[3], float radius, const float a[3], const float b[3], const float c[3],
                             const float face_normal[3], float face_d, std::uint8_t internal_edges, float max_gap,
                             SphereTriangleContact& out) {
  const float height = dot3(face_normal, centre) - face_d;  // signed distance of the centre to the plane
  if (height - radius > max_gap) return false;                // plane test first: cheap rejection
  const TrianglePoint closest = closest_point_on_triangle(centre, a, b, c);
  float d[3];
  sub3(closest.p, centre, d);
  const float distance = std::sqrt(dot3(d, d));  // depth before normalising
  if (distance - radius > max_gap) return false;
  if (closest.region == TriangleRegion::Face || distance <= 1e-12f) {
    // Over the face, or sunk below it: push out along the face normal, never through.
    out.n[0] = -face_normal[0];
    out.n[1] = -face_normal[1];
    out.n[2] = -face_normal[2];
    out.gap = height - radius;
    out.surface_d = -face_d;
    return true;
  }
  // Outside this face and below its plane: the triangle whose face the centre is over owns
  // the contact (at a convex fold this plane passes above the neighbour's surface).
  if (height <= 0.0f) return false;
  if (region_is_internal(closest.region, internal_edges)) {
    // Smooth fold: the true distance, but the face normal, so the edge cannot stick up.
    out.n[0] = -face_normal[0];
    out.n[1] = -face_normal[1];
    out.n[2] = -face_normal[2];
    out.gap = distance - radius;
    // The contact plane sits `distance` ahead of the centre along n, so depenetration sees the
    // same gap as detection did.
    out.surface_d = dot3(out.n, centre) + distance;
    return true;
  }
  const float inv = 1.0f / distance;
  out.n[0] = d[0] * inv;
  out.n[1] = d[1] * inv;
  out.n[2] = d[2] * inv;
  out.gap = distance - radius;
  out.surface_d = dot3(out.n, closest.p);
  return true;
}

}  // namespace hail
