#pragma once
// Per-contact impulse rules (after "Game Physics Cookbook", with its known traps removed).
//
// The solver runs two kinds of pass (Guendelman, Bridson & Fedkiw 2003, "Nonconvex rigid
// bodies with stacking"):
//  * collision passes: every contact closing faster than the restitution threshold gets the
//    impulse j = (1 + e) * closing / K computed from the *current* relative velocity, so chains
//    of contacts pass momentum along one by one (Newton's cradle gives its textbook answer);
//  * resting passes: accumulated, clamped impulses (Catto's sequential impulses) driving the
//    closing speed to zero (or to what closes a speculative gap), with friction clamped to
//    +-mu * (the same contact's accumulated normal impulse).
// Friction in both: a Coulomb cone around the tangential slip, with the angular impulse so that
// spheres spin and roll (or, with rotation off, on the linear velocities alone: FrictionWork).
// The slip is taken before the contact's normal impulse, which cannot change it (exactly so in
// real arithmetic), and both impulses are applied at once: the normal and the friction work of
// a contact then run side by side in the SIMD passes instead of one after the other.
// No damping, no snapping of small velocities to zero.

#include <cmath>
#include <cstdint>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "kernel/solver/impulse_rules.h"

namespace hail {

/// Velocity state of one contact's two bodies, gathered from the SoA (static side: all zero).
/// Modes without rotation neither read nor write w (it stays zero here).
struct ContactBodies {
  float ima = 0, iia = 0, ra = 0;  // inverse mass, inverse inertia, radius of a
  float imb = 0, iib = 0, rb = 0;
  float va[3] = {0, 0, 0}, wa[3] = {0, 0, 0};
  float vb[3] = {0, 0, 0}, wb[3] = {0, 0, 0};
};

template <FrictionWork kWork = kWithFriction>
inline ContactBodies gather_bodies(const SphereSoA& s, const Contact& c) {
  ContactBodies k;
  const std::uint32_t a = c.a;
  k.ima = s.inv_mass[a];
  k.iia = s.inv_inertia[a];
  k.ra = s.radius[a];
  k.va[0] = s.vx[a];
  k.va[1] = s.vy[a];
  k.va[2] = s.vz[a];
  if constexpr (has_rotation(kWork)) {
    k.wa[0] = s.wx[a];
    k.wa[1] = s.wy[a];
    k.wa[2] = s.wz[a];
  }
  if (c.b != kStaticBody) {
    const std::uint32_t b = c.b;
    k.imb = s.inv_mass[b];
    k.iib = s.inv_inertia[b];
    k.rb = s.radius[b];
    k.vb[0] = s.vx[b];
    k.vb[1] = s.vy[b];
    k.vb[2] = s.vz[b];
    if constexpr (has_rotation(kWork)) {
      k.wb[0] = s.wx[b];
      k.wb[1] = s.wy[b];
      k.wb[2] = s.wz[b];
    }
  }
  return k;
}

template <FrictionWork kWork = kWithFriction>
inline void scatter_bodies(SphereSoA& s, const Contact& c, const ContactBodies& k) {
  const std::uint32_t a = c.a;
  s.vx[a] = k.va[0];
  s.vy[a] = k.va[1];
  s.vz[a] = k.va[2];
  if constexpr (has_rotation(kWork)) {
    s.wx[a] = k.wa[0];
    s.wy[a] = k.wa[1];
    s.wz[a] = k.wa[2];
  }
  if (c.b != kStaticBody) {
    const std::uint32_t b = c.b;
    s.vx[b] = k.vb[0];
    s.vy[b] = k.vb[1];
    s.vz[b] = k.vb[2];
    if constexpr (has_rotation(kWork)) {
      s.wx[b] = k.wb[0];
      s.wy[b] = k.wb[1];
      s.wz[b] = k.wb[2];
    }
  }
}

/// The contact's normal, as the rules of kernel/solver/impulse_rules.h take it.
struct ContactNormal {
  float n[3];
  explicit ContactNormal(const Contact& c) : n{c.nx, c.ny, c.nz} {}
};

/// (vb - va) . n (impulse::normal_relative_velocity).
inline float normal_relative_velocity(const Contact& c, const ContactBodies& k) {
  return impulse::normal_relative_velocity(k, ContactNormal(c).n);
}

/// The linear part of an impulse p (N s): +p on b, -p on a.
inline void apply_linear_impulse(ContactBodies& k, const float p[3]) { impulse::apply_linear_impulse(k, p, true); }

/// Effective mass denominator along the normal (no lever arm for spheres).
inline float normal_mass_denominator(const ContactBodies& k) { return k.ima + k.imb; }

/// Impact found by the integrator at its exact time: bounce with restitution when closing
/// faster than the threshold, else stop the closing motion; friction within mu * j. Returns the
/// normal impulse j applied (N s), 0 when the bodies were not closing. kWork: kWithFriction, or
/// kLinearFriction without rotation (the friction cone is applied either way, as before: with
/// zero friction it applies nothing).
template <FrictionWork kWork = kWithFriction>
inline float solve_impact(const Contact& c, ContactBodies& k, float restitution_threshold) {
  static_assert(has_friction(kWork));
  const float closing = -normal_relative_velocity(c, k);
  const float kn = normal_mass_denominator(k);
  if (closing <= 0.0f || kn <= 0.0f) return 0.0f;
  const float e = closing > restitution_threshold ? c.restitution : 0.0f;
  const float j = (1.0f + e) * closing * (1.0f / kn);
  impulse::apply_impact_impulse<kWork>(k, ContactNormal(c).n, j, c.friction, true);
  return j;
}

/// Warm start of one contact: applies the impulse it starts the step with (normal_impulse along
/// n plus the friction impulse), which the resting passes then treat as already applied.
/// A contact with no impulse to start from (a new one, or one that ended the last step with
/// none) is left out: its impulse of zero would change nothing but the sign of a zero velocity
/// (as in resting_idle), and the SIMD pass skips batches of them whole.
template <FrictionWork kFriction = kWithFriction>
inline void apply_warm_start(const Contact& c, ContactBodies& k) {
  if (normal_mass_denominator(k) <= 0.0f) return;
  if (holds_no_impulse(c)) return;
  if constexpr (!has_friction(kFriction)) {
    const float p[3] = {c.normal_impulse * c.nx, c.normal_impulse * c.ny, c.normal_impulse * c.nz};
    apply_linear_impulse(k, p);
    return;
  }
  // Only the friction part turns the spheres (the normal part passes through their centres).
  const float t[3] = {c.tx, c.ty, c.tz};
  impulse::apply_contact_impulse<kFriction>(k, ContactNormal(c).n, c.normal_impulse, t, true);
}

/// Collision pass on one contact. Returns true when it applied an impulse, whose normal part j
/// it adds to c.bounce_impulse (the bounce an embedder reads; nothing in the solve reads it).
/// A speculative contact (gap > 0) collides only if it closes the gap within dt.
///
/// `gravity_closing`: how much of the closing speed this step's gravity added (predict), the
/// contact's gravity_closing_speed under Integrator::UniformAcceleration, else 0. The bodies
/// then approach at closing - gravity_closing (their start-of-step velocities), and move over
/// the step by the mean of the two, (closing - gravity_closing / 2) dt: restitution and its
/// threshold take the approach speed, the impulse stops the whole closing speed and gives back
/// e times the approach, and the speculative test the mean. With 0 it is the rule as it was
/// (semi-implicit Euler moves with the end velocity). Without it a sphere resting on terrain
/// under the uniform integrator was bounced by e (its approach + g dt), from up to g dt^2 / 2
/// above the ground, and never settled (docs/accuracy.md).
template <FrictionWork kFriction = kWithFriction>
inline bool solve_collision(Contact& c, ContactBodies& k, float dt, float restitution_threshold,
                            float gravity_closing = 0.0f) {
  const float closing = -normal_relative_velocity(c, k);
  // closing > 0 as well: bodies that approached but which a gravity scale difference already
  // separates need no impulse (with gravity_closing 0 the threshold, >= 0, implies it).
  if (closing - gravity_closing <= restitution_threshold || !(closing > 0.0f)) return false;
  if (c.gap > 0.0f && (closing - 0.5f * gravity_closing) * dt <= c.gap) return false;
  const float kn = normal_mass_denominator(k);
  if (kn <= 0.0f) return false;
  const float j = ((1.0f + c.restitution) * closing - c.restitution * gravity_closing) * (1.0f / kn);
  c.bounce_impulse += j;
  impulse::apply_impact_impulse<kFriction>(k, ContactNormal(c).n, j, c.friction, true);
  return true;
}

/// A contact's accumulated normal impulse becomes `total` clamped at >= 0, with friction within
/// mu times it (impulse::apply_clamped_impulse, the end of solve_resting and solve_soft).
template <FrictionWork kFriction = kWithFriction>
inline void accumulate_clamped_impulse(Contact& c, ContactBodies& k, float total) {
  float accumulated[3] = {c.tx, c.ty, c.tz};
  c.normal_impulse = impulse::apply_clamped_impulse<kFriction>(k, ContactNormal(c).n, c.normal_impulse, total,
                                                               c.friction, accumulated, true);
  if constexpr (has_friction(kFriction)) c.tx = accumulated[0], c.ty = accumulated[1], c.tz = accumulated[2];
}

/// Whether a resting pass leaves contact c as it is: it holds no impulse (normal or friction)
/// and its bodies close no faster than its gap allows (vn + allowed_closing >= 0), so the
/// clamped normal impulse stays zero and friction, limited to mu * 0, stays zero too. Most
/// speculative contacts are such in every pass (terrain-rain: about half the contact
/// evaluations of the resting passes and more in larger piles, docs/benchmarks.md, "Figures
/// behind the code's choices"). Their rule would add impulses of zero; skipping it
/// differs only in the sign of a velocity that is exactly zero (x - 0 is x, but -0 + 0 is +0)
/// and in a slip small enough that its square underflows, so SIMD batches of such contacts
/// skip their angular loads, their friction and their stores (kernel/simd/contact_solve.cpp).
[[nodiscard]] inline bool resting_idle(const Contact& c, float vn, float allowed_closing) {
  return holds_no_impulse(c) && vn + allowed_closing >= 0.0f;
}

/// Resting pass on one contact: accumulated normal impulse >= 0 making the closing speed at
/// most gap/dt (zero for overlapping contacts), then friction within mu * that impulse.
/// Nothing for a contact that resting_idle leaves as it is.
template <FrictionWork kFriction = kWithFriction>
inline void solve_resting(Contact& c, ContactBodies& k, float inv_dt) {
  const float vn = normal_relative_velocity(c, k);
  const float allowed_closing = c.gap > 0.0f ? c.gap * inv_dt : 0.0f;
  const float kn = normal_mass_denominator(k);
  if (kn <= 0.0f || resting_idle(c, vn, allowed_closing)) return;
  const float lambda = c.normal_impulse - (vn + allowed_closing) * (1.0f / kn);
  accumulate_clamped_impulse<kFriction>(c, k, lambda);
}

}  // namespace hail
