#include "kernel/contact_solve_simd.h"

#include <xsimd/xsimd.hpp>

#include "kernel/contact_impulse.h"

namespace hail {
namespace {

using batch = xsimd::batch<float>;
using lane_mask = xsimd::batch_bool<float>;
constexpr std::size_t W = batch::size;

/// A batch of contacts with their bodies, staged through aligned arrays (gather/scatter are
/// scalar: bodies sit at random places).
struct Staged {
  alignas(64) float ima[W], iia[W], ra[W], imb[W], iib[W], rb[W];
  alignas(64) float va[3][W], wa[3][W], vb[3][W], wb[3][W];
  alignas(64) float n[3][W], gap[W], restitution[W], friction[W], normal_impulse[W], t[3][W];

  void gather(const Contact* c, std::span<const SolverBody> bodies) {
    for (std::size_t l = 0; l < W; ++l) {
      const SolverBody& a = bodies[c[l].a];
      ima[l] = a.inv_mass, iia[l] = a.inv_inertia, ra[l] = a.radius;
      const bool has_b = c[l].b != kStaticBody;
      const SolverBody* b = has_b ? &bodies[c[l].b] : nullptr;
      imb[l] = has_b ? b->inv_mass : 0.0f, iib[l] = has_b ? b->inv_inertia : 0.0f, rb[l] = has_b ? b->radius : 0.0f;
      for (int d = 0; d < 3; ++d) {
        va[d][l] = a.v[d], wa[d][l] = a.w[d];
        vb[d][l] = has_b ? b->v[d] : 0.0f, wb[d][l] = has_b ? b->w[d] : 0.0f;
      }
      n[0][l] = c[l].nx, n[1][l] = c[l].ny, n[2][l] = c[l].nz;
      gap[l] = c[l].gap, restitution[l] = c[l].restitution, friction[l] = c[l].friction;
      normal_impulse[l] = c[l].normal_impulse, t[0][l] = c[l].tx, t[1][l] = c[l].ty, t[2][l] = c[l].tz;
    }
  }

  void scatter_bodies(const Contact* c, std::span<SolverBody> bodies) const {
    for (std::size_t l = 0; l < W; ++l) {
      SolverBody& a = bodies[c[l].a];
      for (int d = 0; d < 3; ++d) a.v[d] = va[d][l], a.w[d] = wa[d][l];
      if (c[l].b == kStaticBody) continue;
      SolverBody& b = bodies[c[l].b];
      for (int d = 0; d < 3; ++d) b.v[d] = vb[d][l], b.w[d] = wb[d][l];
    }
  }

  void scatter_impulses(Contact* c) const {
    for (std::size_t l = 0; l < W; ++l) {
      c[l].normal_impulse = normal_impulse[l];
      c[l].tx = t[0][l], c[l].ty = t[1][l], c[l].tz = t[2][l];
    }
  }
};

/// ContactBodies and the contact's normal, one lane per contact.
struct Lanes {
  batch ima, iia, ra, imb, iib, rb;
  batch va[3], wa[3], vb[3], wb[3], n[3];

