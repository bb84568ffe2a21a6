#pragma once
// Bounces off speculative static contacts, moved to their time of impact.
//
// The collision passes bounce a sphere off a speculative terrain contact (gap > 0) at the start
// of the step, up to one step's travel above the ground: the sphere then ends the step
// (1 + e) gap higher than one that met the ground at its time and bounced there, and leaves with
// e times its speed at the start of the step instead of at the impact. Every bounce on terrain
// gained height that way (A-bounce-terrain: 14% at dt 1/60, docs/accuracy.md). Planes need no
// such contacts: the integrator meets a plane at its time (kernel/solver/integrate.h).
//
// BounceTiming gives terrain bounces the planes' treatment where that is safe. A sphere whose
// step held exactly one such bounce, and no other impulse (no other contact of it, static or
// with a sphere, carries a normal, friction or bounce impulse), is moved as the integrator moves
// a sphere against a plane: along its unbounced path to the contact's plane (Contact::surface_d)
// at the time it reaches it, bounced there (restitution from the speed at that time), and on for
// the rest of the step. The friction impulse of the collision pass stays as the solve gave it.
// The timed end state is kept only where no other contact of the sphere (its idle speculative
// ones, a neighbouring triangle or sphere) ends the step overlapping, and deeper than the
// integrator's path left it; a sphere the sweep moved, or one with two bounces, keeps the
// integrator's motion. The passes solver only (the soft step's substeps bring a sphere to the
// ground before its restitution acts), and not in a step with shock propagation, whose
// impulses the contacts do not record.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "kernel/solver/integrate.h"

namespace hail {

class BounceTiming {
 public:
  /// After the solve, before integration: finds the spheres whose bounce is timed and their
  /// end-of-step state, from the positions they start the step at. `swept`: the sweep's moved()
  /// (empty when it did not run). Costs one pass over the contacts when none bounced.
  void plan(std::span<const Contact> contacts, const SphereSoA& s, const IntegrationParams& p,
            std::span<const std::uint8_t> swept);

  /// After integration: gives each planned sphere its timed end state unless one of its other
  /// contacts would end overlapping more than the integrator's motion left it. Returns how many
  /// spheres it moved.
  std::size_t apply(std::span<const Contact> contacts, SphereSoA& s);

  [[nodiscard]] std::size_t heap_bytes() const;

 private:
  struct Timed {
    std::uint32_t sphere = 0;
    std::uint32_t contact = 0;  ///< the bounced contact, in the solve's order
    bool keep = true;
    float x[3] = {0, 0, 0}, v[3] = {0, 0, 0};  ///< the end-of-step state at the timed bounce
  };
  [[nodiscard]] Timed* find(std::uint32_t sphere);
  [[nodiscard]] bool marked(std::uint32_t sphere) const {
    return (marks_[sphere >> 6] >> (sphere & 63)) & 1u;
  }
  void timed_motion(const Contact& c, const SphereSoA& s, const IntegrationParams& p, Timed& t) const;

  std::vector<Timed> timed_;                ///< by sphere
  std::vector<std::uint32_t> neighbours_;   ///< the other contacts of planned spheres (checked by apply)
  std::vector<std::uint64_t> marks_;        ///< a bit per sphere: planned this step
};

}  // namespace hail
