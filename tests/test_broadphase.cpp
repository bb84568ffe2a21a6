// Every sphere-sphere pair search (scalar and SIMD brute force, uniform grid, sort-and-sweep,
// sphere BVH) returns exactly the same pairs in exactly the same order, on the clouds that
// break broadphases: mixed radii with giants, coincident centres, flat layers, pairs exactly
// at the predicate's boundary, non-finite spheres; whole and in row blocks, serial and parallel.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "catch.h"
#include "kernel/broadphase/sorted_axis_pairs.h"
#include "kernel/broadphase/sphere_bvh_pairs.h"
#include "kernel/broadphase/sphere_grid.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/dispatch/kernel_table.h"
#include "simd_paths.h"

namespace {

using hail::SpherePair;
using hail::SphereSoA;

enum class Cloud { EqualRadii, MixedWithGiants, Coincident, FlatLayer, KnifeEdge, Sprawling };

const char* name_of(Cloud c) {
  switch (c) {
    case Cloud::EqualRadii:
      return "equal radii";
    case Cloud::MixedWithGiants:
      return "radii 1:20 with giants";
    case Cloud::Coincident:
      return "coincident";
    case Cloud::FlatLayer:
      return "flat layer";
    case Cloud::KnifeEdge:
      return "knife edge";
    case Cloud::Sprawling:
      return "sprawling";
  }
  return "?";
}

void add(SphereSoA& s, float x, float y, float z, float r) {
  s.add({x, y, z, 0, 0, 0, 0, 0, 0, r, 1.0f, 1.0f, 0.5f, 0.5f, 0});
}

// Random clouds dense enough to have pairs at every size (box side grows as cbrt(n)).
SphereSoA make_cloud(Cloud kind, std::size_t n, float margin, std::uint32_t seed) {
  SphereSoA s;
  std::mt19937 rng(seed);
  const float half = 1.0f + 0.6f * std::cbrt(static_cast<float>(n));
  std::uniform_real_distribution<float> pos(-half, half), unit(0.0f, 1.0f);
  for (std::size_t k = 0; k < n; ++k) {
    switch (kind) {
      case Cloud::EqualRadii:
        add(s, pos(rng), pos(rng), pos(rng), 0.5f);
        break;
      case Cloud::MixedWithGiants: {
        // Radii 0.1..0.5 spread geometrically, and one sphere in 40 a giant of 2.0 (20x the smallest).
        const float r = k % 40 == 3 ? 2.0f : 0.1f * std::pow(5.0f, unit(rng));
        add(s, pos(rng), pos(rng), pos(rng), r);
        break;
      }
      case Cloud::Coincident:
        add(s, 1.5f, -2.0f, 3.0f, 0.25f);
        break;
      case Cloud::FlatLayer:
        add(s, 2.0f * pos(rng), 0.75f, 2.0f * pos(rng), 0.5f);
        break;
      case Cloud::KnifeEdge: {
        // Pairs (2m, 2m + 1) whose centres are a few ulps either side of exactly the reach the
        // predicate computes, along a random axis, from coordinates near 0 (ulps finer than the
        // radii's, where one ulp less box loses pairs), below 1, or of a few hundred (ulps
        // coarser than the radii's). The other two axes only keep the pairs 40 apart.
        if (k % 2 == 1) break;
        const std::size_t m = k / 2;
        const float ra = 0.05f + unit(rng), rb = 0.05f + unit(rng);
        const float reach = rb + (ra + margin);
        const int axis = static_cast<int>(rng() % 3);
        float p[3];
        p[axis] = (m % 4 == 3 ? 300.0f : m % 4 == 2 ? 1.0f : 1.0e-3f) * unit(rng);
        p[(axis + 1) % 3] = 40.0f * static_cast<float>(m % 64);
        p[(axis + 2) % 3] = 40.0f * static_cast<float>(m / 64);
        add(s, p[0], p[1], p[2], ra);
        float target = p[axis] + reach;
        for (int step = static_cast<int>(rng() % 7) - 3; step != 0; step += step > 0 ? -1 : 1)
          target = std::nextafter(target, step > 0 ? std::numeric_limits<float>::infinity() : 0.0f);
        p[axis] = target;
        if (k + 1 < n) add(s, p[0], p[1], p[2], rb);
        break;
      }
      case Cloud::Sprawling: {
        // Clusters of four 1,000 apart along a diagonal, far from the origin: hundreds of
        // thousands of cells per axis, past where the grid clamps its coordinates
        // (SphereGrid::kMaxCell), with pairs at coarse coordinates.
        const float base = 5.0e4f + 1000.0f * static_cast<float>(k / 4);
        add(s, base + unit(rng), base + 0.5f * unit(rng), -base + unit(rng), 0.3f + 0.3f * unit(rng));
        break;
      }
    }
  }
  return s;
}

// Runs one search over rows [0, n) in blocks of `block` rows, concatenated in block order.
template <class Search>
std::vector<SpherePair> in_blocks(const SphereSoA& s, std::size_t block, Search&& search) {
  std::vector<SpherePair> out;
  for (std::size_t first = 0; first < s.size(); first += block) search(first, std::min(s.size(), first + block), out);
  return out;
}

// Every search other than the scalar reference, whole and in blocks of 64 rows, must return
// exactly `reference` (find_sphere_pairs_scalar's result).
void check_all_searches_agree(const SphereSoA& s, float margin, const std::vector<SpherePair>& reference) {
  hail::SphereGrid grid;
  hail::SortedAxisPairs sweep;
  hail::SphereBvhPairs bvh;
  grid.build(s, margin);
  sweep.build(s, margin);
  bvh.build(s, margin);
  std::vector<std::uint32_t> row;
  auto simd = [&](std::size_t a, std::size_t b, std::vector<SpherePair>& out) {
    hail::find_sphere_pairs_simd(s, a, b, margin, out);
  };
  auto by_grid = [&](std::size_t a, std::size_t b, std::vector<SpherePair>& out) {
    grid.find_pairs(s, a, b, margin, out, row);
  };
  auto by_grid_scalar = [&](std::size_t a, std::size_t b, std::vector<SpherePair>& out) {
    grid.find_pairs_scalar(s, a, b, margin, out, row);
  };
  auto by_sweep = [&](std::size_t a, std::size_t b, std::vector<SpherePair>& out) {
    sweep.find_pairs(s, a, b, margin, out, row);
  };
  auto by_bvh = [&](std::size_t a, std::size_t b, std::vector<SpherePair>& out) {
    bvh.find_pairs(s, a, b, margin, out, row);
  };
  for (const std::size_t block : {s.size() + 1, std::size_t{64}}) {
    INFO("rows in blocks of " << block << " (sweep axis " << sweep.axis() << ", " << sweep.class_count()
                              << " radius classes)");
    CHECK(in_blocks(s, block, simd) == reference);
    CHECK(in_blocks(s, block, by_grid) == reference);
    CHECK(in_blocks(s, block, by_grid_scalar) == reference);
    CHECK(in_blocks(s, block, by_sweep) == reference);
    CHECK(in_blocks(s, block, by_bvh) == reference);
  }
}

}  // namespace

