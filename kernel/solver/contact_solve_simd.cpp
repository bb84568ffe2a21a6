#include "kernel/solver/contact_solve_simd.h"

#include "soa/grow.h"

#include <algorithm>
#include <cstddef>

#include "kernel/dispatch/kernel_table.h"
#include "kernel/solver/contact_impulse.h"

namespace hail {

namespace {

template <FrictionWork kFriction>
bool collision_run(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt, float restitution_threshold,
                   std::uint32_t pass, const float* gravity_dt) {
  bool any = false;
  for (Contact& c : contacts) {
    ContactBodies k = gather_bodies<kFriction>(bodies, c);
    const float gravity_closing = gravity_dt ? gravity_closing_speed(bodies, c, gravity_dt) : 0.0f;
    if (solve_collision<kFriction>(c, k, dt, restitution_threshold, gravity_closing)) {
      scatter_bodies<kFriction>(bodies, c, k);
      bodies[c.a].changed_in_pass = pass + 1;
      if (c.b != kStaticBody) bodies[c.b].changed_in_pass = pass + 1;
      any = true;
    }
  }
  return any;
}

template <FrictionWork kFriction>
void resting_run(std::span<Contact> contacts, std::span<SolverBody> bodies, float inv_dt) {
  for (Contact& c : contacts) {
    ContactBodies k = gather_bodies<kFriction>(bodies, c);
    solve_resting<kFriction>(c, k, inv_dt);
    scatter_bodies<kFriction>(bodies, c, k);
  }
}

template <FrictionWork kFriction>
void warm_start_run(std::span<const Contact> contacts, std::span<SolverBody> bodies) {
  for (const Contact& c : contacts) {
    ContactBodies k = gather_bodies<kFriction>(bodies, c);
    apply_warm_start<kFriction>(c, k);
    scatter_bodies<kFriction>(bodies, c, k);
  }
}

}  // namespace

bool solve_collision_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt,
                                float restitution_threshold, std::uint32_t pass, FrictionWork work,
                                const float* gravity_dt) {
  switch (work) {
    case kNoFriction:
      return collision_run<kNoFriction>(contacts, bodies, dt, restitution_threshold, pass, gravity_dt);
    case kLinearFriction:
      return collision_run<kLinearFriction>(contacts, bodies, dt, restitution_threshold, pass, gravity_dt);
    case kWithFriction:
      break;
  }
  return collision_run<kWithFriction>(contacts, bodies, dt, restitution_threshold, pass, gravity_dt);
}

void solve_resting_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float inv_dt,
                              FrictionWork work) {
  switch (work) {
    case kNoFriction:
      return resting_run<kNoFriction>(contacts, bodies, inv_dt);
    case kLinearFriction:
      return resting_run<kLinearFriction>(contacts, bodies, inv_dt);
    case kWithFriction:
      break;
  }
  resting_run<kWithFriction>(contacts, bodies, inv_dt);
}

void warm_start_run_scalar(std::span<const Contact> contacts, std::span<SolverBody> bodies, FrictionWork work) {
  switch (work) {
    case kNoFriction:
      return warm_start_run<kNoFriction>(contacts, bodies);
    case kLinearFriction:
      return warm_start_run<kLinearFriction>(contacts, bodies);
    case kWithFriction:
      break;
  }
  warm_start_run<kWithFriction>(contacts, bodies);
}

std::size_t contact_batch_width() { return simd_kernels().width; }

ContactBatchArrays ContactBatches::arrays() {
  return {width_,
          a_.data(),
          b_.data(),
          nx_.data(),
          ny_.data(),
          nz_.data(),
          gap_.data(),
          restitution_.data(),
          friction_.data(),
          ra_.data(),
          rb_.data(),
          normal_impulse_.data(),
          tx_.data(),
          ty_.data(),
          tz_.data(),
          bounce_impulse_.data(),
          surface_d_.data(),
          static_b_.data()};
}

void ContactBatches::plan(std::span<const std::uint32_t> colour_begin, std::span<const std::uint8_t> serial) {
  kernels_ = &simd_kernels();
  const std::size_t W = kernels_->width;
  width_ = W;
  colour_batches_.assign(1, 0);
  tail_begin_.clear();
  first_contact_.clear();
  batch_lanes_.clear();
  for (std::size_t c = 0; c + 1 < colour_begin.size(); ++c) {
    const std::size_t begin = colour_begin[c], end = colour_begin[c + 1];
    const std::size_t batches = serial[c] ? 0 : (end - begin + W - 1) / W;
    for (std::size_t k = 0; k < batches; ++k) {
      first_contact_.push_back(static_cast<std::uint32_t>(begin + k * W));
      batch_lanes_.push_back(static_cast<std::uint8_t>(std::min(W, end - begin - k * W)));
    }
    colour_batches_.push_back(colour_batches_.back() + batches);
    tail_begin_.push_back(serial[c] ? begin : end);
  }
  const std::size_t lanes = first_contact_.size() * W;
  for (auto* v : {&a_, &b_}) v->resize(lanes);
  if (static_b_.size() < first_contact_.size()) resize_geometric(static_b_, first_contact_.size());
  for (auto* v : {&nx_, &ny_, &nz_, &gap_, &restitution_, &friction_, &ra_, &rb_, &surface_d_, &normal_impulse_, &tx_,
                  &ty_, &tz_, &bounce_impulse_})
    v->resize(lanes);
}

