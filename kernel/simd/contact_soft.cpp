// The soft step's contact passes (Solver::SoftStep) over staged contact batches, a batch of
// contacts per instruction. Compiled once per SIMD path (kernel/dispatch/simd_arch.h). Each lane
// performs the float operations of kernel/solver/soft_contact.h in their order (the scalar
// reference, soft_run_scalar; the impulses by the same templates, kernel/solver/impulse_rules.h),
// so every path gives its bits (tests/test_soft_step.cpp).

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include <cstddef>

#include "kernel/simd/contact_lanes.h"
#include "kernel/simd/kernels.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/soft_contact.h"
#include "kernel/solver/solver_body.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

/// Float offset in SolverBody of the group {dp[0..2], unused}.
constexpr std::size_t kDisplacementGroup = 12;
static_assert(offsetof(SolverBody, dp) == kDisplacementGroup * sizeof(float));

/// Marks the bodies of every real lane (not the static body) as in a contact.
template <class L>
[[gnu::always_inline]] inline void mark_bodies(const L& lanes) {
  for (std::size_t l = 0; l < W; ++l) {
    if (lanes.body_a[l] != lanes.static_body) lanes.body_a[l]->changed_in_pass = 1;
    if (lanes.body_b[l] != lanes.static_body) lanes.body_b[l]->changed_in_pass = 1;
  }
}

void prepare_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                  std::size_t body_count, const SoftPass& p) {
  const batch zero(0.0f), factor(p.impulse_factor), limit(-p.max_push_speed);
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    const Lanes<false> L(c, k, o, bodies, body_count, Lanes<false>::kDeferAngular);
    impulse::normal_relative_velocity(L, L.n).store_aligned(c.bounce_impulse + o);
    // prepare_soft: a contact whose push is saturated starts from no impulse (soft_push_saturated)
    const lane_mask ground = (L.ima == zero) | (L.imb == zero);
    const batch bias_rate = xsimd::select(ground, batch(p.ground.bias_rate), batch(p.contact.bias_rate));
    const batch f = xsimd::select(bias_rate * batch::load_aligned(c.gap + o) > limit, factor, zero);
    (batch::load_aligned(c.normal_impulse + o) * f).store_aligned(c.normal_impulse + o);
    for (float* t : {c.tx, c.ty, c.tz}) (batch::load_aligned(t + o) * f).store_aligned(t + o);
    mark_bodies(L);
  }
}

/// solve_soft with (Solve) or without (Relax) the push.
template <FrictionWork kWork>
void iteration_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                    std::size_t body_count, const SoftPass& p) {
  constexpr bool kFriction = has_rotation(kWork);  // Lanes' angular terms
  const bool use_bias = p.kind == SoftPassKind::Solve;
  const batch zero(0.0f), one(1.0f);
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    Lanes<kFriction> L(c, k, o, bodies, body_count, Lanes<kFriction>::kDeferAngular);
    batch dpa[4], dpb[4];
    load_body_group(L.body_a, kDisplacementGroup, dpa);
    if (L.b_static) {
      dpb[0] = dpb[1] = dpb[2] = zero;
    } else {
      load_body_group(L.body_b, kDisplacementGroup, dpb);
    }
    // soft_separation
    const batch d[3] = {dpb[0] - dpa[0], dpb[1] - dpa[1], dpb[2] - dpa[2]};
    const batch separation = batch::load_aligned(c.gap + o) + (d[0] * L.n[0] + d[1] * L.n[1] + d[2] * L.n[2]);
    // soft_target
    const lane_mask speculative = separation > zero;
    batch bias = separation * batch(p.inv_h), mass_scale = one, impulse_scale = zero;
    if (use_bias) {
      const lane_mask ground = (L.ima == zero) | (L.imb == zero);
      const batch bias_rate = xsimd::select(ground, batch(p.ground.bias_rate), batch(p.contact.bias_rate));
      const batch push = bias_rate * separation;
      const batch limit(-p.max_push_speed);
      const lane_mask pushing = !speculative & (push > limit);
      bias = xsimd::select(speculative, bias, xsimd::select(pushing, push, zero));
      mass_scale =
          xsimd::select(pushing, xsimd::select(ground, batch(p.ground.mass_scale), batch(p.contact.mass_scale)), one);
      impulse_scale = xsimd::select(
          pushing, xsimd::select(ground, batch(p.ground.impulse_scale), batch(p.contact.impulse_scale)), zero);
    } else {
      bias = xsimd::select(speculative, bias, zero);
    }
    const batch vn = impulse::normal_relative_velocity(L, L.n);
    const batch kn = L.ima + L.imb;
    const batch normal_impulse = batch::load_aligned(c.normal_impulse + o);
    batch accumulated[3] = {batch::load_aligned(c.tx + o), batch::load_aligned(c.ty + o),
                            batch::load_aligned(c.tz + o)};
    const lane_mask idle = (normal_impulse == zero) & (accumulated[0] == zero) & (accumulated[1] == zero) &
                           (accumulated[2] == zero) & (vn + bias >= zero);
    const lane_mask active = !(kn <= zero) & !idle;
    if (lane_bits(active) == 0) continue;
    L.load_angular();
    const batch change = -((vn + bias) * (one / kn)) * mass_scale - impulse_scale * normal_impulse;
    impulse::apply_clamped_impulse<kWork>(L, L.n, normal_impulse, normal_impulse + change,
                                          batch::load_aligned(c.friction + o), accumulated, active)
        .store_aligned(c.normal_impulse + o);
    if constexpr (has_friction(kWork))
      accumulated[0].store_aligned(c.tx + o), accumulated[1].store_aligned(c.ty + o),
          accumulated[2].store_aligned(c.tz + o);
    L.scatter();
  }
}

