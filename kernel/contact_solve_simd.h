#pragma once
// The collision and resting passes of kernel/contact_impulse.h over a run of contacts that share
// no sphere (one colour, or part of one), a batch of contacts per instruction (8 under AVX2).
// Each lane performs the scalar rule's float operations in the scalar rule's order, and a
// skipped lane (an early return in the scalar code) keeps its values through a select, so the
// result is bitwise the scalar result: the scalar functions stay the reference, and
// tests/test_contact_solve_simd.cpp compares the two on random contacts. A run's tail that does
// not fill a batch goes through the scalar rules.
//
// Lanes gather their bodies from SolverBody lines (kernel/solver_body.h) and scatter them back;
// within a run no two contacts share a sphere, so the scatters cannot collide.

#include <cstdint>
#include <span>

#include "kernel/contact.h"
#include "kernel/solver_body.h"

namespace hail {

/// Collision pass (solve_collision) over contacts[first, last), which must share no sphere.
/// Returns true when any contact applied an impulse.
bool solve_collision_run(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt,
                         float restitution_threshold);

/// Resting pass (solve_resting) over contacts, which must share no sphere.
void solve_resting_run(std::span<Contact> contacts, std::span<SolverBody> bodies, float inv_dt);

/// The scalar reference of both: the per-contact rules in a loop.
bool solve_collision_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt,
                                float restitution_threshold);
void solve_resting_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float inv_dt);

}  // namespace hail
