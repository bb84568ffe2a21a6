// The staged SIMD collision and resting passes (ContactBatches) give bitwise the state of their
// scalar reference (the per-contact rules of kernel/solver/contact_impulse.h in a loop), on random runs
// of contacts that share no sphere: sphere-sphere and static contacts, speculative gaps, bodies of zero inverse
// mass (lanes the rules skip), accumulated impulses carried over, and runs whose last batch is
// only partly filled (padding lanes); in each FrictionWork mode (no friction, friction without rotation, the full
// rules). The cradle chain runs on every SIMD path this CPU supports (the rest on the active
// one; tests/test_simd_dispatch.cpp compares every path).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "catch.h"
#include "kernel/solver/contact_solve_simd.h"
#include "scenes/solver_problems.h"
#include "simd_paths.h"

using namespace hail;

namespace {

using Problem = hail::bench::SolverProblem;
using hail::bench::same_bits;

Problem random_run(std::size_t count, std::uint32_t seed) { return hail::bench::random_contacts(count, seed); }

/// Warm start, 4 collision and 4 resting passes over one colour holding every contact of p:
/// SIMD batches (the last padded), or (simd false) the scalar rules alone.
void run_passes(Problem& p, bool simd, FrictionWork work, float threshold = 0.5f) {
  const std::uint32_t colour_begin[2] = {0, static_cast<std::uint32_t>(p.contacts.size())};
  const float dt = 1.0f / 60.0f;
  ContactBatches batches;
  batches.stage(p.contacts, colour_begin, 1, p.bodies);
  const std::size_t batched = simd ? batches.batch_end(0) : 0;
  const std::span<Contact> rest = std::span(p.contacts).subspan(simd ? batches.tail_begin(0) : 0);
  if (simd) batches.warm_start(0, batched, p.bodies, work);
  warm_start_run_scalar(rest, p.bodies, work);
  for (std::uint32_t pass = 0; pass < 4; ++pass) {
    if (simd) batches.solve_collision(0, batched, p.bodies, dt, threshold, pass, work);
    solve_collision_run_scalar(rest, p.bodies, dt, threshold, pass, work);
  }
  for (int pass = 0; pass < 4; ++pass) {
    if (simd) batches.solve_resting(0, batched, p.bodies, 1.0f / dt, work);
    solve_resting_run_scalar(rest, p.bodies, 1.0f / dt, work);
  }
  if (simd) batches.store_impulses(p.contacts);
}

/// The modes this build has: the full rules only with rotation compiled in.
std::vector<FrictionWork> friction_modes() {
  // Built from one array (a push_back after an initializer list trips GCC 12's -Warray-bounds
  // false positive in the sanitizer build).
  constexpr FrictionWork kAll[] = {kNoFriction, kLinearFriction, kWithFriction};
  return std::vector<FrictionWork>(std::begin(kAll), std::end(kAll));
}

}  // namespace

