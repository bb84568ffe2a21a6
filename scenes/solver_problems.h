#pragma once
// Random runs of solver contacts that share no sphere (one colour), for the tests that compare
// the SIMD contact passes with their scalar reference (tests/test_contact_solve_simd.cpp,
// tests/test_simd_dispatch.cpp) and for the microbenchmark that times them
// (bench/micro/micro_solver.cpp): sphere-sphere and static contacts, speculative gaps, immovable
// bodies, carried-over impulses. Header only, so the SIMD tests need no scene library.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "kernel/solver/solver_body.h"

namespace hail::bench {

struct SolverProblem {
  std::vector<SolverBody> bodies;
  std::vector<Contact> contacts;
};

/// Whether some contacts start with no impulse at all (as new and speculative contacts do), or
/// every one carries impulses, so that no batch of the resting passes is idle.
enum class StartImpulses { SomeZero, AllCarried };

/// `count` contacts sharing no sphere (one colour), 30% static, 10% immovable bodies, about a
/// third with no impulse to start from (StartImpulses::SomeZero, what the tests check) or none
/// (AllCarried: the full work of every batch, what hail-micro times; the same contacts but those
/// impulses, drawn from the same seed).
inline SolverProblem random_contacts(std::size_t count, std::uint32_t seed,
                                     StartImpulses start = StartImpulses::SomeZero) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
  SolverProblem p;
  p.bodies.resize(2 * count + 1);  // + the static body
  for (SolverBody& b : std::span(p.bodies).first(2 * count)) {
    for (int d = 0; d < 3; ++d) b.v[d] = 5.0f * u(rng), b.w[d] = 3.0f * u(rng);
    b.radius = 0.1f + unit(rng);
    const bool fixed = unit(rng) < 0.1f;
    b.inv_mass = fixed ? 0.0f : 0.2f + 2.0f * unit(rng);
    b.inv_inertia = fixed ? 0.0f : b.inv_mass / (0.4f * b.radius * b.radius);
  }
  std::vector<std::uint32_t> slot(2 * count);
  std::iota(slot.begin(), slot.end(), 0u);
  std::shuffle(slot.begin(), slot.end(), rng);
  for (std::size_t k = 0; k < count; ++k) {
    Contact c;
    c.a = slot[2 * k];
    c.b = unit(rng) < 0.3f ? kStaticBody : slot[2 * k + 1];
    const float n[3] = {u(rng), u(rng), u(rng)};
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) + 1e-3f;
    c.nx = n[0] / len, c.ny = n[1] / len, c.nz = n[2] / len;
    c.gap = 0.2f * u(rng);
    c.restitution = unit(rng);
    c.friction = unit(rng) < 0.2f ? 0.0f : unit(rng);
    c.normal_impulse = unit(rng) < 0.5f ? 0.0f : unit(rng);
    c.tx = 0.1f * u(rng), c.ty = 0.1f * u(rng), c.tz = 0.1f * u(rng);
    // A third start with no impulse at all, as new and speculative contacts do: the resting
    // passes leave those that do not close too fast as they are (resting_idle).
    if (start == StartImpulses::SomeZero && unit(rng) < 0.3f) c.normal_impulse = c.tx = c.ty = c.tz = 0.0f;
    p.contacts.push_back(c);
  }
  return p;
}

inline bool same_bits(const SolverProblem& a, const SolverProblem& b) {
  return std::memcmp(a.bodies.data(), b.bodies.data(), a.bodies.size() * sizeof(SolverBody)) == 0 &&
         std::memcmp(a.contacts.data(), b.contacts.data(), a.contacts.size() * sizeof(Contact)) == 0;
}

}  // namespace hail::bench
