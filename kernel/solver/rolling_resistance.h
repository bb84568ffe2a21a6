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
// It runs after the passes, on the solver bodies, as a few sweeps over the contacts (each
// sweep brings the rolling and the slip nearer their joint answer, by 5/7 a sweep for a sphere
// on the ground): per solver tile in parallel, then the contacts across tiles in order, so the
// state is the same on any thread count. Scalar: only scenes that ask for it pay for it.

#include <cstddef>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "kernel/solver/solver_body.h"

namespace hail {

/// Sweeps over the contacts after the passes: enough for a sphere on a slope to be held to a
/// residual of (5/7)^8, 7% of one step's gravity along the slope.
inline constexpr int kRollingResistanceSweeps = 8;

/// One sweep over contacts [first, last): each loaded contact's rolling resistance, then its
/// friction. `rolling` holds each contact's accumulated angular impulse (3 floats a contact,
/// zero at the start of the step), indexed like `contacts`.
void resist_rolling(std::span<Contact> contacts, std::size_t first, std::size_t last, std::span<SolverBody> bodies,
                    std::span<float> rolling, float coefficient);

}  // namespace hail
