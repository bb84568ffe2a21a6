#pragma once
// The soft step's work outside the contact kernels (Solver::SoftStep; the rules:
// kernel/solver/soft_contact.h): the scalar pass over a run of contacts (the reference for
// kernel/simd/contact_soft.cpp, and the path of a serial overflow colour), and the per-body
// stages between the contact passes. The step (kernel/world/step_pipeline.cpp) runs:
//
//   load       bodies as for Solver::Passes, less the gravity of all substeps but the first
//   prepare    per contact: approach speed, impulses to per substep; its bodies marked
//   substeps   each: gravity (from the second), warm start, one soft iteration, positions
//              (dp += v h), relax_iterations rigid ones
//   restitute  once, impulses back to per step
//   store      the marked bodies' velocities, and their positions moved by what the substeps
//              moved them less what integration will (spheres in no contact keep their state
//              bitwise as predict left it)
//
// Gravity: predict added g dt for the whole step; the soft step takes back all but one
// substep's share and adds g h before each later substep, as Box2D integrates velocities per
// substep, so that the per-substep impulses hold a resting sphere in every substep.

#include <cstddef>
#include <span>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "kernel/solver/contact_impulse.h"
#include "kernel/solver/integrate.h"
#include "kernel/solver/soft_contact.h"
#include "kernel/solver/solver_body.h"

namespace hail {

/// The soft pass `p` over a run of contacts, in order (scalar rules; they may share spheres).
void soft_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, const SoftPass& p,
                     FrictionWork work = kWithFriction);

/// After load_solver_bodies: bodies [first, last) get their gravity scale (0 if immovable), dp
/// zero, no mark, and the gravity of the substeps after the first taken back from v (`g_rest`:
/// g (dt - h)).
void soft_load_bodies(const SphereSoA& s, std::size_t first, std::size_t last, std::span<SolverBody> bodies,
                      const float g_rest[3], bool gravity_scaled);
/// v += g h gravity_scale for the marked bodies of [first, last) (`g_h`: g h).
void soft_add_gravity(std::span<SolverBody> bodies, std::size_t first, std::size_t last, const float g_h[3]);
/// dp += v h for the marked bodies of [first, last).
void soft_move(std::span<SolverBody> bodies, std::size_t first, std::size_t last, float h);
/// The marked bodies of [first, last) back to the SoA: velocities (angular ones with
/// `angular`), and positions moved by dp less what integrate_positions will move them over
/// p.dt (v dt, less a dt^2 / 2 under Integrator::UniformAcceleration, a its
/// uniform_step_acceleration), so that integration ends them where the substeps did.
void soft_store_bodies(std::span<const SolverBody> bodies, std::size_t first, std::size_t last, SphereSoA& s,
                       bool angular, const IntegrationParams& p);

}  // namespace hail