TEST_CASE("Every pair search returns exactly the brute-force pairs, in order", "[pairs][broadphase]") {
  const Cloud kind = GENERATE(Cloud::EqualRadii, Cloud::MixedWithGiants, Cloud::Coincident, Cloud::FlatLayer,
                              Cloud::KnifeEdge, Cloud::Sprawling);
  const std::size_t n = GENERATE(1, 2, 17, 500, 3000);
  const float margin = GENERATE(0.0f, 0.3f);
  const SphereSoA s = make_cloud(kind, n, margin, static_cast<std::uint32_t>(n * 7 + static_cast<int>(kind)));
  std::vector<SpherePair> reference;
  hail::find_sphere_pairs_scalar(s, 0, s.size(), margin, reference);
  INFO(name_of(kind) << ", " << n << " spheres, margin " << margin << ": " << reference.size() << " pairs");
  // The comparison means something only where there are pairs to get wrong.
  if (n >= 17) CHECK(reference.size() >= n / 8);
  check_all_searches_agree(s, margin, reference);
}

TEST_CASE("Knife-edge clouds have pairs on both sides of the predicate's boundary", "[pairs][broadphase]") {
  // Guards the test above: if the nudges missed the boundary, it would test nothing special.
  const float margin = 0.3f;
  const SphereSoA s = make_cloud(Cloud::KnifeEdge, 3000, margin, 5);
  std::vector<SpherePair> pairs;
  hail::find_sphere_pairs_scalar(s, 0, s.size(), margin, pairs);
  std::size_t partnered = 0;
  for (const SpherePair p : pairs) partnered += p.a % 2 == 0 && p.b == p.a + 1;
  INFO(partnered << " of 1500 pairs accepted");
  CHECK(partnered > 300);
  CHECK(partnered < 1200);
}

