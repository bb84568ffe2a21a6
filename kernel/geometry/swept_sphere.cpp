#include "kernel/geometry/swept_sphere.h"

#include <cmath>

#include "kernel/geometry/sphere_triangle.h"

namespace hail {
namespace {

double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/// Smaller root of A t^2 + 2 B t + C = 0 for a point entering a region it is outside of
/// (C > 0) while moving inwards (B < 0): C / (-B + sqrt(B^2 - A C)), the form that does not
/// cancel when A is tiny. Negative when it never enters or only after t_max.
double entry_time(double A, double B, double C, double t_max) {
  if (B >= 0.0) return -1.0;
  const double disc = B * B - A * C;
  if (disc < 0.0) return -1.0;
  const double t = C / (-B + std::sqrt(disc));
  return t <= t_max ? t : -1.0;
}

/// Returned by the entry times below when the sphere touches that part already at t = 0.
constexpr double kTouching = -2.0;

/// Entry time of the centre into the cylinder of radius r around edge p->q, limited to the
/// segment; -1 for none, kTouching when the centre starts inside the segment's cylinder.
double edge_entry(const double centre[3], const double v[3], double r, const double p[3], const double q[3],
                  double t_max) {
  const double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
  const double m[3] = {centre[0] - p[0], centre[1] - p[1], centre[2] - p[2]};
  const double dd = dot(d, d);
  if (dd <= 0.0) return -1.0;  // zero-length edge: its vertices cover it
  // Distance to the edge's line: |m x d| / |d|; in squares times dd, no subtraction cancels.
  double md_cross[3], vd_cross[3];
  cross(m, d, md_cross);
  cross(v, d, vd_cross);
  const double C = dot(md_cross, md_cross) - dd * r * r;
  const double s0 = dot(m, d) / dd;
  if (C <= 0.0) {
    if (s0 >= 0.0 && s0 <= 1.0) return kTouching;
    return -1.0;  // inside the infinite cylinder beyond an end: the end's vertex decides
  }
  const double A = dot(vd_cross, vd_cross), B = dot(md_cross, vd_cross);
  if (A <= 0.0) return -1.0;  // moving along the edge
  const double t = entry_time(A, B, C, t_max);
  if (t < 0.0) return -1.0;
  const double s = (dot(m, d) + t * dot(v, d)) / dd;
  return s >= 0.0 && s <= 1.0 ? t : -1.0;
}

/// Entry time of the centre into the ball of radius r around vertex p; -1 for none, kTouching
/// when it starts inside.
double vertex_entry(const double centre[3], const double v[3], double r, const double p[3], double t_max) {
  const double m[3] = {centre[0] - p[0], centre[1] - p[1], centre[2] - p[2]};
  const double C = dot(m, m) - r * r;
  if (C <= 0.0) return kTouching;
  return entry_time(dot(v, v), dot(m, v), C, t_max);
}

/// Whether point x on the triangle's plane lies inside it (edges inclusive); the triangle is
/// wound so that (b - a) x (c - a) points along n.
bool inside_triangle(const double x[3], const double a[3], const double b[3], const double c[3], const double n[3]) {
  const double* corner[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    const double* p = corner[k];
    const double* q = corner[(k + 1) % 3];
    const double edge[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    const double to_x[3] = {x[0] - p[0], x[1] - p[1], x[2] - p[2]};
    double side[3];
    cross(edge, to_x, side);
    if (dot(side, n) < 0.0) return false;
  }
  return true;
}

/// Closing speeds at or below this are sliding along, not hitting: a sphere skidding over the
/// ground closes on it by rounding noise only, and each such "hit" would cost an event.
double closing_tolerance(const double v[3]) { return 1e-6 * std::sqrt(dot(v, v)) + 1e-9; }

/// A sphere already touching the triangle at t = 0 hits it now if it is closing on it along the
/// discrete contact's normal (kernel/geometry/sphere_triangle.h, with its internal-edge rule): that is a
/// sphere knocked into the ground by an impact earlier in the same step.
bool touching_hit(const double centre[3], const double v[3], double r, const double a[3], const double b[3],
                  const double c[3], const double n[3], std::uint8_t internal_edges, SweptHit& hit) {
  const float cf[3] = {float(centre[0]), float(centre[1]), float(centre[2])};
  const float af[3] = {float(a[0]), float(a[1]), float(a[2])}, bf[3] = {float(b[0]), float(b[1]), float(b[2])};
  const float cc[3] = {float(c[0]), float(c[1]), float(c[2])}, nf[3] = {float(n[0]), float(n[1]), float(n[2])};
  const float face_d = nf[0] * af[0] + nf[1] * af[1] + nf[2] * af[2];
  SphereTriangleContact contact;
  if (!sphere_triangle_contact(cf, float(r), af, bf, cc, nf, face_d, internal_edges, float(r), contact)) return false;
  const double normal[3] = {contact.n[0], contact.n[1], contact.n[2]};
  if (dot(v, normal) <= closing_tolerance(v)) return false;
  hit.t = 0.0;
  for (int d = 0; d < 3; ++d) hit.n[d] = normal[d];
  return true;
}

}  // namespace

double sphere_sphere_time_of_impact(const double dp[3], const double dv[3], double reach, double t_max) {
  const double b = dot(dp, dv);
  if (-b <= closing_tolerance(dv) * std::sqrt(dot(dp, dp))) return -1.0;  // not closing
  const double c = dot(dp, dp) - reach * reach;
  if (c <= 0.0) return 0.0;  // overlapping and closing: now
  return entry_time(dot(dv, dv), b, c, t_max);
}

bool swept_sphere_triangle(const double centre[3], const double v[3], double r, const double a[3], const double b[3],
                           const double c[3], const double n[3], std::uint8_t internal_edges, double t_max,
                           SweptHit& hit) {
  const double height = dot(n, centre) - dot(n, a);
  if (height < 0.0) return false;  // behind the face: tunnelled already, not ours to fix
  // 0: face, 1..3: edges e0..e2, 4..6: vertices v0..v2.
  double best = -1.0;
  int part = -1;
  auto consider = [&](double t, int which) {
    if (t >= 0.0 && (best < 0.0 || t < best)) best = t, part = which;
  };
  const double vn = dot(n, v);
  if (height <= r) {
    const double foot[3] = {centre[0] - height * n[0], centre[1] - height * n[1], centre[2] - height * n[2]};
    if (inside_triangle(foot, a, b, c, n)) return touching_hit(centre, v, r, a, b, c, n, internal_edges, hit);
  } else if (vn < 0.0) {
    const double t = (height - r) / -vn;
    const double foot[3] = {centre[0] + v[0] * t - r * n[0], centre[1] + v[1] * t - r * n[1],
                            centre[2] + v[2] * t - r * n[2]};
    if (t <= t_max && inside_triangle(foot, a, b, c, n)) consider(t, 0);
  }
  const double entries[6] = {edge_entry(centre, v, r, a, b, t_max), edge_entry(centre, v, r, b, c, t_max),
                             edge_entry(centre, v, r, c, a, t_max), vertex_entry(centre, v, r, a, t_max),
                             vertex_entry(centre, v, r, b, t_max),  vertex_entry(centre, v, r, c, t_max)};
  for (int k = 0; k < 6; ++k) {
    if (entries[k] == kTouching) return touching_hit(centre, v, r, a, b, c, n, internal_edges, hit);
    consider(entries[k], k + 1);
  }
  if (part < 0) return false;
  const double at[3] = {centre[0] + v[0] * best, centre[1] + v[1] * best, centre[2] + v[2] * best};
  // Which edges meet at each vertex: v0 (e0, e2), v1 (e0, e1), v2 (e1, e2).
  constexpr std::uint8_t part_edges[7] = {0,
                                          kEdge0Internal,
                                          kEdge1Internal,
                                          kEdge2Internal,
                                          kEdge0Internal | kEdge2Internal,
                                          kEdge0Internal | kEdge1Internal,
                                          kEdge1Internal | kEdge2Internal};
  const bool internal = part == 0 || (internal_edges & part_edges[part]) == part_edges[part];
  if (internal) {
    for (int d = 0; d < 3; ++d) hit.n[d] = -n[d];
  } else {
    double touch[3];
    if (part >= 4) {
      const double* corner = part == 4 ? a : part == 5 ? b : c;
      for (int d = 0; d < 3; ++d) touch[d] = corner[d];
    } else {
      const double* p = part == 1 ? a : part == 2 ? b : c;
      const double* q = part == 1 ? b : part == 2 ? c : a;
      const double e[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
      const double m[3] = {at[0] - p[0], at[1] - p[1], at[2] - p[2]};
      const double s = dot(m, e) / dot(e, e);
      for (int d = 0; d < 3; ++d) touch[d] = p[d] + s * e[d];
    }
    const double to[3] = {touch[0] - at[0], touch[1] - at[1], touch[2] - at[2]};
    const double len = std::sqrt(dot(to, to));
    if (!(len > 0.0)) return false;
    for (int d = 0; d < 3; ++d) hit.n[d] = to[d] / len;
  }
  if (dot(v, hit.n) <= closing_tolerance(v)) return false;  // not closing along the contact normal
  hit.t = best;
  return true;
}

bool swept_sphere_plane(const double centre[3], const double v[3], double r, const double n[3], double offset,
                        double t_max, SweptHit& hit) {
  const double gap = dot(n, centre) - offset - r;
  const double vn = dot(n, v);
  if (-vn <= closing_tolerance(v)) return false;
  const double t = gap > 0.0 ? gap / -vn : 0.0;  // touching already and closing: now
  if (t > t_max) return false;
  hit.t = t;
  for (int d = 0; d < 3; ++d) hit.n[d] = -n[d];
  return true;
}

}  // namespace hail
