#pragma once
// The soft step's per-contact rules (Solver::SoftStep; Catto, "Solver2D", 2024, and Box2D v3's
// contact_solver.c): the scalar reference that kernel/simd/contact_soft.cpp performs lane by
// lane, operation for operation.
//
// A step of dt is cut into substeps of h = dt / substeps. In each, every contact gets one soft
// iteration: an overlapping contact is pushed apart by a spring-damper of the chosen stiffness
// (make_soft), its separation taken from the spheres' displacements since the step began
// (soft_separation: no new collision detection), and a speculative one (separation > 0) may
// close no faster than it reaches contact within the substep. Then rigid relax iterations
// without that push (use_bias false), so that the push does not stay in the velocities.
// Restitution is applied once after the last substep, from the approach speed the contact had
// when the step began (soft_restitution). Friction is the resting rule's: the slip taken
// before the normal impulse, a Coulomb cone of mu times the contact's accumulated normal
// impulse, the angular impulse making spheres roll (impulse::apply_clamped_impulse,
// kernel/solver/impulse_rules.h).
//
// Impulses accumulate per substep (a resting sphere's is m g h): the prepare pass scales the
// staged per-step impulses (Contact::normal_impulse and the friction impulse, as the warm
// start cache keeps them) down by 1 / substeps and the restitution pass scales them back, so
// contacts, the cache and the contact reports keep N s per step as with Solver::Passes.
// During the solve Contact::bounce_impulse holds the approach speed (m/s); the restitution
// pass replaces it with the restitution impulse it applied (N s), the bounce an embedder reads.

#include <cmath>
#include <cstdint>

#include "hail/contact.h"
#include "kernel/solver/contact_impulse.h"

