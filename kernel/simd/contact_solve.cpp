// The SIMD collision, warm-start and resting passes over staged contact batches
// (kernel/solver/contact_solve_simd.h), a batch of contacts per instruction. Compiled once per SIMD
// path (kernel/dispatch/simd_arch.h). Each lane performs the float operations of the scalar rules of
// kernel/solver/contact_impulse.h in their order (the impulses themselves by the same templates,
// kernel/solver/impulse_rules.h), so every path gives their bits.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include <cstddef>

#include "kernel/simd/contact_lanes.h"
#include "kernel/simd/kernels.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/solver_body.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

template <FrictionWork kWork>
bool collision_pass(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                    std::size_t body_count, float dt, float restitution_threshold, std::uint32_t pass,
                    const float* gravity_dt) {
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
    const batch closing = -impulse::normal_relative_velocity(L, L.n);
    const batch gap = batch::load_aligned(c.gap + o);
    const batch kn = L.ima + L.imb;
    // solve_collision's gravity_closing (uniform-acceleration integrator), else zero: then
    // closing - 0 and closing - 0.5 * 0 are closing, bit for bit, as the rule was.
    batch gravity_closing = zero;
    if (gravity_dt) {
      alignas(64) float scale_a[W], scale_b[W];
      for (std::size_t l = 0; l < W; ++l)
        scale_a[l] = L.body_a[l]->gravity_scale, scale_b[l] = L.b_static ? 0.0f : L.body_b[l]->gravity_scale;
      const batch gn = L.n[0] * batch(gravity_dt[0]) + L.n[1] * batch(gravity_dt[1]) + L.n[2] * batch(gravity_dt[2]);
      gravity_closing = gn * (batch::load_aligned(scale_a) - batch::load_aligned(scale_b));
    }
    const lane_mask closing_fast = !(closing - gravity_closing <= batch(restitution_threshold)) & (closing > zero);
    const lane_mask gap_stays_open = (gap > zero) & ((closing - batch(0.5f) * gravity_closing) * batch(dt) <= gap);
    const lane_mask movable = !(kn <= zero);
    const lane_mask active = closing_fast & !gap_stays_open & movable;
    const std::uint32_t lanes = lane_bits(active);
    if (lanes == 0) continue;  // nothing changes: no scatter needed
    L.load_angular();
    any = true;
    const batch restitution = batch::load_aligned(c.restitution + o);
    const batch j = ((one + restitution) * closing - restitution * gravity_closing) * (one / kn);
    const batch bounce = batch::load_aligned(c.bounce_impulse + o);
    xsimd::select(active, bounce + j, bounce).store_aligned(c.bounce_impulse + o);
    impulse::apply_impact_impulse<kWork>(L, L.n, j, batch::load_aligned(c.friction + o), active);
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
    const batch vn = impulse::normal_relative_velocity(L, L.n);
    const batch gap = batch::load_aligned(c.gap + o);
    const batch allowed_closing = xsimd::select(gap > zero, gap * batch(inv_dt), zero);
    const batch kn = L.ima + L.imb;
    const batch normal_impulse = batch::load_aligned(c.normal_impulse + o);
    batch accumulated[3] = {batch::load_aligned(c.tx + o), batch::load_aligned(c.ty + o),
                            batch::load_aligned(c.tz + o)};
    const lane_mask idle = (normal_impulse == zero) & (accumulated[0] == zero) & (accumulated[1] == zero) &
                           (accumulated[2] == zero) & (vn + allowed_closing >= zero);  // resting_idle
    const lane_mask active = !(kn <= zero) & !idle;
    // A batch of idle contacts (the staging groups the speculative ones, kernel/solver/contact_colouring.h)
    // changes nothing: no angular loads, no friction, no stores.
    if (lane_bits(active) == 0) continue;
    L.load_angular();
    const batch lambda = normal_impulse - (vn + allowed_closing) * (batch(1.0f) / kn);  // solve_resting's reciprocal
    impulse::apply_clamped_impulse<kWork>(L, L.n, normal_impulse, lambda, batch::load_aligned(c.friction + o),
                                          accumulated, active)
        .store_aligned(c.normal_impulse + o);
    if constexpr (has_friction(kWork))
      accumulated[0].store_aligned(c.tx + o), accumulated[1].store_aligned(c.ty + o),
          accumulated[2].store_aligned(c.tz + o);
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
    const batch normal_impulse = batch::load_aligned(c.normal_impulse + o);
    const batch t[3] = {batch::load_aligned(c.tx + o), batch::load_aligned(c.ty + o), batch::load_aligned(c.tz + o)};
    // apply_warm_start leaves out contacts with no impulse: a batch of them loads no body.
    const lane_mask holds = !((normal_impulse == zero) & (t[0] == zero) & (t[1] == zero) & (t[2] == zero));
    if (lane_bits(holds) == 0) continue;
    Lanes<kFriction> L(c, k, o, bodies, body_count);
    const lane_mask active = (!((L.ima + L.imb) <= zero)) & holds;
    if constexpr (has_friction(kWork)) {
      impulse::apply_contact_impulse<kWork>(L, L.n, normal_impulse, t, active);  // apply_warm_start's
    } else {
      const batch p[3] = {normal_impulse * L.n[0], normal_impulse * L.n[1], normal_impulse * L.n[2]};
      impulse::apply_linear_impulse(L, p, active);
    }
    L.scatter();
  }
}

}  // namespace

bool contact_collision(const ContactBatchArrays& c, std::size_t first, std::size_t last, SolverBody* bodies,
                       std::size_t body_count, float dt, float restitution_threshold, std::uint32_t pass,
                       FrictionWork work, const float* gravity_dt) {
  switch (work) {
    case kNoFriction:
      return collision_pass<kNoFriction>(c, first, last, bodies, body_count, dt, restitution_threshold, pass,
                                         gravity_dt);
    case kLinearFriction:
      return collision_pass<kLinearFriction>(c, first, last, bodies, body_count, dt, restitution_threshold, pass,
                                             gravity_dt);
    case kWithFriction:
      break;
  }
  return collision_pass<kWithFriction>(c, first, last, bodies, body_count, dt, restitution_threshold, pass, gravity_dt);
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
  resting_pass<kWithFriction>(c, first, last, bodies, body_count, inv_dt);
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
  warm_start_pass<kWithFriction>(c, first, last, bodies, body_count);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
