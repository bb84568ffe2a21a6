#pragma once
// Time of impact of a sphere moving in a straight line (continuous collision): the earliest
// moment within a step at which it first touches a triangle, a plane or another moving sphere.
// Scalar reference code in double: it runs only for the few spheres that move far in one step
// (kernel/ccd/continuous_collision.h), and at 10,000 m/s a float time would place the impact
// centimetres off.
//
// A swept sphere touches a triangle when its centre enters the triangle grown by the radius:
// the face moved out along its normal, a cylinder around each edge and a ball at each vertex
// (Ericson, "Real-Time Collision Detection", 5.5.7, and the ray tests of 5.3). The earliest
// entry into any of them is the time of impact.

#include <cstdint>

namespace hail {

/// A first touch found by a sweep: the time from the sweep's start and the unit contact normal
/// from the moving sphere's centre into what it touches.
struct SweptHit {
  double t = 0;
  double n[3] = {0, 0, 0};
};

/// Earliest t in [0, t_max] with |dp + dv t| = reach, where dp is the centre of b minus the
/// centre of a, dv the velocity of b minus that of a and reach = ra + rb; or -1 when they do not
/// touch in time or are moving apart. Spheres already overlapping and closing give 0.
[[nodiscard]] double sphere_sphere_time_of_impact(const double dp[3], const double dv[3], double reach, double t_max);

/// Sphere (centre c + v t, radius r) against the triangle (a, b, c) with unit face normal n out
/// of the solid and internal-edge mask `internal_edges` (kernel/geometry/sphere_triangle.h). Only a
/// sphere whose centre is in front of the face can hit (one behind it has tunnelled already).
/// One touching the triangle at t = 0 hits at t = 0 if it closes on it along the discrete
/// contact's normal (it was knocked into the ground earlier in the step). Where the first touch
/// is on an internal edge or vertex the normal is the face's, as for discrete contacts, and a
/// hit whose sphere is not closing along that normal is no hit. Returns false for no hit in
/// [0, t_max].
[[nodiscard]] bool swept_sphere_triangle(const double centre[3], const double v[3], double r, const double a[3],
                                         const double b[3], const double c[3], const double n[3],
                                         std::uint8_t internal_edges, double t_max, SweptHit& hit);

/// Sphere against the plane {x : n.x = offset} approached from the side n points to (n unit).
/// A sphere moving away has no hit; one already touching and closing hits at t = 0.
[[nodiscard]] bool swept_sphere_plane(const double centre[3], const double v[3], double r, const double n[3],
                                      double offset, double t_max, SweptHit& hit);

}  // namespace hail