namespace hail {

/// The soft constraint's coefficients for one stiffness (Box2D v3's b2Softness).
struct SoftCoefficients {
  float bias_rate = 0.0f;      ///< 1/s: push speed per metre of overlap
  float mass_scale = 1.0f;     ///< share of the rigid impulse applied
  float impulse_scale = 0.0f;  ///< share of the accumulated impulse taken back (the spring's give)
};

/// b2MakeSoft: a spring of `hertz` and damping ratio `zeta` over a substep of h seconds.
[[nodiscard]] inline SoftCoefficients make_soft(float hertz, float zeta, float h) {
  if (hertz == 0.0f) return {0.0f, 1.0f, 0.0f};
  const float omega = 2.0f * 3.14159265359f * hertz;
  const float a1 = 2.0f * zeta + h * omega;
  const float a2 = h * omega * a1;
  const float a3 = 1.0f / (1.0f + a2);
  return {omega / a1, a2 * a3, a3};
}

/// The overlap at which a soft contact of `hertz` carries a steady acceleration `accel` (m/s^2):
/// accel / omega^2, a length whatever the spheres' size (17 um for a ground contact and 69 um
/// between spheres under gravity at the defaults and dt 1/60).
[[nodiscard]] inline float soft_sag(float accel, float hertz) {
  const float omega = 2.0f * 3.14159265359f * hertz;
  return accel / (omega * omega);
}

/// Which pass of the soft step (the kernel's one entry runs them all).
enum class SoftPassKind : std::uint8_t {
  Prepare,      ///< approach speed into bounce_impulse, impulses to per-substep, bodies marked
  Solve,        ///< one soft iteration (with the push)
  Relax,        ///< one rigid iteration (without it)
  Restitution,  ///< restitution, impulses back to per-step
};

/// What one pass of the soft step needs besides the batches and bodies.
struct SoftPass {
  SoftPassKind kind = SoftPassKind::Solve;
  float inv_h = 0.0f;           ///< 1 / substep
  SoftCoefficients contact{};   ///< sphere-sphere contacts
  SoftCoefficients ground{};    ///< contacts with a side that cannot move (twice as stiff)
  float max_push_speed = 0.0f;  ///< m/s
  float restitution_threshold = 0.0f;
  float impulse_factor = 1.0f;  ///< Prepare: 1 / substeps; Restitution: substeps
};

/// The contact's separation now: its gap when the step began plus how far the spheres have
/// moved apart along its normal since (dp: SolverBody::dp). Spheres turning does not change it.
[[nodiscard]] inline float soft_separation(const Contact& c, const float dpa[3], const float dpb[3]) {
  const float d[3] = {dpb[0] - dpa[0], dpb[1] - dpa[1], dpb[2] - dpa[2]};
  return c.gap + (d[0] * c.nx + d[1] * c.ny + d[2] * c.nz);
}

/// The target closing speed and the softness of a contact at `separation`: a speculative one
/// may close what separates it within the substep (rigid); an overlapping one, with the push
/// (use_bias), is pushed apart at bias_rate times its overlap, below max_push_speed, by a soft
/// impulse; without the push, or overlapping so deeply that the push would reach
/// max_push_speed, it is rigid and held at zero closing speed.
struct SoftTarget {
  float bias = 0.0f, mass_scale = 1.0f, impulse_scale = 0.0f;
};
[[nodiscard]] inline SoftTarget soft_target(const ContactBodies& k, float separation, const SoftPass& p,
                                            bool use_bias) {
  SoftTarget t;
  if (separation > 0.0f) {
    t.bias = separation * p.inv_h;
  } else if (use_bias) {
    const bool ground = k.ima == 0.0f || k.imb == 0.0f;
    const SoftCoefficients& soft = ground ? p.ground : p.contact;
    const float push = soft.bias_rate * separation;
    // An overlap so deep that the push would be saturated (soft_push_saturated) is held rigid
    // without one, as the relax iterations hold it, and left to depenetration, which moves
    // positions and adds no velocity: pushes at the limit summed over the many contacts of 500
    // spheres created at one point threw them at 10.5 m/s, and they landed 5.9% of their radius
    // into the ground (docs/benchmarks.md, soft step).
    if (!(push > -p.max_push_speed)) return t;
    t.bias = push;
    t.mass_scale = soft.mass_scale;
    t.impulse_scale = soft.impulse_scale;
  }
  return t;
}

/// One soft (use_bias) or relax iteration on contact c at `separation`. A contact that holds no
/// impulse and closes no faster than its target is left as it is (as resting_idle: the clamped
/// impulse stays zero, and friction within mu * 0 too).
template <FrictionWork kFriction = kWithFriction>
inline void solve_soft(Contact& c, ContactBodies& k, float separation, const SoftPass& p, bool use_bias) {
  const float vn = normal_relative_velocity(c, k);
  const SoftTarget t = soft_target(k, separation, p, use_bias);
  const float kn = normal_mass_denominator(k);
  if (kn <= 0.0f || (holds_no_impulse(c) && vn + t.bias >= 0.0f)) return;
  const float change = -((vn + t.bias) * (1.0f / kn)) * t.mass_scale - t.impulse_scale * c.normal_impulse;
  accumulate_clamped_impulse<kFriction>(c, k, c.normal_impulse + change);
}

/// Whether a contact's push is saturated at `separation`: it overlaps so deeply that the soft
/// iteration pushes it apart at max_push_speed (soft_target's limit), deeper than any contact
/// at rest sinks (about 17 cm between spheres at the defaults and dt 1/60, 9 cm on the ground).
[[nodiscard]] inline bool soft_push_saturated(const ContactBodies& k, float separation, const SoftPass& p) {
  const bool ground = k.ima == 0.0f || k.imb == 0.0f;
  return !((ground ? p.ground.bias_rate : p.contact.bias_rate) * separation > -p.max_push_speed);
}

/// The prepare pass on one contact: its approach speed (normal relative velocity, negative when
/// closing) into bounce_impulse, its impulses scaled by p.impulse_factor (1 / substeps). A
/// contact whose push is saturated when the step begins starts from no impulse: what it stored
/// was the push of a deep overlap (spheres created inside each other, a fast impact), not a
/// weight it carries, and warm-starting it pushed spheres that had already parted again. 500
/// spheres created at one point were thrown at 89.5 m/s in the second step (kinetic energy 1 kJ
/// -> 516 kJ), their first step having pushed them apart at the limit of 3 m/s
/// (docs/benchmarks.md, soft step).
inline void prepare_soft(Contact& c, const ContactBodies& k, const SoftPass& p) {
  c.bounce_impulse = normal_relative_velocity(c, k);
  const float factor = soft_push_saturated(k, c.gap, p) ? 0.0f : p.impulse_factor;
  c.normal_impulse = c.normal_impulse * factor;
  c.tx = c.tx * factor, c.ty = c.ty * factor, c.tz = c.tz * factor;
}

/// Restitution, once after the last substep (b2ApplyRestitution): a contact that approached
/// faster than the threshold when the step began and still pushes gets the normal impulse that
/// makes it separate at e times that speed; the impulse applied goes into bounce_impulse (0 if
/// none). Then its impulses are scaled by `factor` (substeps), back to N s per step.
inline void soft_restitution(Contact& c, ContactBodies& k, float threshold, float factor) {
  const float approach = c.bounce_impulse;
  const float kn = normal_mass_denominator(k);
  float impulse = c.normal_impulse, applied = 0.0f;
  if (kn > 0.0f && c.restitution != 0.0f && -approach > threshold && impulse != 0.0f) {
    const float vn = normal_relative_velocity(c, k);
    const float change = -(vn + c.restitution * approach) * (1.0f / kn);
    const float total = impulse + change;
    const float clamped = total > 0.0f ? total : 0.0f;
    applied = clamped - impulse;
    impulse = clamped;
    const float p3[3] = {applied * c.nx, applied * c.ny, applied * c.nz};
    apply_linear_impulse(k, p3);
  }
  c.bounce_impulse = applied;
  c.normal_impulse = impulse * factor;
  c.tx = c.tx * factor, c.ty = c.ty * factor, c.tz = c.tz * factor;
}

}  // namespace hail