/// soft_restitution: normal impulses only, so no angular velocity is read or written.
void restitution_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                      std::size_t body_count, float threshold, float factor) {
  const batch zero(0.0f), one(1.0f), f(factor);
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    const batch approach = batch::load_aligned(c.bounce_impulse + o);
    const batch restitution = batch::load_aligned(c.restitution + o);
    const batch normal_impulse = batch::load_aligned(c.normal_impulse + o);
    for (float* t : {c.tx, c.ty, c.tz}) (batch::load_aligned(t + o) * f).store_aligned(t + o);
    const lane_mask bouncing = (!(restitution == zero)) & (-approach > batch(threshold)) & (!(normal_impulse == zero));
    if (lane_bits(bouncing) == 0) {
      zero.store_aligned(c.bounce_impulse + o);
      (normal_impulse * f).store_aligned(c.normal_impulse + o);
      continue;
    }
    Lanes<false> L(c, k, o, bodies, body_count, Lanes<false>::kDeferAngular);
    const batch kn = L.ima + L.imb;
    const lane_mask active = bouncing & (kn > zero);
    const batch vn = impulse::normal_relative_velocity(L, L.n);
    const batch change = -(vn + restitution * approach) * (one / kn);
    const batch total = normal_impulse + change;
    const batch clamped = xsimd::select(total > zero, total, zero);
    const batch applied = xsimd::select(active, clamped - normal_impulse, zero);
    const batch p3[3] = {applied * L.n[0], applied * L.n[1], applied * L.n[2]};
    impulse::apply_linear_impulse(L, p3, active);
    L.scatter();
    applied.store_aligned(c.bounce_impulse + o);
    (xsimd::select(active, clamped, normal_impulse) * f).store_aligned(c.normal_impulse + o);
  }
}

template <FrictionWork kWork>
void soft_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
               std::size_t body_count, const SoftPass& p) {
  switch (p.kind) {
    case SoftPassKind::Prepare:
      return prepare_pass(c, first, last, bodies, body_count, p);
    case SoftPassKind::Solve:
    case SoftPassKind::Relax:
      return iteration_pass<kWork>(c, first, last, bodies, body_count, p);
    case SoftPassKind::Restitution:
      return restitution_pass(c, first, last, bodies, body_count, p.restitution_threshold, p.impulse_factor);
  }
}

}  // namespace

void contact_soft(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                  std::size_t body_count, const SoftPass& pass, FrictionWork work) {
  switch (work) {
    case kNoFriction:
      return soft_pass<kNoFriction>(c, first, last, bodies, body_count, pass);
    case kLinearFriction:
      return soft_pass<kLinearFriction>(c, first, last, bodies, body_count, pass);
    case kWithFriction:
      break;
  }
  soft_pass<kWithFriction>(c, first, last, bodies, body_count, pass);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
