// The SIMD collision and resting passes give bitwise the state of their scalar reference (the
// per-contact rules of kernel/contact_impulse.h in a loop), on random runs of contacts that
// share no sphere: sphere-sphere and static contacts, speculative gaps, bodies of zero inverse
// mass (lanes the rules skip), accumulated impulses carried over, and runs whose tail does not
// fill a batch.

#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include "catch.h"
#include "kernel/contact_solve_simd.h"

using namespace hail;

namespace {

struct Problem {
  std::vector<SolverBody> bodies;
  std::vector<Contact> contacts;
};

/// `count` contacts over 2 * count bodies, each body in at most one contact (a colour's run).
Problem random_run(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
  Problem p;
  p.bodies.resize(2 * count);
  for (SolverBody& b : p.bodies) {
    for (int d = 0; d < 3; ++d) b.v[d] = 5.0f * u(rng), b.w[d] = 3.0f * u(rng);
    b.radius = 0.1f + unit(rng);
    const bool fixed = unit(rng) < 0.1f;  // static spheres: the rules skip a pair of two
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
    float n[3] = {u(rng), u(rng), u(rng)};
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) + 1e-3f;
    c.nx = n[0] / len, c.ny = n[1] / len, c.nz = n[2] / len;
    c.gap = 0.2f * u(rng);  // half speculative
    c.restitution = unit(rng);
    c.friction = unit(rng) < 0.2f ? 0.0f : unit(rng);
    c.normal_impulse = unit(rng) < 0.5f ? 0.0f : unit(rng);
    c.tx = 0.1f * u(rng), c.ty = 0.1f * u(rng), c.tz = 0.1f * u(rng);
    p.contacts.push_back(c);
  }
  return p;
}

bool same_bits(const Problem& a, const Problem& b) {
  return std::memcmp(a.bodies.data(), b.bodies.data(), a.bodies.size() * sizeof(SolverBody)) == 0 &&
         std::memcmp(a.contacts.data(), b.contacts.data(), a.contacts.size() * sizeof(Contact)) == 0;
}

}  // namespace

TEST_CASE("SIMD contact passes equal their scalar reference bit for bit", "[solver][simd]") {
  const std::size_t count = GENERATE(1, 7, 8, 9, 16, 23, 256, 1001);
  const float threshold = GENERATE(0.0f, 1.0f);
  INFO(count << " contacts, restitution threshold " << threshold);
  Problem simd = random_run(count, static_cast<std::uint32_t>(count * 31 + 7));
  Problem scalar = simd;
  const float dt = 1.0f / 60.0f;
  bool simd_any = false, scalar_any = false;
  for (int pass = 0; pass < 4; ++pass) {
    simd_any |= solve_collision_run(simd.contacts, simd.bodies, dt, threshold);
    scalar_any |= solve_collision_run_scalar(scalar.contacts, scalar.bodies, dt, threshold);
  }
  CHECK(simd_any == scalar_any);
  CHECK(same_bits(simd, scalar));
  for (int pass = 0; pass < 4; ++pass) {
    solve_resting_run(simd.contacts, simd.bodies, 60.0f);
    solve_resting_run_scalar(scalar.contacts, scalar.bodies, 60.0f);
  }
  CHECK(same_bits(simd, scalar));
  // The passes did something: velocities moved away from where they started.
  const Problem start = random_run(count, static_cast<std::uint32_t>(count * 31 + 7));
  CHECK_FALSE(same_bits(simd, start));
}