TEST_CASE("An accepted pair is never farther apart on an axis than the exact sum of its radii", "[pairs][broadphase]") {
  // The property that lets boxes of half-extent |r| and |r + margin| prune without widening
  // (kernel/broadphase/sphere_pair_bounds.h), checked in double on pairs placed within a few ulps of the
  // predicate's boundary in random directions, at fine and coarse coordinates.
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), signed_unit(-1.0f, 1.0f);
  std::size_t accepted = 0, within_an_ulp = 0, beyond = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const float scale = trial % 3 == 0 ? 1.0f : trial % 3 == 1 ? 100.0f : 1.0e4f;
    const float margin = trial % 2 ? 0.0f : 0.3f * unit(rng);
    const float ri = 0.01f + unit(rng), rj = 0.01f + 2.0f * unit(rng);
    const float ri_margin = ri + margin, reach = rj + ri_margin;
    const float pi[3] = {scale * signed_unit(rng), scale * signed_unit(rng), scale * signed_unit(rng)};
    double dir[3] = {signed_unit(rng), signed_unit(rng), signed_unit(rng)};
    if (trial % 4 == 0) dir[1] = dir[2] = 0.0;  // along an axis: where the bound is tightest
    const double norm = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (norm < 1e-3) continue;
    const double distance = double(reach) * (1.0 + 4e-7 * signed_unit(rng));
    float pj[3];
    for (int a = 0; a < 3; ++a) pj[a] = static_cast<float>(pi[a] + distance * dir[a] / norm);
    if (!hail::spheres_within(pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2], reach)) continue;
    ++accepted;
    const double bound = double(ri_margin) + double(rj);
    for (int a = 0; a < 3; ++a) {
      const double gap = std::fabs(double(pj[a]) - double(pi[a]));
      beyond += gap > bound;
      within_an_ulp += bound - gap <= 2.4e-7 * bound;
    }
  }
  INFO(accepted << " accepted, " << within_an_ulp << " axes within an ulp of the bound");
  CHECK(beyond == 0);
  CHECK(accepted > 10000);
  CHECK(within_an_ulp > 100);
}

TEST_CASE("Pair searches agree around a huge sphere and non-finite spheres", "[pairs][broadphase]") {
  SphereSoA s = make_cloud(Cloud::EqualRadii, 800, 0.0f, 99);
  const float margin = GENERATE(0.0f, 0.3f);
  s.radius[5] = 40.0f;  // 80 times the others, overlapping most of the cloud
  s.px[17] = std::numeric_limits<float>::quiet_NaN();
  s.py[18] = std::numeric_limits<float>::infinity();
  s.pz[19] = -std::numeric_limits<float>::infinity();
  s.radius[20] = std::numeric_limits<float>::quiet_NaN();
  s.px[21] = s.px[22] = 1.0e30f;  // finite, far away, with a partner at the same point
  s.py[22] = s.py[21];
  s.pz[22] = s.pz[21];
  std::vector<SpherePair> reference;
  hail::find_sphere_pairs_scalar(s, 0, s.size(), margin, reference);
  CHECK(std::count(reference.begin(), reference.end(), SpherePair{21, 22}) == 1);
  check_all_searches_agree(s, margin, reference);
}

TEST_CASE("Rebuilding a pair search over other clouds forgets the previous one", "[pairs][broadphase]") {
  // One object per search rebuilt over clouds that shrink and grow: capacity is reused, so a
  // stale slot or class from the last build would show up as a wrong pair.
  hail::SphereGrid grid;
  hail::SortedAxisPairs sweep;
  hail::SphereBvhPairs bvh;
  std::vector<std::uint32_t> row;
  std::uint32_t seed = 1;
  for (const std::size_t n : {3000, 17, 500, 2, 1200}) {
    for (const Cloud kind : {Cloud::MixedWithGiants, Cloud::EqualRadii}) {
      const SphereSoA s = make_cloud(kind, n, 0.1f, seed++);
      std::vector<SpherePair> reference, by_grid, by_sweep, by_bvh;
      hail::find_sphere_pairs_scalar(s, 0, s.size(), 0.1f, reference);
      grid.build(s, 0.1f);
      sweep.build(s, 0.1f);
      bvh.build(s, 0.1f);
      grid.find_pairs(s, 0, s.size(), 0.1f, by_grid, row);
      sweep.find_pairs(s, 0, s.size(), 0.1f, by_sweep, row);
      bvh.find_pairs(s, 0, s.size(), 0.1f, by_bvh, row);
      INFO(name_of(kind) << ", " << n << " spheres");
      CHECK(by_grid == reference);
      CHECK(by_sweep == reference);
      CHECK(by_bvh == reference);
    }
  }
}

TEST_CASE("Pair searches give the same pairs when row blocks run in parallel", "[pairs][broadphase]") {
  const SphereSoA s = make_cloud(Cloud::MixedWithGiants, 3000, 0.3f, 42);
  std::vector<SpherePair> reference;
  hail::find_sphere_pairs_scalar(s, 0, s.size(), 0.3f, reference);
  hail::SphereGrid grid;
  hail::SortedAxisPairs sweep;
  hail::SphereBvhPairs bvh;
  grid.build(s, 0.3f);
  sweep.build(s, 0.3f);
  bvh.build(s, 0.3f);
  constexpr std::size_t kBlock = 64;
  const std::size_t blocks = (s.size() + kBlock - 1) / kBlock;
  // Per-block buffers merged in block order: the same vector for any thread count.
  auto parallel = [&](const auto& search) {
    std::vector<std::vector<SpherePair>> out(blocks);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::vector<std::uint32_t> row;
      search.find_pairs(s, b * kBlock, std::min(s.size(), (b + 1) * kBlock), 0.3f, out[b], row);
    });
    std::vector<SpherePair> merged;
    for (const auto& part : out) merged.insert(merged.end(), part.begin(), part.end());
    return merged;
  };
  CHECK(parallel(grid) == reference);
  CHECK(parallel(sweep) == reference);
  CHECK(parallel(bvh) == reference);
}