TEST_CASE("SIMD contact passes equal their scalar reference bit for bit", "[solver][simd]") {
  const std::size_t count = GENERATE(1, 7, 8, 9, 16, 23, 256, 1001);
  const float threshold = GENERATE(0.0f, 1.0f);
  const FrictionWork work = GENERATE(from_range(friction_modes()));
  // The uniform-acceleration integrator's approach speeds (solve_collision's gravity_closing):
  // gravity scales of 1, 0.5 and 2 (0 for immovable bodies), so that pairs differ too.
  const bool approach = GENERATE(false, true);
  INFO(count << " contacts, restitution threshold " << threshold << ", friction mode " << int(work) << ", approach "
             << approach);
  Problem simd = random_run(count, static_cast<std::uint32_t>(count * 31 + 7));
  if (approach)
    for (std::size_t i = 0; i + 1 < simd.bodies.size(); ++i)
      simd.bodies[i].gravity_scale = simd.bodies[i].inv_mass > 0.0f ? (i % 3 == 0   ? 1.0f
                                                                       : i % 3 == 1 ? 0.5f
                                                                                    : 2.0f)
                                                                    : 0.0f;
  const float gravity_dt_values[3] = {0.5f, -9.81f / 60.0f, 0.25f};
  const float* gravity_dt = approach ? gravity_dt_values : nullptr;
  Problem scalar = simd;
  // One colour holding every contact: all in batches, the last one padded when count % W != 0
  // (the padding lanes must change nothing); no scalar tail.
  const std::uint32_t colour_begin[2] = {0, static_cast<std::uint32_t>(count)};
  ContactBatches batches;
  batches.stage(simd.contacts, colour_begin, 1, simd.bodies);
  const std::size_t W = contact_batch_width();
  REQUIRE(batches.batch_end(0) == (count + W - 1) / W);
  REQUIRE(batches.tail_begin(0) == count);
  const std::span<Contact> tail = std::span(simd.contacts).subspan(batches.tail_begin(0));
  const float dt = 1.0f / 60.0f;
  bool simd_any = false, scalar_any = false;
  for (std::uint32_t pass = 0; pass < 4; ++pass) {
    // From pass 1 on, batches whose bodies did not change are skipped: must change nothing.
    simd_any |= batches.solve_collision(0, batches.batch_end(0), simd.bodies, dt, threshold, pass, work, gravity_dt);
    simd_any |= solve_collision_run_scalar(tail, simd.bodies, dt, threshold, pass, work, gravity_dt);
    scalar_any |= solve_collision_run_scalar(scalar.contacts, scalar.bodies, dt, threshold, pass, work, gravity_dt);
  }
  CHECK(simd_any == scalar_any);
  batches.store_impulses(simd.contacts);
  CHECK(same_bits(simd, scalar));  // velocities and every impulse, the bounce impulses included
  // Some contact bounced (so the comparison of bounce impulses is not of zeros alone), and a
  // contact's bounce is positive exactly when some pass applied an impulse to it.
  CHECK(std::any_of(scalar.contacts.begin(), scalar.contacts.end(),
                    [](const Contact& c) { return c.bounce_impulse > 0.0f; }) == scalar_any);
  for (const Contact& c : scalar.contacts) CHECK(c.bounce_impulse >= 0.0f);
  batches.warm_start(0, batches.batch_end(0), simd.bodies, work);
  warm_start_run_scalar(tail, simd.bodies, work);
  warm_start_run_scalar(scalar.contacts, scalar.bodies, work);
  for (int pass = 0; pass < 4; ++pass) {
    batches.solve_resting(0, batches.batch_end(0), simd.bodies, 60.0f, work);
    solve_resting_run_scalar(tail, simd.bodies, 60.0f, work);
    solve_resting_run_scalar(scalar.contacts, scalar.bodies, 60.0f, work);
  }
  batches.store_impulses(simd.contacts);
  CHECK(same_bits(simd, scalar));
  if (!has_rotation(work)) {  // angular velocities neither read nor written
    const Problem start = random_run(count, static_cast<std::uint32_t>(count * 31 + 7));
    for (std::size_t i = 0; i < start.bodies.size(); ++i)
      CHECK(std::memcmp(simd.bodies[i].w, start.bodies[i].w, sizeof start.bodies[i].w) == 0);
  }
  // The passes did something: velocities moved away from where they started.
  const Problem start = random_run(count, static_cast<std::uint32_t>(count * 31 + 7));
  CHECK_FALSE(same_bits(simd, start));
  // The static body was never written.
  const SolverBody& fixed = simd.bodies.back();
  CHECK(
      (fixed.v[0] == 0.0f && fixed.v[1] == 0.0f && fixed.v[2] == 0.0f && fixed.w[0] == 0.0f && fixed.inv_mass == 0.0f));
}

