#include "kernel/solver/rolling_resistance.h"

#include <cmath>

#include "kernel/solver/contact_impulse.h"

namespace hail {
namespace {

/// mu_r r N: the most angular impulse contact c may carry (r its effective radius).
float rolling_limit(const Contact& c, const ContactBodies& b, float coefficient) {
  const float radius = c.b == kStaticBody ? b.ra : b.ra * b.rb / (b.ra + b.rb);
  return coefficient * radius * c.normal_impulse;
}

/// Scales v down to length `limit` if it is longer.
void clamp_length(float v[3], float limit) {
  const float len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (len2 > limit * limit) {
    const float scale = limit / std::sqrt(len2);
    for (int d = 0; d < 3; ++d) v[d] *= scale;
  }
}

/// Turns the two bodies by angular impulse `delta` (a's by -delta).
void apply_angular(ContactBodies& b, const float delta[3]) {
  for (int d = 0; d < 3; ++d) {
    b.wa[d] -= b.iia * delta[d];
    b.wb[d] += b.iib * delta[d];
  }
}

}  // namespace

void warm_start_rolling(const RollingContacts& rolling, std::size_t first, std::size_t last,
                        std::span<SolverBody> bodies) {
  for (std::size_t k = first; k < last; ++k) {
    Contact& c = rolling.contacts[k];
    float* accumulated = rolling.impulse(k);
    if (!(c.normal_impulse > 0.0f)) {  // no load: nothing to carry
      accumulated[0] = accumulated[1] = accumulated[2] = 0.0f;
      continue;
    }
    if (accumulated[0] == 0.0f && accumulated[1] == 0.0f && accumulated[2] == 0.0f) continue;
    ContactBodies b = gather_bodies<kWithFriction>(bodies, c);
    clamp_length(accumulated, rolling_limit(c, b, rolling.coefficient));
    apply_angular(b, accumulated);
    scatter_bodies(bodies, c, b);
  }
}

void resist_rolling(const RollingContacts& rolling, std::size_t first, std::size_t last, std::span<SolverBody> bodies) {
  for (std::size_t k = first; k < last; ++k) {
    Contact& c = rolling.contacts[k];
    float* accumulated = rolling.impulse(k);
    if (!(c.normal_impulse > 0.0f)) {  // no load: nothing to resist with, and the warm start taken back
      if (accumulated[0] != 0.0f || accumulated[1] != 0.0f || accumulated[2] != 0.0f) {
        ContactBodies b = gather_bodies<kWithFriction>(bodies, c);
        const float back[3] = {-accumulated[0], -accumulated[1], -accumulated[2]};
        apply_angular(b, back);
        scatter_bodies(bodies, c, b);
        accumulated[0] = accumulated[1] = accumulated[2] = 0.0f;
      }
      continue;
    }
    ContactBodies b = gather_bodies<kWithFriction>(bodies, c);
    const float angular_mass = b.iia + b.iib;
    if (angular_mass > 0.0f) {
      // Rolling and twisting alike: the whole relative angular velocity. Resisting the rolling
      // alone, a pile's side contacts turned their spheres' resisted roll into spin about the
      // ground's normal, which nothing then stopped (a bowl pile stayed awake).
      const float w[3] = {b.wb[0] - b.wa[0], b.wb[1] - b.wa[1], b.wb[2] - b.wa[2]};
      float target[3];
      for (int d = 0; d < 3; ++d) target[d] = accumulated[d] - w[d] / angular_mass;
      clamp_length(target, rolling_limit(c, b, rolling.coefficient));
      float delta[3];
      for (int d = 0; d < 3; ++d) {
        delta[d] = target[d] - accumulated[d];
        accumulated[d] = target[d];
      }
      apply_angular(b, delta);
    }
    // Friction again, within mu N of the same contact: the slip the rolling impulse made.
    accumulate_clamped_impulse<kWithFriction>(c, b, c.normal_impulse);
    scatter_bodies(bodies, c, b);
  }
}

}  // namespace hail
