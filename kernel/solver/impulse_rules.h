#pragma once
// The impulse rules of a contact written once for both lane types: V = float for one contact
// (the scalar rules of kernel/solver/contact_impulse.h and soft_contact.h, the reference) and
// V = an xsimd batch for a contact per lane (the SIMD passes of kernel/simd/contact_solve.cpp
// and contact_soft.cpp, through kernel/simd/contact_lanes.h). The same float operations in the
// same order for either, so every lane has the scalar bits: hail builds with
// -ffp-contract=off, so no multiply-add is fused in one and not in the other.
//
// The bodies `k` are ContactBodies (one contact) or the SIMD Lanes: both have the fields ima,
// iia, ra, imb, iib, rb (V) and va, wa, vb, wb (V[3]); `n` is the contact normal. A lane that
// is not `active` (M: a bool for one contact, an xsimd batch_bool per lane) keeps what it had:
// select() picks per lane, and for a float it is ?:, so a scalar rule with active true
// computes exactly the plain expression. An xsimd batch finds xsimd's select and sqrt by
// argument-dependent lookup; this layer includes no xsimd.

#include <cmath>
#include <cstdint>

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

namespace impulse {

/// One contact's select and sqrt (an xsimd batch takes xsimd's).
[[nodiscard, gnu::always_inline]] inline float select(bool take, float a, float b) { return take ? a : b; }
[[nodiscard, gnu::always_inline]] inline float sqrt(float v) { return std::sqrt(v); }

/// Velocity of b relative to a at the contact point. The contact point sits at +n ra from a's
/// centre and -n rb from b's, so w x r contributes the rolling/spinning part (none without
/// rotation).
template <FrictionWork kWork, class B, class V>
[[gnu::always_inline]] inline void relative_velocity(const B& k, const V n[3], V out[3]) {
  if constexpr (!has_rotation(kWork)) {
    for (int d = 0; d < 3; ++d) out[d] = k.vb[d] - k.va[d];
  } else {
    const V ra[3] = {n[0] * k.ra, n[1] * k.ra, n[2] * k.ra};
    const V rb[3] = {-n[0] * k.rb, -n[1] * k.rb, -n[2] * k.rb};
    const V wa_x_ra[3] = {k.wa[1] * ra[2] - k.wa[2] * ra[1], k.wa[2] * ra[0] - k.wa[0] * ra[2],
                          k.wa[0] * ra[1] - k.wa[1] * ra[0]};
    const V wb_x_rb[3] = {k.wb[1] * rb[2] - k.wb[2] * rb[1], k.wb[2] * rb[0] - k.wb[0] * rb[2],
                          k.wb[0] * rb[1] - k.wb[1] * rb[0]};
    for (int d = 0; d < 3; ++d) out[d] = (k.vb[d] + wb_x_rb[d]) - (k.va[d] + wa_x_ra[d]);
  }
}

/// The normal component of relative_velocity, (vb - va) . n: for spheres the lever arms lie
/// along n, so w x r is perpendicular to n and drops out. Computed without it, it is the exact
/// answer; through w x r the float products of parallel vectors add rounding-size terms.
template <class B, class V>
[[nodiscard, gnu::always_inline]] inline V normal_relative_velocity(const B& k, const V n[3]) {
  const V v[3] = {k.vb[0] - k.va[0], k.vb[1] - k.va[1], k.vb[2] - k.va[2]};
  return v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
}

/// The relative velocity at the contact point less its normal part: the slip friction opposes.
/// A normal impulse leaves it as it is (it moves both bodies along n and turns neither), so the
/// rules may take it before their normal impulse, and friction's work does not wait for that one's.
template <FrictionWork kWork, class B, class V>
[[gnu::always_inline]] inline void tangential_slip(const B& k, const V n[3], V vt[3]) {
  V v[3];
  relative_velocity<kWork>(k, n, v);
  const V vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
  for (int d = 0; d < 3; ++d) vt[d] = v[d] - vn * n[d];
}

/// The tangential effective mass denominator: with the spheres' inertia when they may spin;
/// without rotation as along the normal (ima + imb, no lever arm for spheres).
template <FrictionWork kWork, class B>
[[nodiscard, gnu::always_inline]] inline auto tangent_mass_denominator(const B& k) {
  if constexpr (!has_rotation(kWork))
    return k.ima + k.imb;
  else
    return k.ima + k.imb + k.ra * k.ra * k.iia + k.rb * k.rb * k.iib;
}

/// The linear part of an impulse p (N s): +p on b, -p on a.
template <class B, class V, class M>
[[gnu::always_inline]] inline void apply_linear_impulse(B& k, const V p[3], const M& active) {
  for (int d = 0; d < 3; ++d) {
    k.va[d] = select(active, k.va[d] - p[d] * k.ima, k.va[d]);
    k.vb[d] = select(active, k.vb[d] + p[d] * k.imb, k.vb[d]);
  }
}

/// The angular part of an impulse p (N s) applied at the contact points (+n ra from a's centre,
/// -n rb from b's): only p's component across n turns anything.
template <class B, class V, class M>
[[gnu::always_inline]] inline void apply_angular_impulse(B& k, const V n[3], const V p[3], const M& active) {
  const V ra[3] = {n[0] * k.ra, n[1] * k.ra, n[2] * k.ra};
  const V rb[3] = {-n[0] * k.rb, -n[1] * k.rb, -n[2] * k.rb};
  const V ra_x_p[3] = {ra[1] * p[2] - ra[2] * p[1], ra[2] * p[0] - ra[0] * p[2], ra[0] * p[1] - ra[1] * p[0]};
  const V rb_x_p[3] = {rb[1] * p[2] - rb[2] * p[1], rb[2] * p[0] - rb[0] * p[2], rb[0] * p[1] - rb[1] * p[0]};
  for (int d = 0; d < 3; ++d) {
    k.wa[d] = select(active, k.wa[d] - ra_x_p[d] * k.iia, k.wa[d]);
    k.wb[d] = select(active, k.wb[d] + rb_x_p[d] * k.iib, k.wb[d]);
  }
}

/// A normal impulse j along n and a friction impulse `delta` at once: j n + delta on the linear
/// velocities, delta alone on the angular ones (j n passes through both centres).
template <FrictionWork kWork, class B, class V, class M>
[[gnu::always_inline]] inline void apply_contact_impulse(B& k, const V n[3], const V& j, const V delta[3],
                                                         const M& active) {
  const V p[3] = {j * n[0] + delta[0], j * n[1] + delta[1], j * n[2] + delta[2]};
  apply_linear_impulse(k, p, active);
  if constexpr (has_rotation(kWork)) apply_angular_impulse(k, n, delta, active);
}

/// Friction impulse opposing the slip `vt`, limited to the Coulomb cone |p_t| <= limit.
/// `accumulated` is the friction impulse already applied at this contact (resting passes;
/// zero for a fresh impact); it becomes the new one, and `delta` the change to apply (zero
/// without a tangent mass, and in lanes not `active`). The reciprocal of the mass denominator,
/// as in every rule: the SIMD passes compute it from the masses alone, off the chain of
/// operations on the velocities, and one division replaces three.
template <FrictionWork kWork, class B, class V, class M>
[[gnu::always_inline]] inline void friction_impulse(const B& k, const V vt[3], const V& limit, V accumulated[3],
                                                    M active, V delta[3]) {
  static_assert(has_friction(kWork));
  const V zero(0.0f);
  const V kt = tangent_mass_denominator<kWork>(k);
  active = M(active & !(kt <= zero));
  const V inv_kt = V(1.0f) / kt;
  V target[3] = {accumulated[0] - vt[0] * inv_kt, accumulated[1] - vt[1] * inv_kt, accumulated[2] - vt[2] * inv_kt};
  const V len2 = target[0] * target[0] + target[1] * target[1] + target[2] * target[2];
  const auto over = len2 > limit * limit;
  const V scale = limit / sqrt(len2);
  for (V& t : target) t = select(over, t * scale, t);
  for (int d = 0; d < 3; ++d) {
    delta[d] = select(active, target[d] - accumulated[d], zero);
    accumulated[d] = select(active, target[d], accumulated[d]);
  }
}

/// A normal impulse j and the friction that goes with it, applied together: the friction
/// impulse `accumulated` moves towards stopping the slip (taken before j, which cannot change
/// it) within the cone |p_t| <= limit. Without friction, j n alone on the linear velocities.
template <FrictionWork kWork, class B, class V, class M>
[[gnu::always_inline]] inline void apply_with_friction(B& k, const V n[3], const V& j, const V& limit, V accumulated[3],
                                                       const M& active) {
  if constexpr (has_friction(kWork)) {
    V vt[3], delta[3];
    tangential_slip<kWork>(k, n, vt);
    friction_impulse<kWork>(k, vt, limit, accumulated, active, delta);
    apply_contact_impulse<kWork>(k, n, j, delta, active);
  } else {
    const V p[3] = {j * n[0], j * n[1], j * n[2]};
    apply_linear_impulse(k, p, active);
  }
}

/// An impact's impulse (collision passes, the integrator's and continuous collision's impacts):
/// the normal impulse j with Coulomb friction within mu j of that same impulse, from no
/// friction impulse before it.
template <FrictionWork kWork, class B, class V, class M>
[[gnu::always_inline]] inline void apply_impact_impulse(B& k, const V n[3], const V& j, const V& mu, const M& active) {
  const V zero(0.0f);
  V fresh[3] = {zero, zero, zero};
  apply_with_friction<kWork>(k, n, j, mu * j, fresh, active);
}

/// The end of every accumulated-impulse rule (the resting passes, the soft step's iterations):
/// the contact's accumulated normal impulse `impulse` becomes `total` clamped at >= 0, and its
/// friction impulse `accumulated` moves within the Coulomb cone of mu times that new normal
/// impulse; the change of both is applied at once. Returns the new normal impulse (`impulse`
/// in lanes not `active`).
template <FrictionWork kWork, class B, class V, class M>
[[nodiscard, gnu::always_inline]] inline V apply_clamped_impulse(B& k, const V n[3], const V& impulse, const V& total,
                                                                 const V& mu, V accumulated[3], const M& active) {
  const V zero(0.0f);
  const V clamped = select(total > zero, total, zero);
  const V dj = clamped - impulse;
  const V new_impulse = select(active, clamped, impulse);
  apply_with_friction<kWork>(k, n, dj, mu * new_impulse, accumulated, active);
  return new_impulse;
}

}  // namespace impulse
}  // namespace hail