TEST_CASE("Skipping unchanged batches keeps a Newton's cradle chain exact across colours", "[solver][simd]") {
  // 2W + 1 touching spheres on the x axis, the first moving at +1 m/s; 2W contacts in two
  // colours of W (even and odd joints), so every colour is one full SIMD batch of the path. An
  // impulse crosses one joint per colour: the far sphere only leaves if no batch is skipped
  // while its bodies change. On every SIMD path this CPU supports.
  for (SimdPath path : hail::testing::supported_paths()) {
    const hail::testing::ScopedSimdPath scoped(path);
    const int W = static_cast<int>(contact_batch_width());
    const int kSpheres = 2 * W + 1;
    INFO("path " << simd_path_name(path) << ", " << kSpheres << " spheres");
    auto make = [&] {
      Problem p;
      p.bodies.resize(kSpheres + 1);  // + the static body
      for (int i = 0; i < kSpheres; ++i) {
        p.bodies[i].inv_mass = 1.0f;
        p.bodies[i].radius = 0.5f;
        p.bodies[i].inv_inertia = 1.0f / (0.4f * 0.25f);
      }
      p.bodies[0].v[0] = 1.0f;
      for (int parity : {0, 1})
        for (int k = parity; k < kSpheres - 1; k += 2) {
          Contact c;
          c.a = static_cast<std::uint32_t>(k), c.b = static_cast<std::uint32_t>(k + 1);
          c.nx = 1, c.ny = 0, c.nz = 0, c.gap = 0, c.restitution = 1, c.friction = 0;
          p.contacts.push_back(c);
        }
      return p;
    };
    Problem simd = make(), scalar = make();
    const std::uint32_t colour_begin[3] = {0, static_cast<std::uint32_t>(W), static_cast<std::uint32_t>(2 * W)};
    ContactBatches batches;
    batches.stage(simd.contacts, colour_begin, 2, simd.bodies);
    REQUIRE(batches.batch_end(1) == 2);
    std::uint32_t passes = 0;
    for (std::uint32_t pass = 0; pass < 80; ++pass) {
      bool simd_any = false, scalar_any = false;
      for (std::size_t colour : {0, 1}) {
        simd_any |= batches.solve_collision(batches.batch_begin(colour), batches.batch_end(colour), simd.bodies,
                                            1.0f / 60.0f, 0.0f, pass);
        simd_any |= solve_collision_run_scalar(
            std::span(simd.contacts)
                .subspan(batches.tail_begin(colour), colour_begin[colour + 1] - batches.tail_begin(colour)),
            simd.bodies, 1.0f / 60.0f, 0.0f, pass);
        scalar_any |= solve_collision_run_scalar(std::span(scalar.contacts).subspan(colour_begin[colour], W),
                                                 scalar.bodies, 1.0f / 60.0f, 0.0f, pass);
      }
      REQUIRE(simd_any == scalar_any);
      if (!simd_any) break;
      ++passes;
    }
    batches.store_impulses(simd.contacts);
    CHECK(same_bits(simd, scalar));
    CHECK(passes >= static_cast<std::uint32_t>(W));  // the impulse needed many passes to cross the chain
    CHECK(simd.bodies[kSpheres - 1].v[0] == Approx(1.0f).margin(1e-5));
    for (int i = 0; i < kSpheres - 1; ++i) CHECK(std::abs(simd.bodies[i].v[0]) < 1e-5f);
  }
}

