// The SIMD brute-force pair kernel finds exactly the pairs of its scalar reference.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "catch.h"
#include "kernel/broadphase/sphere_grid.h"
#include "kernel/broadphase/sphere_pairs.h"

namespace {

hail::SphereSoA random_cloud(std::size_t n, float extent, std::uint32_t seed) {
  hail::SphereSoA s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-extent, extent), rad(0.05f, 1.0f);
  for (std::size_t k = 0; k < n; ++k)
    s.add({pos(rng), pos(rng), pos(rng), 0, 0, 0, 0, 0, 0, rad(rng), 1.0f, 1.0f, 0.5f, 0.5f, 0});
  return s;
}

}  // namespace

TEST_CASE("SIMD pair search equals the scalar reference on random clouds", "[pairs][simd]") {
  const std::size_t n = GENERATE(1, 2, 7, 8, 9, 15, 16, 17, 33, 500, 1999);
  const float margin = GENERATE(0.0f, 0.3f);
  const hail::SphereSoA s = random_cloud(n, 2.0f + 0.02f * static_cast<float>(n), static_cast<std::uint32_t>(n));
  std::vector<hail::SpherePair> scalar, simd;
  hail::find_sphere_pairs_scalar(s, 0, s.size(), margin, scalar);
  hail::find_sphere_pairs_simd(s, 0, s.size(), margin, simd);
  INFO(n << " spheres, margin " << margin << ": " << scalar.size() << " pairs");
  CHECK(simd == scalar);
  if (n >= 500) CHECK(!scalar.empty());  // the cloud is dense enough that the test means something
}

TEST_CASE("Pair search over a sub-range of rows gives that slice of the full result", "[pairs]") {
  const hail::SphereSoA s = random_cloud(300, 4.0f, 7);
  std::vector<hail::SpherePair> all, part;
  hail::find_sphere_pairs_simd(s, 0, s.size(), 0.0f, all);
  hail::find_sphere_pairs_simd(s, 0, 100, 0.0f, part);
  hail::find_sphere_pairs_simd(s, 100, 300, 0.0f, part);
  CHECK(part == all);
}

TEST_CASE("Coincident centres give a finite unit normal", "[pairs]") {
  // Which one: the pair's own (tests/test_degenerate_starts.cpp).
  hail::SphereSoA s;
  s.add({1, 2, 3, 0, 0, 0, 0, 0, 0, 0.5f, 1, 1, 0.5f, 0.5f, 0});
  s.add({1, 2, 3, 0, 0, 0, 0, 0, 0, 0.5f, 1, 1, 0.5f, 0.5f, 0});
  const hail::Contact c = hail::make_sphere_contact(s, {0, 1});
  CHECK(std::abs(std::sqrt(c.nx * c.nx + c.ny * c.ny + c.nz * c.nz) - 1.0f) <= 1e-6f);
  CHECK(c.gap == -1.0f);
}

TEST_CASE("Grid pair search returns exactly the brute-force pairs, in order", "[pairs][grid]") {
  const std::size_t n = GENERATE(1, 2, 17, 300, 3000);
  const float margin = GENERATE(0.0f, 0.25f);
  hail::SphereSoA s =
      random_cloud(n, 1.0f + 0.5f * std::cbrt(static_cast<float>(n)), static_cast<std::uint32_t>(n + 11));
  // Mixed radii: one sphere ten times larger than the rest.
  if (n > 2) s.radius[1] = 3.0f;
  std::vector<hail::SpherePair> brute, grid;
  std::vector<std::uint32_t> row;
  hail::find_sphere_pairs_scalar(s, 0, s.size(), margin, brute);
  hail::SphereGrid g;
  g.build(s, margin);
  g.find_pairs(s, 0, s.size() / 2, margin, grid, row);
  g.find_pairs(s, s.size() / 2, s.size(), margin, grid, row);
  INFO(n << " spheres, margin " << margin << ": " << brute.size() << " pairs");
  CHECK(grid == brute);
}
