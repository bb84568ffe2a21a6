#include "kernel/contact_solve_simd.h"

#include <cstddef>
#include <xsimd/xsimd.hpp>

#include "kernel/contact_impulse.h"

namespace hail {
namespace {

using batch = xsimd::batch<float>;
using index_batch = xsimd::batch<std::int32_t>;
using lane_mask = xsimd::batch_bool<float>;
constexpr std::size_t W = batch::size;
static_assert(index_batch::size == W);

// SolverBody as floats, for gathers.
constexpr std::int32_t kBodyFloats = sizeof(SolverBody) / sizeof(float);
constexpr std::int32_t kVelocity = offsetof(SolverBody, v) / sizeof(float);
constexpr std::int32_t kAngular = offsetof(SolverBody, w) / sizeof(float);
constexpr std::int32_t kChangedInPass = offsetof(SolverBody, changed_in_pass) / sizeof(float);

/// Bit l set for each true lane.
std::uint32_t detail_lane_bits(const lane_mask& m) {
  alignas(64) bool lanes[W];
  m.store_aligned(lanes);
  std::uint32_t bits = 0;
  for (std::size_t l = 0; l < W; ++l) bits |= std::uint32_t(lanes[l]) << l;
  return bits;
}

/// ContactBodies and the contact's normal, one lane per contact.
struct Lanes {
  batch ima, iia, ra, imb, iib, rb;
  batch va[3], wa[3], vb[3], wb[3], n[3];

  /// Lanes of batch `offset` (a multiple of W): staged data, velocities gathered from bodies.
  Lanes(const float* ima_, const float* iia_, const float* ra_, const float* imb_, const float* iib_, const float* rb_,
        const float* const n_[3], const std::int32_t* a, const std::int32_t* b, const float* bodies)
      : ima(batch::load_aligned(ima_)), iia(batch::load_aligned(iia_)), ra(batch::load_aligned(ra_)),
        imb(batch::load_aligned(imb_)), iib(batch::load_aligned(iib_)), rb(batch::load_aligned(rb_)) {
    const index_batch stride(kBodyFloats);
    const index_batch ia = index_batch::load_aligned(a) * stride, ib = index_batch::load_aligned(b) * stride;
    for (int d = 0; d < 3; ++d) {
      va[d] = batch::gather(bodies + kVelocity + d, ia), wa[d] = batch::gather(bodies + kAngular + d, ia);
      vb[d] = batch::gather(bodies + kVelocity + d, ib), wb[d] = batch::gather(bodies + kAngular + d, ib);
      n[d] = batch::load_aligned(n_[d]);
    }
  }

  /// Writes the velocities back: every a, and b where it is not the static body.
  void scatter(const std::int32_t* a, const std::int32_t* b, std::int32_t static_slot, SolverBody* bodies) const {
    alignas(64) float out[12][W];
    for (int d = 0; d < 3; ++d) {
      va[d].store_aligned(out[d]), wa[d].store_aligned(out[3 + d]);
      vb[d].store_aligned(out[6 + d]), wb[d].store_aligned(out[9 + d]);
    }
    for (std::size_t l = 0; l < W; ++l) {
      SolverBody& body_a = bodies[a[l]];
      for (int d = 0; d < 3; ++d) body_a.v[d] = out[d][l], body_a.w[d] = out[3 + d][l];
      if (b[l] == static_slot) continue;
      SolverBody& body_b = bodies[b[l]];
      for (int d = 0; d < 3; ++d) body_b.v[d] = out[6 + d][l], body_b.w[d] = out[9 + d][l];
    }
  }

  // The functions below are relative_contact_velocity, apply_impulse and apply_friction of
  // kernel/contact_impulse.h, operation for operation; `active` lanes change, others keep.

  void relative_velocity(batch out[3]) const {
    const batch r_a[3] = {n[0] * ra, n[1] * ra, n[2] * ra};
    const batch r_b[3] = {-n[0] * rb, -n[1] * rb, -n[2] * rb};
    const batch wa_x_ra[3] = {wa[1] * r_a[2] - wa[2] * r_a[1], wa[2] * r_a[0] - wa[0] * r_a[2], wa[0] * r_a[1] - wa[1] * r_a[0]};
    const batch wb_x_rb[3] = {wb[1] * r_b[2] - wb[2] * r_b[1], wb[2] * r_b[0] - wb[0] * r_b[2], wb[0] * r_b[1] - wb[1] * r_b[0]};
    for (int d = 0; d < 3; ++d) out[d] = (vb[d] + wb_x_rb[d]) - (va[d] + wa_x_ra[d]);
  }

