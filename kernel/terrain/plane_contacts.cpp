#include "kernel/terrain/plane_contacts.h"

#include "kernel/broadphase/sphere_pairs.h"

namespace hail {

void find_plane_contacts(const SphereSoA& s, std::span<const Plane> planes, std::size_t first, std::size_t last,
                         std::vector<Contact>& out) {
  for (std::size_t i = first; i < last; ++i) {
    for (std::uint32_t k = 0; k < planes.size(); ++k) {
      const Plane& p = planes[k];
      const float gap = plane_gap(p, s.px[i], s.py[i], s.pz[i], s.radius[i]);
      if (!plane_touching(p, s.px[i], s.py[i], s.pz[i], s.radius[i], gap)) continue;
      Contact c;
      c.a = static_cast<std::uint32_t>(i);
      c.b = kStaticBody;
      c.nx = -p.nx;  // from the sphere into the surface
      c.ny = -p.ny;
      c.nz = -p.nz;
      c.gap = gap;
      c.surface_d = -p.offset;
      c.restitution = combine_restitution(s.restitution[i], p.restitution);
      c.friction = combine_friction(s.friction[i], p.friction);
      c.feature = kPlaneFeature | k;
      out.push_back(c);
    }
  }
}

}  // namespace hail
