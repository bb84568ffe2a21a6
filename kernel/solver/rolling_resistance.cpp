#include "kernel/solver/rolling_resistance.h"

#include <cmath>

#include "kernel/solver/contact_impulse.h"

namespace hail {

void resist_rolling(std::span<Contact> contacts, std::size_t first, std::size_t last, std::span<SolverBody> bodies,
                    std::span<float> rolling, float coefficient) {
  for (std::size_t k = first; k < last; ++k) {
    Contact& c = contacts[k];
    if (!(c.normal_impulse > 0.0f)) continue;  // no load: nothing to resist with
    ContactBodies b = gather_bodies<kWithFriction>(bodies, c);
    const float angular_mass = b.iia + b.iib;
    if (angular_mass > 0.0f) {
      // Rolling and twisting alike: the whole relative angular velocity. Resisting the rolling
      // alone, a pile's side contacts turned their spheres' resisted roll into spin about the
      // ground's normal, which nothing then stopped (a bowl pile stayed awake).
      const float w[3] = {b.wb[0] - b.wa[0], b.wb[1] - b.wa[1], b.wb[2] - b.wa[2]};
      const float radius = c.b == kStaticBody ? b.ra : b.ra * b.rb / (b.ra + b.rb);
      const float limit = coefficient * radius * c.normal_impulse;
      float* accumulated = rolling.data() + 3 * k;
      float target[3];
      for (int d = 0; d < 3; ++d) target[d] = accumulated[d] - w[d] / angular_mass;
      const float len2 = target[0] * target[0] + target[1] * target[1] + target[2] * target[2];
      if (len2 > limit * limit) {
        const float scale = limit / std::sqrt(len2);
        for (float& t : target) t *= scale;
      }
      for (int d = 0; d < 3; ++d) {
        const float delta = target[d] - accumulated[d];
        accumulated[d] = target[d];
        b.wa[d] -= b.iia * delta;
        b.wb[d] += b.iib * delta;
      }
    }
    // Friction again, within mu N of the same contact: the slip the rolling impulse made.
    accumulate_clamped_impulse<kWithFriction>(c, b, c.normal_impulse);
    scatter_bodies(bodies, c, b);
  }
}

}  // namespace hail
