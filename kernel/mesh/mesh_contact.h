#pragma once
// Sphere-triangle contact for a triangle of a mesh (include/hail/triangle_mesh.h): the terrain's
// closest-point contact and internal-edge rule (kernel/geometry/sphere_triangle.h), with what
// a heightfield's "up" decided there taken from the mesh's sides instead. A closed mesh is a
// solid: a centre behind a face and over it (projected along the face normal) sank in and goes
// out along the normal, as on terrain. A thin shell (any other mesh) has two faces: the one the
// centre is in front of is the one it meets.

#include <cmath>
#include <cstdint>

#include "kernel/dispatch/simd_namespace.h"
#include "kernel/geometry/sphere_triangle.h"

namespace hail {
// Inline, in the namespace of the SIMD path that compiles them, as kernel/geometry/sphere_triangle.h.
inline namespace HAIL_SIMD_NS {

/// Whether q, projected along unit normal n onto the triangle's plane, lies inside (a, b, c)
/// (wound counter-clockwise about n), edges included up to rounding: the footprint test of
/// kernel/geometry/sphere_triangle.h for a triangle facing any way.
inline bool over_triangle(const float q[3], const float a[3], const float b[3], const float c[3], const float n[3]) {
  auto side = [&](const float* from, const float* to) {
    const float e[3] = {to[0] - from[0], to[1] - from[1], to[2] - from[2]};
    const float p[3] = {q[0] - from[0], q[1] - from[1], q[2] - from[2]};
    return n[0] * (e[1] * p[2] - e[2] * p[1]) + n[1] * (e[2] * p[0] - e[0] * p[2]) + n[2] * (e[0] * p[1] - e[1] * p[0]);
  };
  const float e0 = side(a, b), e1 = side(b, c), e2 = side(c, a);
  const float slack = 1e-5f * std::fabs(e0 + e1 + e2);
  return e0 >= -slack && e1 >= -slack && e2 >= -slack;
}

/// The second half of sphere_mesh_triangle_contact, once the closest point is known and within
/// reach (as contact_from_closest_point for terrain): `height` is the centre's signed distance
/// to the face plane along `face_normal`. The packet walk (kernel/simd/terrain_contacts.cpp)
/// finishes its candidates here, so both give the same bits.
inline bool mesh_contact_from_closest_point(const float centre[3], float radius, const TrianglePoint& closest,
                                            const float to[3], float distance, float height, const float face_normal[3],
                                            float face_d, std::uint8_t internal_edges, bool two_sided, const float a[3],
                                            const float b[3], const float c[3], SphereTriangleContact& out) {
  float n[3] = {face_normal[0], face_normal[1], face_normal[2]};
  float d = face_d;
  if (two_sided && height < 0.0f) {
    n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
    d = -d;
    height = -height;
  }
  if (height <= 0.0f) {
    if (!over_triangle(centre, a, b, c, face_normal)) return false;
    out.n[0] = -n[0], out.n[1] = -n[1], out.n[2] = -n[2];
    out.gap = height - radius;
    out.surface_d = -d;
    return true;
  }
  // In front of the face: the terrain's rules, which never reach their behind-the-plane branch.
  return contact_from_closest_point(centre, radius, closest, to, distance, height, n, d, internal_edges, a, b, c, out);
}

/// Contact of sphere (centre, radius) with a mesh triangle whose unit normal (from the winding)
/// is `face_normal` and plane offset face_d = face_normal . a; false when the gap exceeds
/// max_gap. `two_sided`: the mesh is a shell (the face the centre is in front of counts, the
/// normal flipped to it). One-sided: a centre up to a radius behind the plane and over the
/// triangle is pushed out along the normal; deeper, or behind and beside it, no contact (a centre
/// that deep is past a face the sweep and the speculative contacts should have stopped it at).
inline bool sphere_mesh_triangle_contact(const float centre[3], float radius, const float a[3], const float b[3],
                                         const float c[3], const float face_normal[3], float face_d,
                                         std::uint8_t internal_edges, bool two_sided, float max_gap,
                                         SphereTriangleContact& out) {
  const float height = face_normal[0] * centre[0] + face_normal[1] * centre[1] + face_normal[2] * centre[2] - face_d;
  const float reach = two_sided ? std::fabs(height) : height;  // what the plane test sees, as the packet walk
  if (reach - radius > max_gap || reach < -radius) return false;
  const TrianglePoint closest = closest_point_on_triangle(centre, a, b, c);
  const float to[3] = {closest.p[0] - centre[0], closest.p[1] - centre[1], closest.p[2] - centre[2]};
  const float distance = std::sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
  if (distance - radius > max_gap) return false;
  return mesh_contact_from_closest_point(centre, radius, closest, to, distance, height, face_normal, face_d,
                                         internal_edges, two_sided, a, b, c, out);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