  void apply_impulse(const batch p[3], const lane_mask& active) {
    const batch r_a[3] = {n[0] * ra, n[1] * ra, n[2] * ra};
    const batch r_b[3] = {-n[0] * rb, -n[1] * rb, -n[2] * rb};
    const batch ra_x_p[3] = {r_a[1] * p[2] - r_a[2] * p[1], r_a[2] * p[0] - r_a[0] * p[2], r_a[0] * p[1] - r_a[1] * p[0]};
    const batch rb_x_p[3] = {r_b[1] * p[2] - r_b[2] * p[1], r_b[2] * p[0] - r_b[0] * p[2], r_b[0] * p[1] - r_b[1] * p[0]};
    for (int d = 0; d < 3; ++d) {
      va[d] = xsimd::select(active, va[d] - p[d] * ima, va[d]);
      wa[d] = xsimd::select(active, wa[d] - ra_x_p[d] * iia, wa[d]);
      vb[d] = xsimd::select(active, vb[d] + p[d] * imb, vb[d]);
      wb[d] = xsimd::select(active, wb[d] + rb_x_p[d] * iib, wb[d]);
    }
  }

  void apply_friction(const batch& limit, batch accumulated[3], lane_mask active) {
    batch v[3];
    relative_velocity(v);
    const batch vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    const batch vt[3] = {v[0] - vn * n[0], v[1] - vn * n[1], v[2] - vn * n[2]};
    const batch kt = ima + imb + ra * ra * iia + rb * rb * iib;
    active = active & !(kt <= batch(0.0f));
    batch target[3] = {accumulated[0] - vt[0] / kt, accumulated[1] - vt[1] / kt, accumulated[2] - vt[2] / kt};
    const batch len2 = target[0] * target[0] + target[1] * target[1] + target[2] * target[2];
    const lane_mask over = len2 > limit * limit;
    const batch scale = limit / xsimd::sqrt(len2);
    for (batch& t : target) t = xsimd::select(over, t * scale, t);
    const batch delta[3] = {target[0] - accumulated[0], target[1] - accumulated[1], target[2] - accumulated[2]};
    apply_impulse(delta, active);
    for (int d = 0; d < 3; ++d) accumulated[d] = xsimd::select(active, target[d], accumulated[d]);
  }
};

}  // namespace

/// The staged data of the batch at lane offset o, with its bodies' velocities gathered.
struct ContactBatchAccess {
  static Lanes lanes(const ContactBatches& c, std::size_t o, const float* bodies) {
    const float* const n[3] = {&c.nx_[o], &c.ny_[o], &c.nz_[o]};
    return Lanes(&c.ima_[o], &c.iia_[o], &c.ra_[o], &c.imb_[o], &c.iib_[o], &c.rb_[o], n, &c.a_[o], &c.b_[o], bodies);
  }
  /// Runs f(o, lanes) over batches [first, last) and scatters each batch's velocities back: the
  /// loop every pass that touches all its batches shares.
  template <class F>
  static void for_each_batch(const ContactBatches& c, std::size_t first, std::size_t last, std::span<SolverBody> bodies,
                             F&& f) {
    const float* base = reinterpret_cast<const float*>(bodies.data());
    const auto static_slot = static_cast<std::int32_t>(bodies.size() - 1);
    for (std::size_t k = first; k < last; ++k) {
      const std::size_t o = k * W;
      Lanes L = lanes(c, o, base);
      f(o, L);
      L.scatter(&c.a_[o], &c.b_[o], static_slot, bodies.data());
    }
  }
};

bool solve_collision_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt,
                                float restitution_threshold, std::uint32_t pass) {
  bool any = false;
  for (Contact& c : contacts) {
    ContactBodies k = gather_bodies(bodies, c);
    if (solve_collision(c, k, dt, restitution_threshold)) {
      scatter_bodies(bodies, c, k);
      bodies[c.a].changed_in_pass = pass + 1;
      if (c.b != kStaticBody) bodies[c.b].changed_in_pass = pass + 1;
      any = true;
    }
  }
  return any;
}