TEST_CASE("The grid with per-pair margins returns brute force's pairs after the per-pair filter",
          "[pairs][broadphase]") {
  // The filter of kernel/world/step_pipeline.cpp (keep_pairs_within_their_margin), applied here to
  // brute force's pairs; the grid applies it inside the search, scalar and on every SIMD path.
  const Cloud kind = GENERATE(Cloud::EqualRadii, Cloud::MixedWithGiants, Cloud::KnifeEdge, Cloud::Sprawling);
  const float margin = 0.3f, factor = GENERATE(0.0f, 0.5f, 2.0f);
  const SphereSoA s = make_cloud(kind, 2000, margin, 11 + static_cast<std::uint32_t>(kind));
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> travel(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    // At rest, slow, fast (beyond the step's margin), and a NaN (the step's margin).
    const std::uint32_t pick = rng() % 8;
    travel[i] = pick == 0                 ? 0.0f
                : pick == 7               ? 1.0f
                : pick == 6 && i % 5 == 0 ? std::numeric_limits<float>::quiet_NaN()
                                          : 0.1f * unit(rng);
  }
  std::vector<SpherePair> reference;
  hail::find_sphere_pairs_scalar(s, 0, s.size(), margin, reference);
  const std::size_t unfiltered = reference.size();
  std::erase_if(reference, [&](const SpherePair& p) {
    const float pair_margin = std::min(margin, factor * (travel[p.a] + travel[p.b]));
    const float reach = s.radius[p.b] + (s.radius[p.a] + pair_margin);
    return !hail::spheres_within(s.px[p.b] - s.px[p.a], s.py[p.b] - s.py[p.a], s.pz[p.b] - s.pz[p.a], reach);
  });
  INFO(name_of(kind) << ", factor " << factor << ": " << reference.size() << " of " << unfiltered << " pairs kept");
  CHECK(reference.size() > 0);
  if (factor < 2.0f) CHECK(reference.size() < unfiltered);
  hail::SphereGrid grid;
  grid.build(s, margin, {travel.data(), factor});
  std::vector<std::uint32_t> row;
  auto scalar = [&](std::size_t a, std::size_t b, std::vector<SpherePair>& out) {
    grid.find_pairs_scalar(s, a, b, margin, out, row);
  };
  CHECK(in_blocks(s, 64, scalar) == reference);
  for (const hail::SimdPath path : hail::testing::supported_paths()) {
    INFO("path " << hail::simd_path_name(path));
    const hail::SimdKernels& k = hail::simd_kernels(path);
    auto simd = [&](std::size_t a, std::size_t b, std::vector<SpherePair>& out) {
      k.grid_find_pairs(grid.view(), s, a, b, margin, out, row);
    };
    CHECK(in_blocks(s, 64, simd) == reference);
    CHECK(in_blocks(s, s.size() + 1, simd) == reference);
  }
}

TEST_CASE("The grid agrees with brute force at the extremes of its cell size", "[pairs][broadphase]") {
  // An infinite radius makes the cell infinite (every sphere in cell 0, every pair with that
  // sphere accepted); zero radii and margin make it the smallest float (coordinates clamp).
  for (const float special : {std::numeric_limits<float>::infinity(), 0.0f}) {
    SphereSoA s = make_cloud(Cloud::EqualRadii, 300, 0.0f, 5);
    if (special == 0.0f)
      for (std::size_t i = 0; i < s.size(); ++i) s.radius[i] = 0.0f;
    else
      s.radius[7] = special;
    const float margin = 0.0f;
    std::vector<SpherePair> reference;
    hail::find_sphere_pairs_scalar(s, 0, s.size(), margin, reference);
    INFO("special radius " << special << ": " << reference.size() << " pairs");
    hail::SphereGrid grid;
    grid.build(s, margin);
    std::vector<SpherePair> scalar, simd;
    std::vector<std::uint32_t> row;
    grid.find_pairs_scalar(s, 0, s.size(), margin, scalar, row);
    grid.find_pairs(s, 0, s.size(), margin, simd, row);
    CHECK(scalar == reference);
    CHECK(simd == reference);
  }
}
