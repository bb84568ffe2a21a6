#pragma once
// What Terrain::find_contacts does for one sphere: how far its contacts reach this step, and
// how each candidate triangle becomes a contact, reduced to one per distinct normal. Shared by
// the scalar reference (Terrain::find_contacts_scalar, one BVH walk per sphere) and the packet
// walk of every SIMD path (kernel/simd/terrain_contacts.cpp), which therefore give the same
// contacts in the same order. Inline code that a per-path translation unit compiles with its
// own flags, so it lives in that path's namespace (kernel/dispatch/simd_namespace.h).

#include <cmath>
#include <cstdint>
#include <new>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/dispatch/simd_namespace.h"
#include "kernel/geometry/fast_motion.h"
#include "kernel/geometry/sphere_triangle.h"
#include "kernel/terrain/terrain_triangles.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

inline constexpr int kMaxTerrainContactsPerSphere = 8;

/// One sphere's terrain contacts while its candidates come in, reduced to one contact per
/// distinct normal (a flat area split into triangles, or the two triangles sharing an internal
/// edge, would otherwise push twice); when full, the deepest are kept.
struct ContactReduction {
  Contact found[kMaxTerrainContactsPerSphere];
  int count = 0;

  /// Where a new contact of normal n, gap `gap` and plane offset `surface_d` goes: merged into
  /// a kept contact of the same normal (the deeper gap kept; then nullptr), else the next free
  /// entry, else the shallowest kept one if the new one is deeper (else nullptr). The caller
  /// writes the whole contact there. `centre`: the sphere's, which the planes are measured from.
  [[nodiscard]] Contact* place(const float n[3], float gap, float surface_d, const float centre[3]) {
    for (int m = 0; m < count; ++m) {
      Contact& kept = found[m];
      const float same = kept.nx * n[0] + kept.ny * n[1] + kept.nz * n[2];
      if (same > 0.99999f) {
        if (gap < kept.gap) {
          kept.gap = gap;
          // The kept normal with the new contact's plane offset would put the plane elsewhere
          // by (n_kept - n_new) . x: up to 0.5% of the distance from the origin, tens of metres
          // at 1e4 m (depenetration then threw spheres). Shift the offset so that the plane
          // sits at the new gap along the kept normal; exact (a no-op) for equal normals.
          kept.surface_d =
              surface_d + ((kept.nx - n[0]) * centre[0] + (kept.ny - n[1]) * centre[1] + (kept.nz - n[2]) * centre[2]);
        }
        return nullptr;
      }
    }
    if (count < kMaxTerrainContactsPerSphere) return &found[count++];
    int worst = 0;
    for (int m = 1; m < count; ++m)
      if (found[m].gap > found[worst].gap) worst = m;
    return gap < found[worst].gap ? &found[worst] : nullptr;
  }
};

/// The reach of a swept fast sphere's terrain contacts, as a fraction of its radius: what it
/// touches, or all but touches. A light sphere pressed against the ground by a heavy one is
/// fast by the heavy one's speed and rests a rounding above the ground, where the guard put it;
/// without its ground contact it took the heavy sphere's whole push and ended inside it.
inline constexpr float kSweptTouchFraction = 0.02f;

/// How far beyond its surface sphere i meets terrain this step: its travel |v| dt, capped for
/// fast spheres (is_fast): a reach of hundreds of metres would gather hundreds of triangles the
/// sphere is not heading for, and bounce it from the nearest one at once. With `sweep_fast`
/// a fast sphere gets only what it touches (kSweptTouchFraction); the sweep meets the rest at
/// its time.
[[nodiscard]] inline float terrain_contact_reach(const SphereSoA& s, std::size_t i, float dt, float fast_fraction,
                                                 bool sweep_fast) {
  const float speed2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
  const float speed = std::sqrt(speed2);
  const bool fast = s.inv_mass[i] > 0.0f && is_fast(speed2, dt, s.radius[i], fast_fraction);
  return fast ? (sweep_fast ? kSweptTouchFraction : fast_fraction) * s.radius[i] : speed * dt;
}

/// Sphere i's contact `st` with terrain triangle k (BVH order) as a Contact, into `reduction`.
/// `restitution` and `friction` are the terrain's.
inline void add_terrain_contact(const SphereSoA& s, std::size_t i, const SphereTriangleContact& st, std::uint32_t k,
                                float restitution, float friction, ContactReduction& reduction) {
  const float centre[3] = {s.px[i], s.py[i], s.pz[i]};
  Contact* const slot = reduction.place(st.n, st.gap, st.surface_d, centre);
  if (slot == nullptr) return;
  // Made in its place: built in a temporary and copied, the copy read back 32 bytes at a time
  // what had just been stored 4 bytes at a time, and store forwarding failed on every contact
  // (perf: docs/benchmarks.md, "Figures behind the code's choices").
  ::new (static_cast<void*>(slot)) Contact{.a = static_cast<std::uint32_t>(i),
                                           .b = kStaticBody,
                                           .nx = st.n[0],
                                           .ny = st.n[1],
                                           .nz = st.n[2],
                                           .gap = st.gap,
                                           .restitution = combine_restitution(s.restitution[i], restitution),
                                           .friction = combine_friction(s.friction[i], friction),
                                           .surface_d = st.surface_d,
                                           .feature = k};  // the first triangle of a merged normal names it
}

/// Sphere i against terrain triangle k (BVH order): the contact goes to `reduction` when the
/// gap is within `margin`. The scalar reference's step; the SIMD kernels test a batch of
/// candidates at once and call the overload above for the ones within reach.
inline void add_terrain_contact(const SphereSoA& s, std::size_t i, const TerrainTriangles& t, std::uint32_t k,
                                float margin, float restitution, float friction, ContactReduction& reduction) {
  const float centre[3] = {s.px[i], s.py[i], s.pz[i]};
  const float a[3] = {t.v0x[k], t.v0y[k], t.v0z[k]}, b[3] = {t.v1x[k], t.v1y[k], t.v1z[k]},
              c[3] = {t.v2x[k], t.v2y[k], t.v2z[k]};
  const float n[3] = {t.nx[k], t.ny[k], t.nz[k]};
  SphereTriangleContact st;
  if (!sphere_triangle_contact(centre, s.radius[i], a, b, c, n, t.d[k], t.internal_edges[k], margin, st)) return;
  add_terrain_contact(s, i, st, k, restitution, friction, reduction);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
