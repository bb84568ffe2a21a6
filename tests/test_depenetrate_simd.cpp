// The SIMD depenetration pass (ContactBatches::depenetrate) moves spheres bitwise as its scalar
// reference does: push_apart over the same contacts, with StepPipeline::depenetrate's rule
// for skipping contacts whose spheres did not move since their previous evaluation. On every
// SIMD path this CPU supports, on random runs of contacts that share no sphere (one colour):
// sphere pairs and static contacts, overlaps beyond the slop and within it, immovable spheres,
// and a last batch only partly filled.

#include <cstring>
#include <random>
#include <span>
#include <vector>

#include "catch.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/depenetrate.h"
#include "simd_paths.h"

using namespace hail;
using namespace hail::testing;

namespace {

struct Scene {
  SphereSoA spheres;
  std::vector<Contact> contacts;
  std::vector<std::uint32_t> moved;  // per slot, then the static slot's entry (0)
};

/// `count` contacts between distinct spheres (a third of them static), most overlapping by up to
/// 0.2 m, so that some push, some sit within the slop and some are apart.
Scene random_scene(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
  Scene scene;
  const std::size_t n = 2 * count;
  for (std::size_t k = 0; k < n; ++k) {
    SphereRecord r{};
    r.px = 10.0f * u(rng), r.py = 10.0f * u(rng), r.pz = 10.0f * u(rng);
    r.radius = 0.2f + unit(rng);
    r.inv_mass = unit(rng) < 0.1f ? 0.0f : 0.1f + unit(rng);
    scene.spheres.add(r);
  }
  SphereSoA& s = scene.spheres;
  for (std::size_t k = 0; k < count; ++k) {
    Contact c;
    c.a = static_cast<std::uint32_t>(2 * k + 1);  // not in slot order: batches gather
    const bool is_static = unit(rng) < 0.35f;
    c.b = is_static ? kStaticBody : static_cast<std::uint32_t>(2 * k);
    const float n3[3] = {u(rng), u(rng), u(rng)};
    const float len = std::sqrt(n3[0] * n3[0] + n3[1] * n3[1] + n3[2] * n3[2]) + 1e-3f;
    c.nx = n3[0] / len, c.ny = n3[1] / len, c.nz = n3[2] / len;
    // 60% overlap by up to 0.2 m, the others are apart by up to 0.1 m.
    const float overlap = unit(rng) < 0.6f ? 0.2f * unit(rng) : -0.1f * unit(rng);
    if (is_static) {
      // The plane n.x = surface_d lies `overlap` inside the sphere's surface.
      c.surface_d = c.nx * s.px[c.a] + c.ny * s.py[c.a] + c.nz * s.pz[c.a] + s.radius[c.a] - overlap;
    } else {
      // b placed along n from a, `overlap` closer than touching.
      const float d = s.radius[c.a] + s.radius[c.b] - overlap;
      s.px[c.b] = s.px[c.a] + c.nx * d, s.py[c.b] = s.py[c.a] + c.ny * d, s.pz[c.b] = s.pz[c.a] + c.nz * d;
    }
    scene.contacts.push_back(c);
  }
  scene.moved.assign(n + 1, 0);
  return scene;
}

bool same_positions(const Scene& x, const Scene& y) {
  const std::size_t n = x.spheres.size();
  return std::memcmp(x.spheres.px.data(), y.spheres.px.data(), n * sizeof(float)) == 0 &&
         std::memcmp(x.spheres.py.data(), y.spheres.py.data(), n * sizeof(float)) == 0 &&
         std::memcmp(x.spheres.pz.data(), y.spheres.pz.data(), n * sizeof(float)) == 0 && x.moved == y.moved;
}

/// The reference: StepPipeline::depenetrate's loop over one colour. Counts the contacts that
/// pushed and those skipped; true if one pushed from beyond twice the slop (push_apart's deep).
bool scalar_pass(Scene& scene, const DepenetrationParams& params, float deep_radius, std::uint32_t now,
                 std::uint32_t previous, std::size_t& pushed, std::size_t& skipped) {
  bool deep = false;
  for (const Contact& c : scene.contacts) {
    const bool dynamic_b = c.b != kStaticBody;
    if (previous > 0 && scene.moved[c.a] < previous && !(dynamic_b && scene.moved[c.b] >= previous)) {
      ++skipped;
      continue;
    }
    if (!push_apart(scene.spheres, c, params, deep_radius, deep)) continue;
    ++pushed;
    scene.moved[c.a] = now;
    if (dynamic_b) scene.moved[c.b] = now;
  }
  return deep;
}

/// Sinks every sphere a little along -y and marks every third one as moved in `stamp`: the
/// next pass must evaluate exactly the contacts of marked spheres (the others would push too if
/// evaluated, so a different skip rule shows).
void disturb(Scene& scene, std::uint32_t stamp) {
  for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
    scene.spheres.py[k] -= 0.05f;
    if (k % 3 == 0) scene.moved[k] = stamp;
  }
}

}  // namespace

