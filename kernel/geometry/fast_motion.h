#pragma once
// Which spheres are fast: those that travel more than a fraction of their radius in a step.
// Continuous collision sweeps them (kernel/ccd/continuous_collision.h); terrain contacts and the
// integrator leave them to it.

namespace hail {

/// Whether a sphere whose squared speed is `speed2` (vx vx + vy vy + vz vz, in that order, so
/// every caller gets the same bits) travels more than `fraction` of its radius in dt: then it is
/// swept. fraction <= 0: no sphere is fast. Squared, so that the per-sphere test needs no root.
[[nodiscard]] inline bool is_fast(float speed2, float dt, float radius, float fraction) {
  const float reach = fraction * radius;
  return fraction > 0.0f && speed2 * (dt * dt) > reach * reach;
}

}  // namespace hail
