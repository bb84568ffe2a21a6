// The SIMD collision, warm-start and resting passes over staged contact batches
// (kernel/solver/contact_solve_simd.h), a batch of contacts per instruction. Compiled once per SIMD
// path (kernel/dispatch/simd_arch.h). Each lane performs the float operations of the scalar rules of
// kernel/solver/contact_impulse.h in their order, so every path gives their bits.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include <cstddef>

#include "kernel/simd/body_rows.h"
#include "kernel/simd/kernels.h"
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

namespace {

template <FrictionWork kWork>
bool collision_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                    std::size_t body_count, float dt, float restitution_threshold, std::uint32_t pass) {
  constexpr bool kFriction = has_rotation(kWork);  // Lanes' angular terms
  // c.width == W: ContactBatches::plan laid the batches out for this path and keeps its table.
  const batch zero(0.0f), one(1.0f);
  const index_batch changed_since(static_cast<std::int32_t>(pass));
  bool any = false;
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    if (pass > 0) {
      // Skip when no body of the batch changed in the previous pass or since (stamp >= pass).
      const index_batch sa = load_body_stamps(bodies, c.a + o), sb = load_body_stamps(bodies, c.b + o);
      if (!xsimd::any((sa >= changed_since) | (sb >= changed_since))) continue;
    }
    Lanes<kFriction> L(c, k, o, bodies, body_count, Lanes<kFriction>::kDeferAngular);
    const batch closing = -L.normal_velocity();
    const batch gap = batch::load_aligned(c.gap + o);
    const batch kn = L.ima + L.imb;
    const lane_mask closing_fast = !(closing <= batch(restitution_threshold));
    const lane_mask gap_stays_open = (gap > zero) & (closing * batch(dt) <= gap);
    const lane_mask movable = !(kn <= zero);
    const lane_mask active = closing_fast & !gap_stays_open & movable;
    const std::uint32_t lanes = lane_bits(active);
    if (lanes == 0) continue;  // nothing changes: no scatter needed
    L.load_angular();
    any = true;
    const batch j = (one + batch::load_aligned(c.restitution + o)) * closing * (one / kn);
    const batch bounce = batch::load_aligned(c.bounce_impulse + o);
    xsimd::select(active, bounce + j, bounce).store_aligned(c.bounce_impulse + o);
    if constexpr (has_friction(kWork)) {
      batch vt[3], fresh[3] = {zero, zero, zero}, delta[3];
      L.tangential_slip(vt);
      L.friction_impulse(vt, batch::load_aligned(c.friction + o) * j, fresh, active, delta);
      L.apply_contact_impulse(j, delta, active);
    } else {
      const batch p[3] = {j * L.n[0], j * L.n[1], j * L.n[2]};
      L.apply_linear_impulse(p, active);
    }
    L.scatter();
    for (std::uint32_t rest = lanes; rest != 0; rest &= rest - 1) {
      const std::size_t l = lowest_lane(rest);
      L.body_a[l]->changed_in_pass = pass + 1;
      if (L.body_b[l] != L.static_body) L.body_b[l]->changed_in_pass = pass + 1;
    }
  }
  return any;
}