TEST_CASE("Every SIMD path's depenetration pass moves spheres exactly as push_apart does one by one",
          "[simd][dispatch][depenetrate]") {
  const DepenetrationParams params{0.8f, 0.01f};
  // Radii are 0.2-1.2 m: contacts on both sides of it, so the deep flag's radius test shows.
  constexpr float kDeepRadius = 0.7f;
  for (SimdPath path : supported_paths()) {
    const ScopedSimdPath scoped(path);
    std::size_t pushed = 0, skipped = 0, first_pass = 0, first_pass_contacts = 0, deep_passes = 0;
    for (const std::size_t count : {std::size_t{5}, std::size_t{16}, std::size_t{37}, std::size_t{400}}) {
      INFO(count << " contacts, path " << simd_path_name(path));
      Scene simd = random_scene(count, static_cast<std::uint32_t>(count) * 7u);
      Scene scalar = simd;
      // Batches staged from the contacts with the spheres' radii; the static slot is n.
      const std::uint32_t colour_begin[2] = {0, static_cast<std::uint32_t>(count)};
      const std::uint8_t serial[1] = {0};
      ContactBatches batches;
      batches.plan(colour_begin, serial);
      const std::size_t n = simd.spheres.size();
      batches.fill(0, batches.batch_count(), simd.contacts, std::span<const float>(simd.spheres.radius.data(), n));
      REQUIRE(batches.tail_begin(0) == count);  // every contact batched, the last batch padded
      DepenetrationArrays arrays{simd.spheres.px.data(),
                                 simd.spheres.py.data(),
                                 simd.spheres.pz.data(),
                                 simd.spheres.inv_mass.data(),
                                 simd.moved.data(),
                                 static_cast<std::int32_t>(n),
                                 params,
                                 kDeepRadius};
      const std::size_t pushed_before = pushed;
      for (std::uint32_t pass = 0; pass < 4; ++pass) {
        const std::uint32_t now = 2 * pass + 1, previous = pass == 0 ? 0 : now - 2;
        const bool simd_deep = batches.depenetrate(0, batches.batch_end(0), arrays, now, previous);
        CHECK(simd_deep == scalar_pass(scalar, params, kDeepRadius, now, previous, pushed, skipped));
        deep_passes += simd_deep ? 1 : 0;
        if (pass == 0) first_pass += pushed - pushed_before;
        CHECK(same_positions(simd, scalar));
        disturb(simd, now + 1);
        disturb(scalar, now + 1);
      }
      // Undisturbed, passes go on until none pushes from beyond twice the slop (the soft
      // step's rule, SoftStepParams::depenetration_iterations_max): the flag the same on both
      // sides in every pass, and it clears.
      bool deep = true;
      for (std::uint32_t pass = 4; pass < 64 && deep; ++pass) {
        const std::uint32_t now = 2 * pass + 1, previous = now - 2;
        deep = batches.depenetrate(0, batches.batch_end(0), arrays, now, previous);
        CHECK(deep == scalar_pass(scalar, params, kDeepRadius, now, previous, pushed, skipped));
        CHECK(same_positions(simd, scalar));
      }
      CHECK_FALSE(deep);
      CHECK(simd.moved[n] == 0);  // the static slot's entry is never written
      first_pass_contacts += count;
    }
    // The runs mean something: the first passes push some contacts and leave others; the later
    // ones skip some contacts and push others.
    CHECK(first_pass > 0);
    CHECK(first_pass < first_pass_contacts);
    CHECK(skipped > 0);
    CHECK(pushed > first_pass);
    CHECK(deep_passes > 0);
  }
}
