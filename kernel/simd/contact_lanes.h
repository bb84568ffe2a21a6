#pragma once
// One staged contact batch in registers, a lane per contact: the bodies' velocities and mass
// properties (kernel/simd/body_rows.h) and the contact's normal, the bodies of the rules of
// kernel/solver/impulse_rules.h (the scalar rules' own, run on batches). Shared by the passes of
// kernel/simd/contact_solve.cpp (Solver::Passes) and kernel/simd/contact_soft.cpp
// (Solver::SoftStep). Included only by kernel/simd/ translation units (compiled once per path).

#include <cstddef>

#include "kernel/dispatch/simd_arch.h"
#include "kernel/simd/body_rows.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/impulse_rules.h"
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
};

}  // namespace
}  // namespace HAIL_SIMD_NS
}  // namespace hail
