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

namespace hail {

/// Which terms a solver rule computes. A normal impulse passes through both centres (r x n = 0)
/// and w x r is perpendicular to n, so every rule takes the normal part on linear velocities
/// alone (normal_relative_velocity, apply_linear_impulse): that is the exact answer, where the
/// angular terms would leave spins of rounding size from the float products of parallel
/// vectors. Without friction (no contact of the step has any) nothing turns a sphere, and the
/// passes drop the angular terms altogether (kNoFriction). Without rotation
/// (WorldSettings::rotation false) friction acts on the linear velocities alone, with the
/// effective mass 1 / (1/m_a + 1/m_b) (kLinearFriction): spheres slide and never spin.
/// kWithFriction is the full rule: friction with the angular impulse that makes spheres spin
/// and roll.
enum FrictionWork : std::uint8_t { kNoFriction, kLinearFriction, kWithFriction };

/// Whether a mode applies friction impulses.
[[nodiscard]] constexpr bool has_friction(FrictionWork work) { return work != kNoFriction; }
/// Whether a mode reads and changes angular velocities (w x r, r x p, inverse inertia).
[[nodiscard]] constexpr bool has_rotation(FrictionWork work) { return work == kWithFriction; }
/// The mode of a step: no friction anywhere, else friction with or without rotation.
[[nodiscard]] constexpr FrictionWork friction_work(bool friction, bool rotation) {
  return !friction ? kNoFriction : rotation ? kWithFriction : kLinearFriction;
}

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

/// Velocity of b relative to a at the contact point. The contact point sits at +n ra from a's
/// centre and -n rb from b's, so w x r contributes the rolling/spinning part.
template <FrictionWork kFriction = kWithFriction>
inline void relative_contact_velocity(const Contact& c, const ContactBodies& k, float out[3]) {
  if constexpr (!has_rotation(kFriction)) {
    for (int d = 0; d < 3; ++d) out[d] = k.vb[d] - k.va[d];
    return;
  }
  const float n[3] = {c.nx, c.ny, c.nz};
  const float ra[3] = {n[0] * k.ra, n[1] * k.ra, n[2] * k.ra};
  const float rb[3] = {-n[0] * k.rb, -n[1] * k.rb, -n[2] * k.rb};
  const float wa_x_ra[3] = {k.wa[1] * ra[2] - k.wa[2] * ra[1], k.wa[2] * ra[0] - k.wa[0] * ra[2],
                            k.wa[0] * ra[1] - k.wa[1] * ra[0]};
  const float wb_x_rb[3] = {k.wb[1] * rb[2] - k.wb[2] * rb[1], k.wb[2] * rb[0] - k.wb[0] * rb[2],
                            k.wb[0] * rb[1] - k.wb[1] * rb[0]};
  for (int d = 0; d < 3; ++d) out[d] = (k.vb[d] + wb_x_rb[d]) - (k.va[d] + wa_x_ra[d]);
}

/// The normal component of relative_contact_velocity, (vb - va) . n: for spheres the lever arms
/// lie along n, so w x r is perpendicular to n and drops out. Computed without it, it is the
/// exact answer; through w x r the float products of parallel vectors add rounding-size terms.
inline float normal_relative_velocity(const Contact& c, const ContactBodies& k) {
  const float v[3] = {k.vb[0] - k.va[0], k.vb[1] - k.va[1], k.vb[2] - k.va[2]};
  return v[0] * c.nx + v[1] * c.ny + v[2] * c.nz;
}

/// The linear part of an impulse p (N s): +p on b, -p on a.
inline void apply_linear_impulse(ContactBodies& k, const float p[3]) {
  for (int d = 0; d < 3; ++d) k.va[d] -= p[d] * k.ima, k.vb[d] += p[d] * k.imb;
}

/// The angular part of an impulse p (N s) applied at the contact points (+n ra from a's centre,
/// -n rb from b's): only p's component across n turns anything.
inline void apply_angular_impulse(const Contact& c, ContactBodies& k, const float p[3]) {
  const float n[3] = {c.nx, c.ny, c.nz};
  const float ra[3] = {n[0] * k.ra, n[1] * k.ra, n[2] * k.ra};
  const float rb[3] = {-n[0] * k.rb, -n[1] * k.rb, -n[2] * k.rb};
  const float ra_x_p[3] = {ra[1] * p[2] - ra[2] * p[1], ra[2] * p[0] - ra[0] * p[2], ra[0] * p[1] - ra[1] * p[0]};
  const float rb_x_p[3] = {rb[1] * p[2] - rb[2] * p[1], rb[2] * p[0] - rb[0] * p[2], rb[0] * p[1] - rb[1] * p[0]};
  for (int d = 0; d < 3; ++d) k.wa[d] -= ra_x_p[d] * k.iia, k.wb[d] += rb_x_p[d] * k.iib;
}

/// Effective mass denominators: along the normal (no lever arm for spheres) and tangentially
/// (with the spheres' inertia when they may spin; without rotation as along the normal).
inline float normal_mass_denominator(const ContactBodies& k) { return k.ima + k.imb; }
template <FrictionWork kFriction = kWithFriction>
inline float tangent_mass_denominator(const ContactBodies& k) {
  if constexpr (!has_rotation(kFriction)) return k.ima + k.imb;
  return k.ima + k.imb + k.ra * k.ra * k.iia + k.rb * k.rb * k.iib;
}

/// The relative velocity at the contact point less its normal part: the slip friction opposes.
/// A normal impulse leaves it as it is (it moves both bodies along n and turns neither), so the
/// rules take it before their normal impulse, and friction's work does not wait for that one's.
template <FrictionWork kFriction = kWithFriction>
inline void tangential_slip(const Contact& c, const ContactBodies& k, float vt[3]) {
  float v[3];
  relative_contact_velocity<kFriction>(c, k, v);
  const float vn = v[0] * c.nx + v[1] * c.ny + v[2] * c.nz;
  vt[0] = v[0] - vn * c.nx, vt[1] = v[1] - vn * c.ny, vt[2] = v[2] - vn * c.nz;
}

/// Friction impulse opposing the slip `vt`, limited to the cone |p_t| <= limit. `accumulated`
/// is the friction impulse already applied at this contact (resting passes; zero for a fresh
/// impact); it becomes the new one, and `delta` the change to apply (zero without a tangent
/// mass). The reciprocal of the mass denominator, as in every rule here: the SIMD passes
/// compute it from the masses alone, off the chain of operations on the velocities, and one
/// division replaces three.
template <FrictionWork kFriction = kWithFriction>
inline void friction_impulse(const ContactBodies& k, const float vt[3], float limit, float accumulated[3],
                             float delta[3]) {
  static_assert(has_friction(kFriction));
  const float kt = tangent_mass_denominator<kFriction>(k);
  if (kt <= 0.0f) {
    delta[0] = delta[1] = delta[2] = 0.0f;
    return;
  }
  const float inv_kt = 1.0f / kt;
  float target[3] = {accumulated[0] - vt[0] * inv_kt, accumulated[1] - vt[1] * inv_kt, accumulated[2] - vt[2] * inv_kt};
  const float len2 = target[0] * target[0] + target[1] * target[1] + target[2] * target[2];
  if (len2 > limit * limit) {
    const float scale = limit / std::sqrt(len2);
    for (float& t : target) t *= scale;
  }
  for (int d = 0; d < 3; ++d) delta[d] = target[d] - accumulated[d], accumulated[d] = target[d];
}

/// A normal impulse j along n and a friction impulse `delta` at once: j n + delta on the linear
/// velocities, delta alone on the angular ones (j n passes through both centres).
template <FrictionWork kFriction = kWithFriction>
inline void apply_contact_impulse(const Contact& c, ContactBodies& k, float j, const float delta[3]) {
  const float p[3] = {j * c.nx + delta[0], j * c.ny + delta[1], j * c.nz + delta[2]};
  apply_linear_impulse(k, p);
  if constexpr (has_rotation(kFriction)) apply_angular_impulse(c, k, delta);
}

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
  float vt[3], fresh[3] = {0, 0, 0}, delta[3];
  tangential_slip<kWork>(c, k, vt);
  friction_impulse<kWork>(k, vt, c.friction * j, fresh, delta);
  apply_contact_impulse<kWork>(c, k, j, delta);
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
  const float p[3] = {c.normal_impulse * c.nx + c.tx, c.normal_impulse * c.ny + c.ty, c.normal_impulse * c.nz + c.tz};
  apply_linear_impulse(k, p);
  // Only the friction part turns the spheres (the normal part passes through their centres).
  if constexpr (has_rotation(kFriction)) {
    const float t[3] = {c.tx, c.ty, c.tz};
    apply_angular_impulse(c, k, t);
  }
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
  if constexpr (has_friction(kFriction)) {
    float vt[3], fresh[3] = {0, 0, 0}, delta[3];
    tangential_slip<kFriction>(c, k, vt);
    friction_impulse<kFriction>(k, vt, c.friction * j, fresh, delta);
    apply_contact_impulse<kFriction>(c, k, j, delta);
  } else {
    const float p[3] = {j * c.nx, j * c.ny, j * c.nz};
    apply_linear_impulse(k, p);
  }
  return true;
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
  const float clamped = lambda > 0.0f ? lambda : 0.0f;
  const float dj = clamped - c.normal_impulse;
  c.normal_impulse = clamped;
  if constexpr (has_friction(kFriction)) {
    float vt[3], accumulated[3] = {c.tx, c.ty, c.tz}, delta[3];
    tangential_slip<kFriction>(c, k, vt);
    friction_impulse<kFriction>(k, vt, c.friction * c.normal_impulse, accumulated, delta);
    apply_contact_impulse<kFriction>(c, k, dj, delta);
    c.tx = accumulated[0];
    c.ty = accumulated[1];
    c.tz = accumulated[2];
  } else {
    const float p[3] = {dj * c.nx, dj * c.ny, dj * c.nz};
    apply_linear_impulse(k, p);
  }
}

}  // namespace hail
