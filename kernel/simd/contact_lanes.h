#pragma once
// One staged contact batch in registers, a lane per contact: the bodies' velocities and mass
// properties (kernel/simd/body_rows.h) and the contact's normal, with the scalar rules of
// kernel/solver/contact_impulse.h as lane operations in their order. Shared by the passes of
// kernel/simd/contact_solve.cpp (Solver::Passes) and kernel/simd/contact_soft.cpp
// (Solver::SoftStep). Included only by kernel/simd/ translation units (compiled once per path).

#include <cstddef>

#include "kernel/dispatch/simd_arch.h"
#include "kernel/simd/body_rows.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/solver_body.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

using batch = xsimd::batch<float, simd_arch>;
using index_batch = xsimd::batch<std::int32_t, simd_arch>;
using lane_mask = xsimd::batch_bool<float, simd_arch>;
constexpr std::size_t W = batch::size;
static_assert(index_batch::size == W);

/// ContactBodies and the contact's normal, one lane per contact. kFriction: the angular terms of
/// friction (FrictionWork kWithFriction). False (kNoFriction, or kLinearFriction: friction without
/// rotation) gathers, changes and scatters no angular velocity: has_rotation() of the mode.
template <bool kFriction>
struct Lanes {
  batch ima, iia, ra, imb, iib, rb;
  batch va[3], wa[3], vb[3], wb[3], n[3];

  // The bodies of each lane.
  SolverBody* body_a[W];
  SolverBody* body_b[W];
  const SolverBody* static_body;
  bool b_static;  // every lane's b is the static body (ContactBatchArrays::static_b)

  /// Lanes of batch k (lane offset o = k W): staged data, velocities loaded from bodies
  /// (kernel/simd/body_rows.h). `bodies` ends with the static body. With `angular` false
  /// (kDeferAngular) the angular group is left for load_angular(): a collision pass decides
  /// from the linear velocities alone whether a batch does anything (normal_velocity).
  static constexpr bool kDeferAngular = false;
  [[gnu::always_inline]] Lanes(const ContactBatchArrays& c, std::size_t k, std::size_t o, SolverBody* bodies,
                               std::size_t body_count, bool angular = true)
      : ra(batch::load_aligned(c.ra + o)),
        rb(batch::load_aligned(c.rb + o)),
        static_body(bodies + body_count - 1),
        b_static(c.static_b[k] != 0) {
    for (std::size_t l = 0; l < W; ++l) body_a[l] = bodies + c.a[o + l], body_b[l] = bodies + c.b[o + l];
    // The fourth float of each group is the inverse mass (inertia): the static body's are zero,
    // as are its velocities, so a static b side is set, not loaded: the same bits.
    load(body_a, kLinearGroup, va, ima);
    if (b_static) {
      vb[0] = vb[1] = vb[2] = imb = batch(0.0f);
    } else {
      load(body_b, kLinearGroup, vb, imb);
    }
    if (angular) load_angular();
    for (int d = 0; d < 3; ++d) n[d] = batch::load_aligned((d == 0 ? c.nx : d == 1 ? c.ny : c.nz) + o);
  }

  /// The angular group of both sides (with kFriction; else the inverse inertias are zero).
  [[gnu::always_inline]] void load_angular() {
    if constexpr (kFriction) {
      load(body_a, kAngularGroup, wa, iia);
      if (b_static) {
        wb[0] = wb[1] = wb[2] = iib = batch(0.0f);
      } else {
        load(body_b, kAngularGroup, wb, iib);
      }
    } else {
      iia = iib = batch(0.0f);  // no angular work reads them
    }
  }

  /// Writes the velocities back, except to the static body: it is every static contact's b,
  /// and both sides of the padding lanes that fill a colour's last batch.
  [[gnu::always_inline]] void scatter() const {
    store(body_a, static_body, kLinearGroup, va, ima);
    if (!b_static) store(body_b, static_body, kLinearGroup, vb, imb);
    if constexpr (kFriction) {
      store(body_a, static_body, kAngularGroup, wa, iia);
      if (!b_static) store(body_b, static_body, kAngularGroup, wb, iib);
    }
  }

  [[gnu::always_inline]] static void load(SolverBody* const* body, std::size_t group, batch v[3], batch& fourth) {
    batch rows[4];
    load_body_group(body, group, rows);
    v[0] = rows[0], v[1] = rows[1], v[2] = rows[2], fourth = rows[3];
  }
  [[gnu::always_inline]] static void store(SolverBody* const* body, const SolverBody* skip, std::size_t group,
                                           const batch v[3], const batch& fourth) {
    const batch rows[4] = {v[0], v[1], v[2], fourth};
    store_body_group(body, skip, group, rows);
  }

  // The functions below are relative_contact_velocity, normal_relative_velocity,
  // apply_linear_impulse, apply_angular_impulse, apply_contact_impulse, tangential_slip and
  // friction_impulse of kernel/solver/contact_impulse.h, operation for operation; `active` lanes
  // change, others keep.

