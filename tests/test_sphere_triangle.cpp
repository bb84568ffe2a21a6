// Closest point on a triangle by region, and the sphere-triangle contact with internal edges.

#include <cmath>

#include "catch.h"
#include "kernel/geometry/sphere_triangle.h"

using hail::TriangleRegion;

namespace {
// A right triangle in the y = 0 plane, normal +y (winding a -> c -> b seen from above is
// irrelevant here: the face normal is passed in).
const float A[3] = {0, 0, 0}, B[3] = {1, 0, 0}, C[3] = {0, 0, 1};
const float Up[3] = {0, 1, 0};
}  // namespace

TEST_CASE("Closest point lands in the right region", "[sphere-triangle]") {
  struct Case {
    float q[3];
    TriangleRegion region;
    float p[3];
  };
  const Case cases[] = {
      {{0.25f, 2, 0.25f}, TriangleRegion::Face, {0.25f, 0, 0.25f}}, {{-1, 1, -1}, TriangleRegion::Vertex0, {0, 0, 0}},
      {{2, 1, -0.5f}, TriangleRegion::Vertex1, {1, 0, 0}},          {{-0.5f, 0, 2}, TriangleRegion::Vertex2, {0, 0, 1}},
      {{0.5f, 0, -1}, TriangleRegion::Edge0, {0.5f, 0, 0}},         {{1, 0, 1}, TriangleRegion::Edge1, {0.5f, 0, 0.5f}},
      {{-1, 0, 0.5f}, TriangleRegion::Edge2, {0, 0, 0.5f}},
  };
  for (const Case& c : cases) {
    const hail::TrianglePoint t = hail::closest_point_on_triangle(c.q, A, B, C);
    CHECK(t.region == c.region);
    for (int d = 0; d < 3; ++d) CHECK(t.p[d] == Approx(c.p[d]).margin(1e-6));
  }
}

TEST_CASE("A zero-area triangle gives a finite closest point", "[sphere-triangle]") {
  const float q[3] = {0.3f, 1, 0.2f}, p0[3] = {0, 0, 0}, p1[3] = {1, 0, 0}, p2[3] = {2, 0, 0};
  const hail::TrianglePoint t = hail::closest_point_on_triangle(q, p0, p1, p2);
  for (float v : t.p) CHECK(std::isfinite(v));
}

TEST_CASE("Sphere over the face: face normal and plane gap", "[sphere-triangle]") {
  const float centre[3] = {0.2f, 0.4f, 0.2f};
  hail::SphereTriangleContact c;
  REQUIRE(hail::sphere_triangle_contact(centre, 0.5f, A, B, C, Up, 0.0f, 0, 0.0f, c));
  CHECK(c.n[1] == -1.0f);
  CHECK(c.gap == Approx(-0.1f));
}

TEST_CASE("A real edge pushes sideways; an internal edge pushes along the face normal", "[sphere-triangle]") {
  // Centre beside edge e0 (z < 0), slightly above the plane.
  const float centre[3] = {0.5f, 0.1f, -0.3f};
  hail::SphereTriangleContact real, internal;
  REQUIRE(hail::sphere_triangle_contact(centre, 0.5f, A, B, C, Up, 0.0f, 0, 0.0f, real));
  REQUIRE(hail::sphere_triangle_contact(centre, 0.5f, A, B, C, Up, 0.0f, hail::kEdge0Internal, 0.0f, internal));
  CHECK(real.n[2] > 0.9f);  // the edge is to the sphere's +z
  CHECK(internal.n[1] == -1.0f);
  CHECK(internal.gap == Approx(real.gap));  // same true distance, only the direction differs
}

TEST_CASE("Far spheres and spheres below a neighbour's plane give no contact", "[sphere-triangle]") {
  hail::SphereTriangleContact c;
  const float far[3] = {0.2f, 3, 0.2f};
  CHECK_FALSE(hail::sphere_triangle_contact(far, 0.5f, A, B, C, Up, 0.0f, 0, 0.1f, c));
  const float beside_below[3] = {0.5f, -0.2f, -0.3f};
  CHECK_FALSE(hail::sphere_triangle_contact(beside_below, 0.5f, A, B, C, Up, 0.0f, 0, 0.0f, c));
  // Sunk under the face: pushed up along the face normal, never through.
  const float sunk[3] = {0.2f, -0.3f, 0.2f};
  REQUIRE(hail::sphere_triangle_contact(sunk, 0.5f, A, B, C, Up, 0.0f, 0, 0.0f, c));
  CHECK(c.n[1] == -1.0f);
  CHECK(c.gap == Approx(-0.8f));
}
