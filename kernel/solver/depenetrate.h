#pragma once
// Position correction after integration: push overlapping bodies apart along the contact
// normal, shared by inverse mass. Velocities are untouched, so this can neither add nor remove
// kinetic energy; it only stops overlap from accumulating step after step.

#include <cstdint>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "hail/world_settings.h"

namespace hail {

/// What the SIMD depenetration pass (ContactBatches::depenetrate) reads and moves, by slot:
/// the spheres' positions, radii and inverse masses, and `moved`, the number of the last (pass,
/// colour) that moved each sphere (0: none yet), with one more entry for the static body's slot
/// (static_slot, the number of spheres) that stays 0.
struct DepenetrationArrays {
  float *px, *py, *pz;
  const float* inv_mass;
  std::uint32_t* moved;
  std::int32_t static_slot;
  DepenetrationParams params;
  /// A contact whose smaller radius is below this that pushes from beyond twice the slop sets
  /// the pass's deep flag (push_apart); 0: none does.
  float deep_radius = 0.0f;
};

/// Current signed gap of a contact from the spheres' present positions (normal kept fixed).
inline float current_gap(const SphereSoA& s, const Contact& c) {
  const std::uint32_t a = c.a;
  if (c.b == kStaticBody) return c.surface_d - (c.nx * s.px[a] + c.ny * s.py[a] + c.nz * s.pz[a]) - s.radius[a];
  const std::uint32_t b = c.b;
  return c.nx * (s.px[b] - s.px[a]) + c.ny * (s.py[b] - s.py[a]) + c.nz * (s.pz[b] - s.pz[a]) - s.radius[a] -
         s.radius[b];
}

/// Moves the contact's spheres apart if they overlap beyond the slop, shared by the inverse
/// masses `ima` and `imb` (0: that body holds still); true if it moved them. `deep` is set when
/// it moved them from an overlap beyond twice the slop (the excess over the slop larger than
/// the slop itself) and the smaller radius is below `deep_radius`: the soft step's
/// depenetration goes on while a pass finds one (SoftStepParams::depenetration_iterations_max).
inline bool push_apart_weighted(SphereSoA& s, const Contact& c, const DepenetrationParams& p, float ima, float imb,
                                float deep_radius, bool& deep) {
  const std::uint32_t a = c.a;
  const bool dynamic_b = c.b != kStaticBody;
  const float rmin = dynamic_b && s.radius[c.b] < s.radius[a] ? s.radius[c.b] : s.radius[a];
  const float excess = -current_gap(s, c) - p.slop_fraction * rmin;
  if (excess <= 0.0f) return false;
  const float w = ima + imb;
  if (w <= 0.0f) return false;
  if (excess > p.slop_fraction * rmin && rmin < deep_radius) deep = true;
  const float move = p.fraction * excess / w;
  s.px[a] -= c.nx * move * ima;
  s.py[a] -= c.ny * move * ima;
  s.pz[a] -= c.nz * move * ima;
  if (dynamic_b) {
    const std::uint32_t b = c.b;
    s.px[b] += c.nx * move * imb;
    s.py[b] += c.ny * move * imb;
    s.pz[b] += c.nz * move * imb;
  }
  return true;
}

/// push_apart_weighted by the spheres' own inverse masses (the static body's is 0).
inline bool push_apart(SphereSoA& s, const Contact& c, const DepenetrationParams& p, float deep_radius, bool& deep) {
  return push_apart_weighted(s, c, p, s.inv_mass[c.a], c.b != kStaticBody ? s.inv_mass[c.b] : 0.0f, deep_radius,
                             deep);
}

/// push_apart without the deep flag.
inline bool push_apart(SphereSoA& s, const Contact& c, const DepenetrationParams& p) {
  bool deep = false;
  return push_apart(s, c, p, 0.0f, deep);
}

}  // namespace hail