  [[gnu::always_inline]] void relative_velocity(batch out[3]) const {
    if constexpr (!kFriction) {
      for (int d = 0; d < 3; ++d) out[d] = vb[d] - va[d];
      return;
    }
    const batch r_a[3] = {n[0] * ra, n[1] * ra, n[2] * ra};
    const batch r_b[3] = {-n[0] * rb, -n[1] * rb, -n[2] * rb};
    const batch wa_x_ra[3] = {wa[1] * r_a[2] - wa[2] * r_a[1], wa[2] * r_a[0] - wa[0] * r_a[2],
                              wa[0] * r_a[1] - wa[1] * r_a[0]};
    const batch wb_x_rb[3] = {wb[1] * r_b[2] - wb[2] * r_b[1], wb[2] * r_b[0] - wb[0] * r_b[2],
                              wb[0] * r_b[1] - wb[1] * r_b[0]};
    for (int d = 0; d < 3; ++d) out[d] = (vb[d] + wb_x_rb[d]) - (va[d] + wa_x_ra[d]);
  }

  /// normal_relative_velocity: (vb - va) . n, w x r dropping out along n.
  [[nodiscard, gnu::always_inline]] batch normal_velocity() const {
    const batch v[3] = {vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]};
    return v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
  }

  [[gnu::always_inline]] void apply_linear_impulse(const batch p[3], const lane_mask& active) {
    for (int d = 0; d < 3; ++d) {
      va[d] = xsimd::select(active, va[d] - p[d] * ima, va[d]);
      vb[d] = xsimd::select(active, vb[d] + p[d] * imb, vb[d]);
    }
  }

  [[gnu::always_inline]] void apply_angular_impulse(const batch p[3], const lane_mask& active) {
    const batch r_a[3] = {n[0] * ra, n[1] * ra, n[2] * ra};
    const batch r_b[3] = {-n[0] * rb, -n[1] * rb, -n[2] * rb};
    const batch ra_x_p[3] = {r_a[1] * p[2] - r_a[2] * p[1], r_a[2] * p[0] - r_a[0] * p[2],
                             r_a[0] * p[1] - r_a[1] * p[0]};
    const batch rb_x_p[3] = {r_b[1] * p[2] - r_b[2] * p[1], r_b[2] * p[0] - r_b[0] * p[2],
                             r_b[0] * p[1] - r_b[1] * p[0]};
    for (int d = 0; d < 3; ++d) {
      wa[d] = xsimd::select(active, wa[d] - ra_x_p[d] * iia, wa[d]);
      wb[d] = xsimd::select(active, wb[d] + rb_x_p[d] * iib, wb[d]);
    }
  }

  /// apply_contact_impulse: j n + delta on the linear velocities, delta alone on the angular ones.
  [[gnu::always_inline]] void apply_contact_impulse(const batch& j, const batch delta[3], const lane_mask& active) {
    const batch p[3] = {j * n[0] + delta[0], j * n[1] + delta[1], j * n[2] + delta[2]};
    apply_linear_impulse(p, active);
    if constexpr (kFriction) apply_angular_impulse(delta, active);
  }

  /// tangential_slip: the relative velocity at the contact point less its normal part.
  [[gnu::always_inline]] void tangential_slip(batch vt[3]) const {
    batch v[3];
    relative_velocity(v);
    const batch vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    for (int d = 0; d < 3; ++d) vt[d] = v[d] - vn * n[d];
  }

  /// friction_impulse: from the slip `vt`, the change `delta` of the friction impulse
  /// (zero in lanes not `active`, or with no tangent mass), and the new `accumulated`.
  [[gnu::always_inline]] void friction_impulse(const batch vt[3], const batch& limit, batch accumulated[3],
                                               lane_mask active, batch delta[3]) const {
    batch kt = ima + imb;  // tangent_mass_denominator: without rotation as along the normal
    if constexpr (kFriction) kt = ima + imb + ra * ra * iia + rb * rb * iib;
    active = active & !(kt <= batch(0.0f));
    const batch inv_kt = batch(1.0f) / kt;
    batch target[3] = {accumulated[0] - vt[0] * inv_kt, accumulated[1] - vt[1] * inv_kt,
                       accumulated[2] - vt[2] * inv_kt};
    const batch len2 = target[0] * target[0] + target[1] * target[1] + target[2] * target[2];
    const lane_mask over = len2 > limit * limit;
    const batch scale = limit / xsimd::sqrt(len2);
    for (batch& t : target) t = xsimd::select(over, t * scale, t);
    for (int d = 0; d < 3; ++d) {
      delta[d] = xsimd::select(active, target[d] - accumulated[d], batch(0.0f));
      accumulated[d] = xsimd::select(active, target[d], accumulated[d]);
    }
  }
};

}  // namespace
}  // namespace HAIL_SIMD_NS
}  // namespace hail
