#include "kernel/solver/soft_step.h"

namespace hail {

namespace {

template <FrictionWork kFriction>
void soft_run(std::span<Contact> contacts, std::span<SolverBody> bodies, const SoftPass& p) {
  const std::size_t static_slot = bodies.size() - 1;
  for (Contact& c : contacts) {
    SolverBody& a = bodies[c.a];
    SolverBody& b = bodies[c.b != kStaticBody ? c.b : static_slot];
    switch (p.kind) {
      case SoftPassKind::Prepare: {
        prepare_soft(c, gather_bodies<kNoFriction>(bodies, c), p);
        a.changed_in_pass = 1;
        if (c.b != kStaticBody) b.changed_in_pass = 1;
        break;
      }
      case SoftPassKind::Solve:
      case SoftPassKind::Relax: {
        ContactBodies k = gather_bodies<kFriction>(bodies, c);
        solve_soft<kFriction>(c, k, soft_separation(c, a.dp, b.dp), p, p.kind == SoftPassKind::Solve);
        scatter_bodies<kFriction>(bodies, c, k);
        break;
      }
      case SoftPassKind::Restitution: {
        ContactBodies k = gather_bodies<kNoFriction>(bodies, c);
        soft_restitution(c, k, p.restitution_threshold, p.impulse_factor);
        scatter_bodies<kNoFriction>(bodies, c, k);
        break;
      }
    }
  }
}

}  // namespace

void soft_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, const SoftPass& p, FrictionWork work) {
  switch (work) {
    case kNoFriction:
      return soft_run<kNoFriction>(contacts, bodies, p);
    case kLinearFriction:
      return soft_run<kLinearFriction>(contacts, bodies, p);
    case kWithFriction:
      break;
  }
  soft_run<kWithFriction>(contacts, bodies, p);
}

void soft_load_bodies(const SphereSoA& s, std::size_t first, std::size_t last, std::span<SolverBody> bodies,
                      const float g_rest[3], bool gravity_scaled) {
  for (std::size_t i = first; i < last; ++i) {
    SolverBody& b = bodies[i];
    const float scale = s.inv_mass[i] > 0.0f ? (gravity_scaled ? s.gravity_scale[i] : 1.0f) : 0.0f;
    b.gravity_scale = scale;
    for (int d = 0; d < 3; ++d) b.v[d] -= g_rest[d] * scale, b.dp[d] = 0.0f;
    b.changed_in_pass = 0;
  }
}

void soft_add_gravity(std::span<SolverBody> bodies, std::size_t first, std::size_t last, const float g_h[3]) {
  for (std::size_t i = first; i < last; ++i) {
    SolverBody& b = bodies[i];
    if (!b.changed_in_pass) continue;
    for (int d = 0; d < 3; ++d) b.v[d] += g_h[d] * b.gravity_scale;
  }
}

void soft_move(std::span<SolverBody> bodies, std::size_t first, std::size_t last, float h) {
  for (std::size_t i = first; i < last; ++i) {
    SolverBody& b = bodies[i];
    if (!b.changed_in_pass) continue;
    for (int d = 0; d < 3; ++d) b.dp[d] += b.v[d] * h;
  }
}

void soft_store_bodies(std::span<const SolverBody> bodies, std::size_t first, std::size_t last, SphereSoA& s,
                       bool angular, const IntegrationParams& p) {
  const bool uniform = p.modes.uniform_acceleration();
  const float dt = p.dt, half_dt2 = 0.5f * p.dt * p.dt;
  for (std::size_t i = first; i < last; ++i) {
    const SolverBody& b = bodies[i];
    if (!b.changed_in_pass) continue;  // in no contact: as predict left it
    s.vx[i] = b.v[0], s.vy[i] = b.v[1], s.vz[i] = b.v[2];
    if (angular) s.wx[i] = b.w[0], s.wy[i] = b.w[1], s.wz[i] = b.w[2];
    float a[3] = {0.0f, 0.0f, 0.0f};
    if (uniform) uniform_step_acceleration(s, i, p, b.v, a);
    s.px[i] += b.dp[0] - (b.v[0] * dt - a[0] * half_dt2);
    s.py[i] += b.dp[1] - (b.v[1] * dt - a[1] * half_dt2);
    s.pz[i] += b.dp[2] - (b.v[2] * dt - a[2] * half_dt2);
  }
}

}  // namespace hail