void solve_resting_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float inv_dt) {
  for (Contact& c : contacts) {
    ContactBodies k = gather_bodies(bodies, c);
    solve_resting(c, k, inv_dt);
    scatter_bodies(bodies, c, k);
  }
}

void warm_start_run_scalar(std::span<const Contact> contacts, std::span<SolverBody> bodies) {
  for (const Contact& c : contacts) {
    ContactBodies k = gather_bodies(bodies, c);
    apply_warm_start(c, k);
    scatter_bodies(bodies, c, k);
  }
}

std::size_t contact_batch_width() { return W; }

void ContactBatches::plan(std::span<const std::uint32_t> colour_begin, std::size_t batched_colours) {
  width_ = W;
  colour_batches_.assign(1, 0);
  tail_begin_.clear();
  first_contact_.clear();
  for (std::size_t c = 0; c < batched_colours; ++c) {
    const std::size_t begin = colour_begin[c], end = colour_begin[c + 1];
    const std::size_t full = (end - begin) / W;
    for (std::size_t k = 0; k < full; ++k) first_contact_.push_back(static_cast<std::uint32_t>(begin + k * W));
    colour_batches_.push_back(colour_batches_.back() + full);
    tail_begin_.push_back(begin + full * W);
  }
  const std::size_t lanes = first_contact_.size() * W;
  for (auto* v : {&a_, &b_}) v->resize(lanes);
  for (auto* v : {&nx_, &ny_, &nz_, &gap_, &restitution_, &friction_, &ima_, &iia_, &ra_, &imb_, &iib_, &rb_,
                  &normal_impulse_, &tx_, &ty_, &tz_})
    v->resize(lanes);
}

void ContactBatches::fill(std::size_t first, std::size_t last, std::span<const Contact> contacts,
                          std::span<const SolverBody> bodies) {
  const auto static_slot = static_cast<std::int32_t>(bodies.size() - 1);
  for (std::size_t k = first; k < last; ++k)
    for (std::size_t l = 0; l < W; ++l) {
      const Contact& c = contacts[first_contact_[k] + l];
      const std::size_t i = k * W + l;
      const SolverBody& a = bodies[c.a];
      const bool has_b = c.b != kStaticBody;
      a_[i] = static_cast<std::int32_t>(c.a);
      b_[i] = has_b ? static_cast<std::int32_t>(c.b) : static_slot;
      ima_[i] = a.inv_mass, iia_[i] = a.inv_inertia, ra_[i] = a.radius;
      // A static side has zero mass properties, as gather_bodies gives it (not the static body's).
      imb_[i] = has_b ? bodies[c.b].inv_mass : 0.0f;
      iib_[i] = has_b ? bodies[c.b].inv_inertia : 0.0f;
      rb_[i] = has_b ? bodies[c.b].radius : 0.0f;
      nx_[i] = c.nx, ny_[i] = c.ny, nz_[i] = c.nz;
      gap_[i] = c.gap, restitution_[i] = c.restitution, friction_[i] = c.friction;
      normal_impulse_[i] = c.normal_impulse, tx_[i] = c.tx, ty_[i] = c.ty, tz_[i] = c.tz;
    }
}

void ContactBatches::stage(std::span<const Contact> contacts, std::span<const std::uint32_t> colour_begin,
                           std::size_t batched_colours, std::span<const SolverBody> bodies) {
  plan(colour_begin, batched_colours);
  fill(0, batch_count(), contacts, bodies);
}