template <FrictionWork kWork>
void resting_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                  std::size_t body_count, float inv_dt) {
  constexpr bool kFriction = has_rotation(kWork);  // Lanes' angular terms
  const batch zero(0.0f);
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    Lanes<kFriction> L(c, k, o, bodies, body_count, Lanes<kFriction>::kDeferAngular);
    const batch vn = L.normal_velocity();
    const batch gap = batch::load_aligned(c.gap + o);
    const batch allowed_closing = xsimd::select(gap > zero, gap * batch(inv_dt), zero);
    const batch kn = L.ima + L.imb;
    const batch impulse = batch::load_aligned(c.normal_impulse + o);
    batch accumulated[3] = {batch::load_aligned(c.tx + o), batch::load_aligned(c.ty + o),
                            batch::load_aligned(c.tz + o)};
    const lane_mask idle = (impulse == zero) & (accumulated[0] == zero) & (accumulated[1] == zero) &
                           (accumulated[2] == zero) & (vn + allowed_closing >= zero);  // resting_idle
    const lane_mask active = !(kn <= zero) & !idle;
    // A batch of idle contacts (the staging groups the speculative ones, kernel/solver/contact_colouring.h)
    // changes nothing: no angular loads, no friction, no stores.
    if (lane_bits(active) == 0) continue;
    L.load_angular();
    batch vt[3];  // first: the normal impulse does not change it, and its chain runs beside the normal one
    if constexpr (has_friction(kWork)) L.tangential_slip(vt);
    const batch lambda = impulse - (vn + allowed_closing) * (batch(1.0f) / kn);  // solve_resting's reciprocal
    const batch clamped = xsimd::select(lambda > zero, lambda, zero);
    const batch dj = clamped - impulse;
    const batch new_impulse = xsimd::select(active, clamped, impulse);
    new_impulse.store_aligned(c.normal_impulse + o);
    if constexpr (has_friction(kWork)) {
      batch delta[3];
      L.friction_impulse(vt, batch::load_aligned(c.friction + o) * new_impulse, accumulated, active, delta);
      L.apply_contact_impulse(dj, delta, active);
      accumulated[0].store_aligned(c.tx + o), accumulated[1].store_aligned(c.ty + o),
          accumulated[2].store_aligned(c.tz + o);
    } else {
      const batch p[3] = {dj * L.n[0], dj * L.n[1], dj * L.n[2]};
      L.apply_linear_impulse(p, active);
    }
    L.scatter();
  }
}

template <FrictionWork kWork>
void warm_start_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                     std::size_t body_count) {
  constexpr bool kFriction = has_rotation(kWork);  // Lanes' angular terms
  const batch zero(0.0f);
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    const batch impulse = batch::load_aligned(c.normal_impulse + o);
    const batch t[3] = {batch::load_aligned(c.tx + o), batch::load_aligned(c.ty + o), batch::load_aligned(c.tz + o)};
    // apply_warm_start leaves out contacts with no impulse: a batch of them loads no body.
    const lane_mask holds = !((impulse == zero) & (t[0] == zero) & (t[1] == zero) & (t[2] == zero));
    if (lane_bits(holds) == 0) continue;
    Lanes<kFriction> L(c, k, o, bodies, body_count);
    const lane_mask active = (!((L.ima + L.imb) <= zero)) & holds;
    if constexpr (has_friction(kWork)) {
      const batch p[3] = {impulse * L.n[0] + t[0], impulse * L.n[1] + t[1], impulse * L.n[2] + t[2]};
      L.apply_linear_impulse(p, active);
      if constexpr (kFriction) L.apply_angular_impulse(t, active);  // apply_warm_start's
    } else {
      const batch p[3] = {impulse * L.n[0], impulse * L.n[1], impulse * L.n[2]};
      L.apply_linear_impulse(p, active);
    }
    L.scatter();
  }
}

}  // namespace

// kWithFriction runs kRotationWork: the angular passes are not compiled without rotation
// (HAIL_WITH_ROTATION=OFF), where World never asks for them.
bool contact_collision(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                       std::size_t body_count, float dt, float restitution_threshold, std::uint32_t pass,
                       FrictionWork work) {
  switch (work) {
    case kNoFriction:
      return collision_pass<kNoFriction>(c, first, last, bodies, body_count, dt, restitution_threshold, pass);
    case kLinearFriction:
      return collision_pass<kLinearFriction>(c, first, last, bodies, body_count, dt, restitution_threshold, pass);
    case kWithFriction:
      break;
  }
  return collision_pass<kRotationWork>(c, first, last, bodies, body_count, dt, restitution_threshold, pass);
}

void contact_resting(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                     std::size_t body_count, float inv_dt, FrictionWork work) {
  switch (work) {
    case kNoFriction:
      return resting_pass<kNoFriction>(c, first, last, bodies, body_count, inv_dt);
    case kLinearFriction:
      return resting_pass<kLinearFriction>(c, first, last, bodies, body_count, inv_dt);
    case kWithFriction:
      break;
  }
  resting_pass<kRotationWork>(c, first, last, bodies, body_count, inv_dt);
}

void contact_warm_start(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                        std::size_t body_count, FrictionWork work) {
  switch (work) {
    case kNoFriction:
      return warm_start_pass<kNoFriction>(c, first, last, bodies, body_count);
    case kLinearFriction:
      return warm_start_pass<kLinearFriction>(c, first, last, bodies, body_count);
    case kWithFriction:
      break;
  }
  warm_start_pass<kRotationWork>(c, first, last, bodies, body_count);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