TEST_CASE("Resting and warm-start passes leave contacts with no impulse that close slowly as they are",
          "[solver][simd]") {
  // Two full batches and a partial one: the first all idle (no impulse, a gap, separating or
  // closing slower than gap / dt), the second idle but for one lane closing faster than its gap
  // allows, the third one idle lane. Idle lanes' bodies must keep every bit; the closing lane
  // must get an impulse; SIMD equals scalar. On every SIMD path this CPU supports.
  for (SimdPath path : hail::testing::supported_paths()) {
    const hail::testing::ScopedSimdPath scoped(path);
    const std::size_t W = contact_batch_width();
    const std::size_t count = 2 * W + 1, closing_lane = W + 3;
    INFO("path " << simd_path_name(path));
    auto make = [&] {
      Problem p;
      p.bodies.resize(2 * count + 1);  // + the static body
      for (std::size_t k = 0; k < count; ++k) {
        SolverBody& a = p.bodies[2 * k];
        SolverBody& b = p.bodies[2 * k + 1];
        for (SolverBody* body : {&a, &b}) body->inv_mass = 1.0f, body->radius = 0.5f, body->inv_inertia = 10.0f;
        a.w[1] = 0.5f, b.w[2] = -0.25f;  // spin: friction would act on a slip
        // The one bit the rule's zero impulse would change: vb + 0 turns -0 into +0.
        b.v[1] = -0.0f;
        // a moves along +x towards b at 0.3 m/s: a gap of 0.01 m allows 0.6 m/s at dt = 1/60.
        a.v[0] = k == closing_lane ? 2.0f : (k % 2 == 0 ? 0.3f : -0.3f);
        Contact c;
        c.a = static_cast<std::uint32_t>(2 * k), c.b = static_cast<std::uint32_t>(2 * k + 1);
        c.nx = 1, c.ny = 0, c.nz = 0, c.gap = 0.01f, c.restitution = 0.5f, c.friction = 0.8f;
        p.contacts.push_back(c);
      }
      return p;
    };
    for (const FrictionWork work : friction_modes()) {
      INFO("friction mode " << int(work));
      const Problem start = make();
      Problem simd = make(), scalar = make();
      const std::uint32_t colour_begin[2] = {0, static_cast<std::uint32_t>(count)};
      ContactBatches batches;
      batches.stage(simd.contacts, colour_begin, 1, simd.bodies);
      REQUIRE(batches.batch_end(0) == 3);
      batches.warm_start(0, 3, simd.bodies, work);
      warm_start_run_scalar(scalar.contacts, scalar.bodies, work);
      for (int pass = 0; pass < 3; ++pass) {
        batches.solve_resting(0, 3, simd.bodies, 60.0f, work);
        solve_resting_run_scalar(scalar.contacts, scalar.bodies, 60.0f, work);
      }
      batches.store_impulses(simd.contacts);
      CHECK(same_bits(simd, scalar));
      for (std::size_t k = 0; k < count; ++k) {
        INFO("contact " << k);
        const bool idle = k != closing_lane;
        for (std::size_t side : {2 * k, 2 * k + 1})
          CHECK((std::memcmp(&simd.bodies[side], &start.bodies[side], sizeof(SolverBody)) == 0) == idle);
        CHECK((simd.contacts[k].normal_impulse > 0.0f) == !idle);
      }
    }
  }
}

TEST_CASE("Frictionless passes do no angular work and match the full rules to rounding", "[solver][simd]") {
  const std::size_t count = GENERATE(9, 256, 1001);
  INFO(count << " contacts");
  Problem base = random_run(count, static_cast<std::uint32_t>(count * 17 + 3));
  for (Contact& c : base.contacts) c.friction = 0.0f, c.tx = c.ty = c.tz = 0.0f;
  Problem simd = base, scalar = base, linear = base;
  run_passes(simd, true, kNoFriction);
  run_passes(scalar, false, kNoFriction);
  run_passes(linear, false, kLinearFriction);
  CHECK(same_bits(simd, scalar));  // the SIMD frictionless passes equal their scalar reference
  // With zero friction, friction without rotation adds nothing (zero impulses: the same values,
  // up to the sign of a zero).
  for (std::size_t i = 0; i < base.bodies.size(); ++i)
    for (int d = 0; d < 3; ++d) CHECK(linear.bodies[i].v[d] == scalar.bodies[i].v[d]);
  for (std::size_t k = 0; k < base.contacts.size(); ++k) {
    CHECK(linear.contacts[k].normal_impulse == scalar.contacts[k].normal_impulse);
    CHECK(linear.contacts[k].bounce_impulse == scalar.contacts[k].bounce_impulse);
  }
  CHECK(std::any_of(simd.contacts.begin(), simd.contacts.end(),
                    [](const Contact& c) { return c.bounce_impulse > 0.0f; }));
  Problem full = base;
  run_passes(full, false, kWithFriction);
  for (std::size_t i = 0; i < base.bodies.size(); ++i) {
    INFO("body " << i);
    for (int d = 0; d < 3; ++d) {
      CHECK(scalar.bodies[i].w[d] == base.bodies[i].w[d]);  // no spin from normal impulses
      // The full rules differ only by the rounding of the angular terms they compute.
      CHECK(std::fabs(scalar.bodies[i].v[d] - full.bodies[i].v[d]) <= 1e-4f * (1.0f + std::fabs(full.bodies[i].v[d])));
    }
  }
}

