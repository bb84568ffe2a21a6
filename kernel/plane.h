#pragma once
// Static infinite planes: the solid half-space {x : n.x < offset}.

#include <cstdint>
#include <span>
#include <vector>

#include "kernel/contact.h"
#include "soa/sphere_soa.h"

namespace hail {

struct Plane {
  float nx, ny, nz;  ///< unit normal pointing out of the solid
  float offset;      ///< n.x = offset on the surface, m
  float restitution;
  float friction;
};

/// Signed distance from the sphere's surface to the plane (negative when overlapping).
inline float plane_gap(const Plane& p, float x, float y, float z, float r) {
  return p.nx * x + p.ny * y + p.nz * z - p.offset - r;
}

/// Appends a contact for every sphere in [first, last) touching or overlapping a plane
/// (gap <= 0); spheres approaching but not yet touching are handled exactly at their time of
/// impact by the integrator, so planes need no speculative contacts.
void find_plane_contacts(const SphereSoA& spheres, std::span<const Plane> planes, std::size_t first,
                         std::size_t last, std::vector<Contact>& out);

}  // namespace hail