template <class RadiusOf>
void ContactBatches::fill_batches(std::size_t first, std::size_t last, std::span<const Contact> contacts,
                                  std::int32_t static_slot, RadiusOf&& radius_of) {
  const std::size_t W = width_;
  for (std::size_t k = first; k < last; ++k) {
    bool all_static = true;
    const std::size_t used = batch_lanes_[k];
    for (std::size_t l = 0; l < used; ++l) {
      const Contact& c = contacts[first_contact_[k] + l];
      const std::size_t i = k * W + l;
      const bool has_b = c.b != kStaticBody;
      all_static = all_static && !has_b;
      a_[i] = static_cast<std::int32_t>(c.a);
      b_[i] = has_b ? static_cast<std::int32_t>(c.b) : static_slot;
      // Inverse masses and inertias come with the velocities from the bodies in each pass (the
      // static body's are zero, as gather_bodies gives a static side); radii are staged here.
      ra_[i] = radius_of(c.a);
      rb_[i] = has_b ? radius_of(c.b) : 0.0f;
      nx_[i] = c.nx, ny_[i] = c.ny, nz_[i] = c.nz;
      gap_[i] = c.gap, restitution_[i] = c.restitution, friction_[i] = c.friction;
      surface_d_[i] = c.surface_d;
      normal_impulse_[i] = c.normal_impulse, tx_[i] = c.tx, ty_[i] = c.ty, tz_[i] = c.tz;
      bounce_impulse_[i] = c.bounce_impulse;
    }
    // Padding lanes of a colour's last batch: both sides the static body, so the lane's
    // inverse masses are zero and every rule leaves it inactive (kn <= 0); no store writes
    // the static body.
    for (std::size_t l = used; l < W; ++l) {
      const std::size_t i = k * W + l;
      a_[i] = b_[i] = static_slot;
      ra_[i] = rb_[i] = nx_[i] = ny_[i] = nz_[i] = gap_[i] = restitution_[i] = friction_[i] = surface_d_[i] = 0.0f;
      normal_impulse_[i] = tx_[i] = ty_[i] = tz_[i] = bounce_impulse_[i] = 0.0f;
    }
    static_b_[k] = all_static ? 1 : 0;
  }
}

void ContactBatches::fill(std::size_t first, std::size_t last, std::span<const Contact> contacts,
                          std::span<const SolverBody> bodies) {
  fill_batches(first, last, contacts, static_cast<std::int32_t>(bodies.size() - 1),
               [&](std::uint32_t slot) { return bodies[slot].radius; });
}

void ContactBatches::fill(std::size_t first, std::size_t last, std::span<const Contact> contacts,
                          std::span<const float> radius) {
  fill_batches(first, last, contacts, static_cast<std::int32_t>(radius.size()),
               [&](std::uint32_t slot) { return radius[slot]; });
}

void ContactBatches::stage(std::span<const Contact> contacts, std::span<const std::uint32_t> colour_begin,
                           std::size_t batched_colours, std::span<const SolverBody> bodies) {
  std::vector<std::uint8_t>& serial = stage_serial_;
  serial.assign(colour_begin.empty() ? 0 : colour_begin.size() - 1, 0);
  for (std::size_t c = batched_colours; c < serial.size(); ++c) serial[c] = 1;
  plan(colour_begin, serial);
  fill(0, batch_count(), contacts, bodies);
}

bool ContactBatches::solve_collision(std::size_t first, std::size_t last, std::span<SolverBody> bodies, float dt,
                                     float restitution_threshold, std::uint32_t pass, FrictionWork work,
                                     const float* gravity_dt) {
  if (first >= last) return false;
  return kernels_->contact_collision(arrays(), first, last, bodies.data(), bodies.size(), dt, restitution_threshold,
                                     pass, work, gravity_dt);
}

void ContactBatches::solve_resting(std::size_t first, std::size_t last, std::span<SolverBody> bodies, float inv_dt,
                                   FrictionWork work) {
  if (first >= last) return;
  kernels_->contact_resting(arrays(), first, last, bodies.data(), bodies.size(), inv_dt, work);
}

void ContactBatches::solve_soft(std::size_t first, std::size_t last, std::span<SolverBody> bodies, const SoftPass& pass,
                                FrictionWork work) {
  if (first >= last) return;
  kernels_->contact_soft(arrays(), first, last, bodies.data(), bodies.size(), pass, work);
}

bool ContactBatches::depenetrate(std::size_t first, std::size_t last, const DepenetrationArrays& spheres,
                                 std::uint32_t now, std::uint32_t previous) {
  if (first >= last) return false;
  return kernels_->contact_depenetrate(arrays(), first, last, spheres, now, previous);
}

void ContactBatches::warm_start(std::size_t first, std::size_t last, std::span<SolverBody> bodies, FrictionWork work) {
  if (first >= last) return;
  kernels_->contact_warm_start(arrays(), first, last, bodies.data(), bodies.size(), work);
}

void ContactBatches::store_impulses(std::span<Contact> contacts) const { store_impulses(contacts, 0, batch_count()); }

void ContactBatches::store_impulses(std::span<Contact> contacts, std::size_t first, std::size_t last) const {
  const std::size_t W = width_;
  for (std::size_t k = first; k < last; ++k)
    for (std::size_t l = 0; l < batch_lanes_[k]; ++l) {
      Contact& c = contacts[first_contact_[k] + l];
      const std::size_t i = k * W + l;
      c.normal_impulse = normal_impulse_[i], c.tx = tx_[i], c.ty = ty_[i], c.tz = tz_[i];
      c.bounce_impulse = bounce_impulse_[i];
    }
}

}  // namespace hail
