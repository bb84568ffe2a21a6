#pragma once
// Static infinite planes: the solid half-space {x : n.x < offset}.

#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "hail/plane.h"
#include "hail/sphere_soa.h"

namespace hail {

/// Appends a contact for every sphere in [first, last) touching or overlapping a plane
/// (plane_touching); spheres approaching but not yet touching are handled exactly at their time of
/// impact by the integrator, so planes need no speculative contacts.
void find_plane_contacts(const SphereSoA& spheres, std::span<const Plane> planes, std::size_t first, std::size_t last,
                         std::vector<Contact>& out);

}  // namespace hail
