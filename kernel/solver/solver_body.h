#pragma once
// The solver's copy of each sphere's velocity and mass properties, one 64-byte cache line per
// sphere. The SoA (include/hail/sphere_soa.h) spreads a sphere over a dozen arrays, which suits the
// per-sphere phases; the solver instead visits contacts in colour order, i.e. spheres at
// random, and gathering a body from the SoA touches up to nine lines where this touches one.
// The solve phase copies velocities in, runs every pass on these, and copies them back; the
// values and the float operations are the same, so the result is bitwise the same.

#include <cstddef>
#include <cstdint>
#include <span>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "kernel/solver/contact_impulse.h"

namespace hail {

struct alignas(64) SolverBody {
  float v[3];
  float inv_mass;
  float w[3];
  float inv_inertia;
  float radius;
  /// 1 + the last collision pass that changed this body's velocity (0: none this step). A
  /// contact neither of whose bodies changed since it last applied nothing cannot apply now, so
  /// collision passes skip it (kernel/solver/contact_solve_simd.h): the same result, less work.
  std::uint32_t changed_in_pass;
  /// The soft step's (kernel/solver/soft_step.h): the gravity scale a substep's g h is
  /// multiplied by (0 for immovable spheres), and the displacement dp since the step began,
  /// from which the contacts' separations follow (the fourth float of dp's group is unused).
  float gravity_scale;
  float unused;
  float dp[3];
  float unused_after_dp;
};
static_assert(sizeof(SolverBody) == 64, "one solver body per cache line");
static_assert(offsetof(SolverBody, dp) == 48, "dp is the fourth group of four floats (kernel/simd/body_rows.h)");

/// Copies spheres [first, last) of the SoA into bodies; angular velocities only when the passes
/// will use them (`angular`: FrictionWork kWithFriction), else the bodies' w is left as it was.
inline void load_solver_bodies(const SphereSoA& s, std::size_t first, std::size_t last, std::span<SolverBody> bodies,
                               bool angular = true) {
  for (std::size_t i = first; i < last; ++i) {
    SolverBody& b = bodies[i];
    b.v[0] = s.vx[i];
    b.v[1] = s.vy[i];
    b.v[2] = s.vz[i];
    if (angular) b.w[0] = s.wx[i], b.w[1] = s.wy[i], b.w[2] = s.wz[i];
    b.inv_mass = s.inv_mass[i];
    b.inv_inertia = s.inv_inertia[i];
    b.radius = s.radius[i];
    b.changed_in_pass = 0;
  }
}

/// Writes the velocities of bodies [first, last) back to the SoA (angular ones when `angular`,
/// as load_solver_bodies read them).
inline void store_solver_velocities(std::span<const SolverBody> bodies, std::size_t first, std::size_t last,
                                    SphereSoA& s, bool angular = true) {
  for (std::size_t i = first; i < last; ++i) {
    const SolverBody& b = bodies[i];
    s.vx[i] = b.v[0];
    s.vy[i] = b.v[1];
    s.vz[i] = b.v[2];
    if (angular) s.wx[i] = b.w[0], s.wy[i] = b.w[1], s.wz[i] = b.w[2];
  }
}

/// The closing speed along c's normal that this step's gravity added to its bodies (predict):
/// (g dt . n) (scale_a - scale_b), `gravity_dt` = g dt, scales from SolverBody::gravity_scale
/// (the static body's is 0). Zero between spheres of one scale. solve_collision's
/// `gravity_closing` under Integrator::UniformAcceleration.
[[nodiscard]] inline float gravity_closing_speed(std::span<const SolverBody> bodies, const Contact& c,
                                                 const float gravity_dt[3]) {
  const float scale_b = c.b != kStaticBody ? bodies[c.b].gravity_scale : 0.0f;
  const float gn = gravity_dt[0] * c.nx + gravity_dt[1] * c.ny + gravity_dt[2] * c.nz;
  return gn * (bodies[c.a].gravity_scale - scale_b);
}

/// gather_bodies (kernel/solver/contact_impulse.h) from solver bodies: the same values.
template <FrictionWork kWork = kWithFriction>
inline ContactBodies gather_bodies(std::span<const SolverBody> bodies, const Contact& c) {
  ContactBodies k;
  const SolverBody& a = bodies[c.a];
  k.ima = a.inv_mass;
  k.iia = a.inv_inertia;
  k.ra = a.radius;
  k.va[0] = a.v[0];
  k.va[1] = a.v[1];
  k.va[2] = a.v[2];
  if constexpr (has_rotation(kWork)) {
    k.wa[0] = a.w[0];
    k.wa[1] = a.w[1];
    k.wa[2] = a.w[2];
  }
  if (c.b != kStaticBody) {
    const SolverBody& b = bodies[c.b];
    k.imb = b.inv_mass;
    k.iib = b.inv_inertia;
    k.rb = b.radius;
    k.vb[0] = b.v[0];
    k.vb[1] = b.v[1];
    k.vb[2] = b.v[2];
    if constexpr (has_rotation(kWork)) {
      k.wb[0] = b.w[0];
      k.wb[1] = b.w[1];
      k.wb[2] = b.w[2];
    }
  }
  return k;
}

/// scatter_bodies to solver bodies.
template <FrictionWork kWork = kWithFriction>
inline void scatter_bodies(std::span<SolverBody> bodies, const Contact& c, const ContactBodies& k) {
  SolverBody& a = bodies[c.a];
  a.v[0] = k.va[0];
  a.v[1] = k.va[1];
  a.v[2] = k.va[2];
  if constexpr (has_rotation(kWork)) {
    a.w[0] = k.wa[0];
    a.w[1] = k.wa[1];
    a.w[2] = k.wa[2];
  }
  if (c.b != kStaticBody) {
    SolverBody& b = bodies[c.b];
    b.v[0] = k.vb[0];
    b.v[1] = k.vb[1];
    b.v[2] = k.vb[2];
    if constexpr (has_rotation(kWork)) {
      b.w[0] = k.wb[0];
      b.w[1] = k.wb[1];
      b.w[2] = k.wb[2];
    }
  }
}

}  // namespace hail