bool ContactBatches::solve_collision(std::size_t first, std::size_t last, std::span<SolverBody> bodies, float dt,
                                     float restitution_threshold, std::uint32_t pass) {
  const float* base = reinterpret_cast<const float*>(bodies.data());
  const auto* stamps = reinterpret_cast<const std::int32_t*>(bodies.data()) + kChangedInPass;
  const auto static_slot = static_cast<std::int32_t>(bodies.size() - 1);
  const batch zero(0.0f), one(1.0f);
  const index_batch stride(kBodyFloats), changed_since(static_cast<std::int32_t>(pass));
  bool any = false;
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    if (pass > 0) {
      // Skip when no body of the batch changed in the previous pass or since (stamp >= pass).
      const index_batch sa = index_batch::gather(stamps, index_batch::load_aligned(&a_[o]) * stride);
      const index_batch sb = index_batch::gather(stamps, index_batch::load_aligned(&b_[o]) * stride);
      if (!xsimd::any((sa >= changed_since) | (sb >= changed_since))) continue;
    }
    Lanes L = ContactBatchAccess::lanes(*this, o, base);
    batch v[3];
    L.relative_velocity(v);
    const batch closing = -(v[0] * L.n[0] + v[1] * L.n[1] + v[2] * L.n[2]);
    const batch gap = batch::load_aligned(&gap_[o]);
    const batch kn = L.ima + L.imb;
    const lane_mask closing_fast = !(closing <= batch(restitution_threshold));
    const lane_mask gap_stays_open = (gap > zero) & (closing * batch(dt) <= gap);
    const lane_mask movable = !(kn <= zero);
    const lane_mask active = closing_fast & !gap_stays_open & movable;
    if (!xsimd::any(active)) continue;  // nothing changes: no scatter needed
    any = true;
    const batch j = (one + batch::load_aligned(&restitution_[o])) * closing / kn;
    const batch p[3] = {j * L.n[0], j * L.n[1], j * L.n[2]};
    L.apply_impulse(p, active);
    batch fresh[3] = {zero, zero, zero};
    L.apply_friction(batch::load_aligned(&friction_[o]) * j, fresh, active);
    L.scatter(&a_[o], &b_[o], static_slot, bodies.data());
    const std::uint32_t lanes = detail_lane_bits(active);
    for (std::size_t l = 0; l < W; ++l)
      if (lanes >> l & 1u) {
        bodies[a_[o + l]].changed_in_pass = pass + 1;
        if (b_[o + l] != static_slot) bodies[b_[o + l]].changed_in_pass = pass + 1;
      }
  }
  return any;
}

void ContactBatches::solve_resting(std::size_t first, std::size_t last, std::span<SolverBody> bodies, float inv_dt) {
  const batch zero(0.0f);
  ContactBatchAccess::for_each_batch(*this, first, last, bodies, [&](std::size_t o, Lanes& L) {
    batch v[3];
    L.relative_velocity(v);
    const batch vn = v[0] * L.n[0] + v[1] * L.n[1] + v[2] * L.n[2];
    const batch gap = batch::load_aligned(&gap_[o]);
    const batch allowed_closing = xsimd::select(gap > zero, gap * batch(inv_dt), zero);
    const batch kn = L.ima + L.imb;
    const lane_mask active = !(kn <= zero);
    const batch impulse = batch::load_aligned(&normal_impulse_[o]);
    const batch lambda = impulse - (vn + allowed_closing) / kn;
    const batch clamped = xsimd::select(lambda > zero, lambda, zero);
    const batch dj = clamped - impulse;
    const batch new_impulse = xsimd::select(active, clamped, impulse);
    const batch p[3] = {dj * L.n[0], dj * L.n[1], dj * L.n[2]};
    L.apply_impulse(p, active);
    batch accumulated[3] = {batch::load_aligned(&tx_[o]), batch::load_aligned(&ty_[o]), batch::load_aligned(&tz_[o])};
    L.apply_friction(batch::load_aligned(&friction_[o]) * new_impulse, accumulated, active);
    new_impulse.store_aligned(&normal_impulse_[o]);
    accumulated[0].store_aligned(&tx_[o]), accumulated[1].store_aligned(&ty_[o]), accumulated[2].store_aligned(&tz_[o]);
  });
}

void ContactBatches::warm_start(std::size_t first, std::size_t last, std::span<SolverBody> bodies) {
  const batch zero(0.0f);
  ContactBatchAccess::for_each_batch(*this, first, last, bodies, [&](std::size_t o, Lanes& L) {
    const lane_mask active = !((L.ima + L.imb) <= zero);
    const batch impulse = batch::load_aligned(&normal_impulse_[o]);
    const batch p[3] = {impulse * L.n[0] + batch::load_aligned(&tx_[o]), impulse * L.n[1] + batch::load_aligned(&ty_[o]),
                        impulse * L.n[2] + batch::load_aligned(&tz_[o])};
    L.apply_impulse(p, active);
  });
}

void ContactBatches::store_impulses(std::span<Contact> contacts) const {
  for (std::size_t k = 0; k < first_contact_.size(); ++k)
    for (std::size_t l = 0; l < W; ++l) {
      Contact& c = contacts[first_contact_[k] + l];
      const std::size_t i = k * W + l;
      c.normal_impulse = normal_impulse_[i], c.tx = tx_[i], c.ty = ty_[i], c.tz = tz_[i];
    }
}

}  // namespace hail
