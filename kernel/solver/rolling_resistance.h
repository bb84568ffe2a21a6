#pragma once
// Rolling resistance (WorldSettings::rolling_resistance): the constant-torque model of DEM codes.
//
// A contact that carries load N (its accumulated normal impulse after the passes) opposes the
// turning of its two spheres against each other, their whole relative angular velocity
// (rolling, and twist about the normal: resisting the rolling alone, a pile's side contacts
// turned the resisted roll into spin about the ground's normal that nothing stopped), with an
// accumulated angular impulse of at most mu_r r N (r the contact's effective radius). Friction is solved again beside it, within its Coulomb cone: on a sphere rolling on
// the ground the angular impulse alone would only make the contact slip, and it is friction
// that then slows the sphere's travel; the two together give the textbook deceleration
// 5/7 mu_r g and hold a sphere still on a slope up to tan theta = mu_r.
//
// It runs after the passes, on the solver bodies: first each contact's impulse from the last
// step is applied again (warm start, clamped to this step's limit), then a few sweeps over the
// contacts (each sweep brings the rolling and the slip nearer their joint answer, by 5/7 a
// sweep for a sphere on the ground); per solver tile in parallel, then the contacts across
// tiles in order, so the state is the same on any thread count. Without the warm start a pile
// crept: each step's sweeps left (5/7)^8 of its gravity along the slope unresisted, and the
// next step started again from zero. Scalar: only scenes that ask for it pay for it.

#include <cstddef>
#include <cstdint>
#include <span>

#include "hail/contact.h"
#include "kernel/solver/solver_body.h"

namespace hail {

/// Sweeps over the contacts after the passes: enough for a sphere on a slope to be held to a
/// residual of (5/7)^8, 7% of one step's gravity along the slope, in the step where the load
/// changes; the warm start carries the rest over.
inline constexpr int kRollingResistanceSweeps = 8;

/// The step's contacts, in colour order, and their accumulated rolling impulses: 3 floats a
/// contact by its detection-order index, order[k] for contacts[k] (where the contact cache
/// keeps them).
struct RollingContacts {
  std::span<Contact> contacts;
  std::span<const std::uint32_t> order;
  std::span<float> impulses;
  float coefficient = 0.0f;  ///< WorldSettings::rolling_resistance, mu_r

  [[nodiscard]] float* impulse(std::size_t k) const { return impulses.data() + 3 * order[k]; }
};

/// Applies contacts [first, last)'s remembered impulses to their bodies, each clamped to its
/// contact's limit this step (none without load).
void warm_start_rolling(const RollingContacts& rolling, std::size_t first, std::size_t last,
                        std::span<SolverBody> bodies);

/// One sweep over contacts [first, last): each loaded contact's rolling resistance, then its
/// friction.
void resist_rolling(const RollingContacts& rolling, std::size_t first, std::size_t last, std::span<SolverBody> bodies);

}  // namespace hail
