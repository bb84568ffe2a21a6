#pragma once
// A contact between a sphere and another sphere or a static surface (plane, terrain).
// Contacts are plain data produced by the detect phase and consumed by solve and depenetrate.

#include <cstdint>

namespace hail {

/// `Contact::b` of a contact whose second body is static geometry (infinite mass).
inline constexpr std::uint32_t kStaticBody = 0xFFFFFFFFu;

struct Contact {
  std::uint32_t a = 0;            ///< dense slot of the first sphere
  std::uint32_t b = kStaticBody;  ///< dense slot of the second sphere, or kStaticBody
  float nx = 0, ny = 1, nz = 0;   ///< unit normal pointing from a towards b (into the surface)
  float gap = 0;                  ///< signed distance between surfaces: < 0 overlapping, > 0 speculative
  float restitution = 0;          ///< effective: min of the two
  float friction = 0;             ///< effective: sqrt of the product (geometric mean)
  float normal_impulse = 0;       ///< accumulated by the resting-contact passes, N s
  float tx = 0, ty = 0, tz = 0;   ///< accumulated friction impulse, N s
  /// Sum of the normal impulses the collision passes gave this contact this step (N s, >= 0):
  /// the bounce, (1 + e) m v_closing for a sphere meeting static ground. 0 when it only rested.
  /// Kept for the embedder (World::last_contacts: sounds); it does not feed back into the solve.
  float bounce_impulse = 0;
  /// For static contacts the surface is linearised as the plane {x : n.x = surface_d}, so the
  /// gap after the sphere moves is surface_d - n.x - r (depenetration recomputes it this way).
  float surface_d = 0;
  /// What b is for a static contact, so that the contact can be found again next step (warm
  /// starting): the terrain triangle (BVH order), kPlaneFeature | plane index or kMeshFeature |
  /// mesh triangle. 0 for spheres.
  std::uint32_t feature = 0;
};

/// Whether c carries no impulse, normal or friction: a new contact, or one the last step left
/// at zero. Branch-free (& rather than &&): which contacts do is a coin toss.
[[nodiscard]] inline bool holds_no_impulse(const Contact& c) {
  return (c.normal_impulse == 0.0f) & (c.tx == 0.0f) & (c.ty == 0.0f) & (c.tz == 0.0f);
}

/// Contact::feature of a plane contact: this bit, or'd with the plane's index.
inline constexpr std::uint32_t kPlaneFeature = 0x80000000u;
/// Contact::feature of a mesh contact: this bit, or'd with the triangle's number among all the
/// world's mesh triangles (each mesh's triangles in its BVH order, meshes in the order added).
inline constexpr std::uint32_t kMeshFeature = 0x40000000u;

/// An impact resolved at its exact time within a step, outside the contact solve: a sphere that
/// reaches a plane during the step (the integrator splits its motion there) or an impact of
/// continuous collision (a swept sphere against terrain, a plane or another sphere). Plain data
/// for the embedder (World::last_impacts); the step itself does not read it back.
struct Impact {
  std::uint32_t a = 0;            ///< dense slot of the sphere
  std::uint32_t b = kStaticBody;  ///< dense slot of the other sphere, or kStaticBody
  std::uint32_t feature = 0;      ///< static b: as Contact::feature (terrain triangle, plane or mesh triangle)
  float time = 0;                 ///< s after the start of the step (of its last substep)
  float px = 0, py = 0, pz = 0;   ///< contact point at that time: a's centre + n * a's radius, m
  float nx = 0, ny = 1, nz = 0;   ///< unit normal pointing from a towards b (into the surface)
  /// Normal impulse applied, N s, > 0: (1 + e) v_closing / (1/m_a + 1/m_b) for a bounce (m_b
  /// infinite for static b), without the 1 + e for one closing no faster than the restitution
  /// threshold (it stops instead).
  float impulse = 0;
};

}  // namespace hail