  explicit Lanes(const Staged& s)
      : ima(batch::load_aligned(s.ima)), iia(batch::load_aligned(s.iia)), ra(batch::load_aligned(s.ra)),
        imb(batch::load_aligned(s.imb)), iib(batch::load_aligned(s.iib)), rb(batch::load_aligned(s.rb)) {
    for (int d = 0; d < 3; ++d) {
      va[d] = batch::load_aligned(s.va[d]), wa[d] = batch::load_aligned(s.wa[d]);
      vb[d] = batch::load_aligned(s.vb[d]), wb[d] = batch::load_aligned(s.wb[d]);
      n[d] = batch::load_aligned(s.n[d]);
    }
  }
  void store(Staged& s) const {
    for (int d = 0; d < 3; ++d) {
      va[d].store_aligned(s.va[d]), wa[d].store_aligned(s.wa[d]);
      vb[d].store_aligned(s.vb[d]), wb[d].store_aligned(s.wb[d]);
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

bool solve_collision_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt,
                                float restitution_threshold) {
  bool any = false;
  for (Contact& c : contacts) {
    ContactBodies k = gather_bodies(bodies, c);
    if (solve_collision(c, k, dt, restitution_threshold)) {
      scatter_bodies(bodies, c, k);
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

bool solve_collision_run(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt,
                         float restitution_threshold) {
  const std::size_t full = contacts.size() / W * W;
  bool any = false;
  Staged s;
  const batch zero(0.0f), one(1.0f);
  for (std::size_t k = 0; k < full; k += W) {
    s.gather(&contacts[k], bodies);
    Lanes L(s);
    batch v[3];
    L.relative_velocity(v);
    const batch closing = -(v[0] * L.n[0] + v[1] * L.n[1] + v[2] * L.n[2]);
    const batch gap = batch::load_aligned(s.gap);
    const batch kn = L.ima + L.imb;
    const lane_mask closing_fast = !(closing <= batch(restitution_threshold));
    const lane_mask gap_stays_open = (gap > zero) & (closing * batch(dt) <= gap);
    const lane_mask movable = !(kn <= zero);
    const lane_mask active = closing_fast & !gap_stays_open & movable;
    if (!xsimd::any(active)) continue;  // nothing changes: no scatter needed
    any = true;
    const batch j = (one + batch::load_aligned(s.restitution)) * closing / kn;
    const batch p[3] = {j * L.n[0], j * L.n[1], j * L.n[2]};
    L.apply_impulse(p, active);
    batch fresh[3] = {zero, zero, zero};
    L.apply_friction(batch::load_aligned(s.friction) * j, fresh, active);
    L.store(s);
    s.scatter_bodies(&contacts[k], bodies);
  }
  const bool tail_any = solve_collision_run_scalar(contacts.subspan(full), bodies, dt, restitution_threshold);
  return any || tail_any;
}

void solve_resting_run(std::span<Contact> contacts, std::span<SolverBody> bodies, float inv_dt) {
  const std::size_t full = contacts.size() / W * W;
  Staged s;
  const batch zero(0.0f);
  for (std::size_t k = 0; k < full; k += W) {
    s.gather(&contacts[k], bodies);
    Lanes L(s);
    batch v[3];
    L.relative_velocity(v);
    const batch vn = v[0] * L.n[0] + v[1] * L.n[1] + v[2] * L.n[2];
    const batch gap = batch::load_aligned(s.gap);
    const batch allowed_closing = xsimd::select(gap > zero, gap * batch(inv_dt), zero);
    const batch kn = L.ima + L.imb;
    const lane_mask active = !(kn <= zero);
    const batch impulse = batch::load_aligned(s.normal_impulse);
    const batch lambda = impulse - (vn + allowed_closing) / kn;
    const batch clamped = xsimd::select(lambda > zero, lambda, zero);
    const batch dj = clamped - impulse;
    const batch new_impulse = xsimd::select(active, clamped, impulse);
    const batch p[3] = {dj * L.n[0], dj * L.n[1], dj * L.n[2]};
    L.apply_impulse(p, active);
    batch accumulated[3] = {batch::load_aligned(s.t[0]), batch::load_aligned(s.t[1]), batch::load_aligned(s.t[2])};
    L.apply_friction(batch::load_aligned(s.friction) * new_impulse, accumulated, active);
    L.store(s);
    new_impulse.store_aligned(s.normal_impulse);
    for (int d = 0; d < 3; ++d) accumulated[d].store_aligned(s.t[d]);
    s.scatter_bodies(&contacts[k], bodies);
    s.scatter_impulses(&contacts[k]);
  }
  solve_resting_run_scalar(contacts.subspan(full), bodies, inv_dt);
}

}  // namespace hail