TEST_CASE("Friction without rotation: SIMD equals scalar, no angular velocity is read or written", "[solver][simd]") {
  const std::size_t count = GENERATE(9, 256, 1001);
  INFO(count << " contacts");
  Problem base = random_run(count, static_cast<std::uint32_t>(count * 13 + 5));
  // Poisoned angular velocities: any read would make a velocity NaN, any write change the bits.
  for (std::size_t i = 0; i + 1 < base.bodies.size(); ++i)
    for (float& w : base.bodies[i].w) w = std::numeric_limits<float>::quiet_NaN();
  Problem simd = base, scalar = base;
  run_passes(simd, true, kLinearFriction);
  run_passes(scalar, false, kLinearFriction);
  CHECK(same_bits(simd, scalar));
  for (std::size_t i = 0; i < base.bodies.size(); ++i) {
    INFO("body " << i);
    CHECK(std::memcmp(simd.bodies[i].w, base.bodies[i].w, sizeof base.bodies[i].w) == 0);
    for (int d = 0; d < 3; ++d) CHECK(std::isfinite(simd.bodies[i].v[d]));
  }
  for (const Contact& c : simd.contacts) CHECK((std::isfinite(c.tx) && std::isfinite(c.ty) && std::isfinite(c.tz)));
  CHECK(std::any_of(simd.contacts.begin(), simd.contacts.end(), [](const Contact& c) { return c.tx != 0.0f; }));
}

TEST_CASE("A sphere sliding on the ground: without rotation friction stops it, with rotation it rolls at 5/7",
          "[solver][friction]") {
  // One resting pass on a sphere (m 1, r 0.5) sliding at 2 m/s while closing at 0.1 m/s, with
  // friction large enough not to limit: the friction impulse removes the whole slip through the
  // effective mass, m without rotation (it stops), and 1 / (1/m + r^2 / I) = 2/7 m with rotation
  // (it keeps 5/7 of its speed and rolls: v = w r).
  for (const FrictionWork work : friction_modes()) {
    if (work == kNoFriction) continue;
    INFO("friction mode " << int(work));
    Problem p;
    p.bodies.resize(2);  // the sphere, then the static body
    SolverBody& b = p.bodies[0];
    b.v[0] = 2.0f, b.v[1] = -0.1f, b.v[2] = 0.0f;
    b.w[0] = b.w[1] = b.w[2] = 0.0f;
    b.inv_mass = 1.0f, b.radius = 0.5f, b.inv_inertia = 1.0f / (0.4f * 0.25f);
    Contact c;
    c.a = 0, c.b = kStaticBody, c.nx = 0, c.ny = -1, c.nz = 0, c.gap = 0, c.friction = 100.0f;
    p.contacts.push_back(c);
    solve_resting_run_scalar(p.contacts, p.bodies, 60.0f, work);
    CHECK(p.contacts[0].normal_impulse == Approx(0.1f));
    CHECK(p.bodies[0].v[1] == Approx(0.0f).margin(1e-7));
    if (work == kLinearFriction) {
      CHECK(p.bodies[0].v[0] == Approx(0.0f).margin(1e-6));
      CHECK(p.contacts[0].tx == Approx(2.0f));
      CHECK((p.bodies[0].w[0] == 0.0f && p.bodies[0].w[1] == 0.0f && p.bodies[0].w[2] == 0.0f));
    } else {
      CHECK(p.bodies[0].v[0] == Approx(2.0f * 5.0f / 7.0f));
      CHECK(-p.bodies[0].w[2] * 0.5f == Approx(p.bodies[0].v[0]));  // rolling: no slip at the contact
    }
  }
}
