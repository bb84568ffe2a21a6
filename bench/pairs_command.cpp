#include "pairs_command.h"

// Recipe: each (radius distribution, N) is one random pile, fixed seed, measured twice: slots in
// generated (random) order and Morton-sorted, as World's periodic re-sort leaves them, which
// decides how coherent consecutive rows' memory accesses are. Each method's time is build +
// find_pairs over all rows, called directly on this thread (no TBB), into an output vector kept
// across repeats (so only the first repeat pays its growth); the median of the repeats is printed
// per sphere. Brute force gets fewer repeats, or none, where its predicted time (the last N's,
// scaled by N^2) would pass kBruteBudgetSeconds; the output says so. Each row prints a hash of
// the pair list; "agree" = every method returned the same pairs in the same order.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "cli.h"
#include "kernel/broadphase/sorted_axis_pairs.h"
#include "kernel/broadphase/spatial_order.h"
#include "kernel/broadphase/sphere_bvh_pairs.h"
#include "kernel/broadphase/sphere_grid.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/world/fnv1a.h"
#include "scenes/machine_info.h"

namespace hail::bench {
namespace {

using clock_type = std::chrono::steady_clock;

constexpr float kMargin = 0.1f;
constexpr double kVolumeFraction = 0.3;
constexpr double kBruteBudgetSeconds = 5.0;
constexpr std::size_t kSizes[] = {256, 1000, 4000, 16000, 64000};

enum class Radii { Uniform, Mixed };
constexpr Radii kDistributions[] = {Radii::Uniform, Radii::Mixed};

const char* describe(Radii r) { return r == Radii::Uniform ? "r 0.5" : "r 0.25..2.5, 1% r 5"; }

// Random centres in a cube sized so that the spheres' volumes add up to kVolumeFraction of it,
// a loose pile's density (overlaps allowed, as speculative contacts in a pile overlap).
SphereSoA make_pile(std::size_t n, Radii radii, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> radius(n);
  double volume = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    // Mixed: uniform in 0.25..2.5, and every hundredth sphere a giant of 5 (20x the smallest).
    radius[k] = radii == Radii::Uniform ? 0.5f : k % 100 == 37 ? 5.0f : 0.25f + 2.25f * unit(rng);
    volume += 4.0 / 3.0 * std::numbers::pi * double(radius[k]) * radius[k] * radius[k];
  }
  const float side = static_cast<float>(std::cbrt(volume / kVolumeFraction));
  SphereSoA s;
  s.reserve(n);
  for (std::size_t k = 0; k < n; ++k)
    s.add(
        {side * unit(rng), side * unit(rng), side * unit(rng), 0, 0, 0, 0, 0, 0, radius[k], 1.0f, 1.0f, 0.5f, 0.5f, 0});
  return s;
}

struct Timing {
  double total_ns = 0.0;  // median build + find_pairs, whole pile
  double build_ns = 0.0;  // median build alone
  int repeats = 0;        // 0: skipped
  std::vector<SpherePair> pairs;
};

double nanoseconds(clock_type::duration d) { return std::chrono::duration<double, std::nano>(d).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <class Build, class Find>
Timing time_search(int repeats, Build&& build, Find&& find) {
  Timing t;
  t.repeats = repeats;
  std::vector<double> total, build_only;
  for (int r = 0; r < repeats; ++r) {
    t.pairs.clear();
    const auto t0 = clock_type::now();
    build();
    const auto t1 = clock_type::now();
    find(t.pairs);
    const auto t2 = clock_type::now();
    total.push_back(nanoseconds(t2 - t0));
    build_only.push_back(nanoseconds(t1 - t0));
  }
  t.total_ns = median(total);
  t.build_ns = median(build_only);
  return t;
}

// FNV-1a over the pair list, in order (each index low byte first).
std::uint64_t hash_pairs(const std::vector<SpherePair>& pairs) {
  std::uint64_t h = kFnvOffsetBasis;
  for (const SpherePair p : pairs)
    for (const std::uint32_t v : {p.a, p.b}) {
      const std::byte bytes[4] = {std::byte(v), std::byte(v >> 8), std::byte(v >> 16), std::byte(v >> 24)};
      h = fnv1a(bytes, h);
    }
  return h;
}

enum Method { kBrute, kGrid, kSweep, kBvh, kMethods };
constexpr const char* kMethodNames[kMethods] = {"brute force SIMD", "grid", "sort and sweep", "sphere BVH"};

}  // namespace

int pairs_command(const PairsOptions& o) {
  const int max_n = o.max_n, repeats = o.repeats;

  std::printf("hail-bench pairs: sphere-sphere pair search, build + find_pairs over all rows, 1 thread, median of %d\n",
              repeats);
  std::printf(
      "  random piles at volume fraction %.2f (fixed seeds), margin %.2f; slot order as generated (random)\n"
      "  or Morton-sorted (what World's periodic re-sort gives)\n",
      kVolumeFraction, kMargin);
  std::printf("  machine %s, SIMD %s\n  flags %s\n", cpu_model().c_str(), simd_path().c_str(), build_flags().c_str());
  std::printf("  ns per sphere, build + find (build alone in parentheses); pairs hash = FNV-1a of the pair list\n");
  std::printf("  %-20s %-6s %6s", "radii", "order", "N");
  for (const char* name : kMethodNames) std::printf(" %16s", name);
  std::printf(" %9s %-16s %5s\n", "pairs", "pairs hash", "agree");

  bool all_agree = true;
  for (const Radii radii : kDistributions) {
    for (const bool morton : {false, true}) {
      const char* order_name = morton ? "morton" : "random";
      // time[method][size index]; < 0 where not measured
      std::vector<std::vector<double>> time(kMethods);
      std::vector<std::size_t> sizes;
      std::vector<std::string> notes;
      double brute_seconds_last = 0.0;
      std::size_t brute_n_last = 0;
      for (const std::size_t n : kSizes) {
        if (n > static_cast<std::size_t>(max_n)) continue;
        sizes.push_back(n);
        SphereSoA s = make_pile(n, radii, static_cast<std::uint32_t>(2024 + n));
        if (morton) {
          std::vector<std::uint64_t> keys;
          std::vector<std::uint32_t> order;
          morton_slot_order(s, keys, order);
          s.permute(order);
        }
        SphereGrid grid;
        SortedAxisPairs sweep;
        SphereBvhPairs bvh;
        std::vector<std::uint32_t> row;
        Timing result[kMethods];

        // Brute force is O(N^2): predict this N from the last and cut repeats to the budget.
        int brute_repeats = repeats;
        if (brute_n_last > 0) {
          const double ratio = double(n) / double(brute_n_last);
          const double predicted = brute_seconds_last * ratio * ratio;
          brute_repeats = predicted > kBruteBudgetSeconds
                              ? 0
                              : std::clamp(static_cast<int>(kBruteBudgetSeconds / predicted), 1, repeats);
        }
        if (brute_repeats > 0) {
          result[kBrute] = time_search(
              brute_repeats, [] {},
              [&](std::vector<SpherePair>& out) { find_sphere_pairs_simd(s, 0, n, kMargin, out); });
          brute_seconds_last = result[kBrute].total_ns * 1e-9;
          brute_n_last = n;
        }
        result[kGrid] = time_search(
            repeats, [&] { grid.build(s, kMargin); },
            [&](std::vector<SpherePair>& out) { grid.find_pairs(s, 0, n, kMargin, out, row); });
        result[kSweep] = time_search(
            repeats, [&] { sweep.build(s, kMargin); },
            [&](std::vector<SpherePair>& out) { sweep.find_pairs(s, 0, n, kMargin, out, row); });
        result[kBvh] = time_search(
            repeats, [&] { bvh.build(s, kMargin); },
            [&](std::vector<SpherePair>& out) { bvh.find_pairs(s, 0, n, kMargin, out, row); });

        // The reference is brute force where it ran, else the grid (itself checked at smaller N).
        const std::vector<SpherePair>& reference =
            result[kBrute].repeats > 0 ? result[kBrute].pairs : result[kGrid].pairs;
        bool agree = true;
        std::printf("  %-20s %-6s %6zu", describe(radii), order_name, n);
        for (int m = 0; m < kMethods; ++m) {
          const Timing& t = result[m];
          char cell[32] = "skipped";
          if (t.repeats > 0) {
            agree = agree && t.pairs == reference;
            std::snprintf(cell, sizeof cell, "%.0f (%.0f)", t.total_ns / double(n), t.build_ns / double(n));
          }
          std::printf(" %16s", cell);
          time[m].push_back(t.repeats > 0 ? t.total_ns : -1.0);
        }
        all_agree = all_agree && agree;
        std::printf(" %9zu %016llx %5s\n", reference.size(), static_cast<unsigned long long>(hash_pairs(reference)),
                    agree ? "yes" : "NO");
        if (result[kBrute].repeats == 0)
          notes.push_back("brute force skipped at N = " + std::to_string(n) + ": predicted over " +
                          std::to_string(int(kBruteBudgetSeconds)) +
                          " s per repeat; agreement checked against the grid");
        else if (result[kBrute].repeats < repeats)
          notes.push_back("brute force at N = " + std::to_string(n) + ": " + std::to_string(result[kBrute].repeats) +
                          " repeat(s), to stay within about " + std::to_string(int(kBruteBudgetSeconds)) + " s");
        if (n == sizes.front())
          notes.push_back("sort and sweep: axis " + std::string(1, "xyz"[sweep.axis()]) + ", " +
                          std::to_string(sweep.class_count()) + " radius class(es)");
      }
      for (const std::string& note : notes) std::printf("    (%s)\n", note.c_str());
      // Crossover: the smallest N at which each method is faster than brute force.
      for (int m = kGrid; m < kMethods; ++m) {
        std::size_t first_win = 0;
        bool compared = false;
        for (std::size_t k = 0; k < sizes.size() && time[kBrute][k] >= 0.0; ++k) {
          compared = true;
          if (time[m][k] < time[kBrute][k]) {
            first_win = sizes[k];
            break;
          }
        }
        std::printf("    crossover, %s, %s order: %s ", describe(radii), order_name, kMethodNames[m]);
        if (first_win != 0)
          std::printf("beats brute force from N = %zu%s\n", first_win,
                      first_win == sizes.front() ? " (the smallest N measured)" : "");
        else
          std::printf("does not beat brute force at any N measured%s\n", compared ? "" : " (brute force not run)");
      }
    }
  }
  std::printf("  all methods agree: %s\n", all_agree ? "yes" : "NO");
  return all_agree ? 0 : 1;
}

// The flags of `hail-bench pairs` (bench/cli.h's rules).

void add_pairs_options(CLI::App& app, PairsOptions& o) {
  app.description("sphere-sphere pair searches (brute force, grid, sweep and prune, sphere BVH) by N and radius mix");
  add_count(app, "--max", o.max_n, 1, 10'000'000, "the largest sphere count");
  add_count(app, "--repeats", o.repeats, 1, 1000, "timed repeats; the median is reported");
}

int pairs_command(const std::vector<std::string>& args) {
  const std::optional<PairsOptions> parsed = parse_command("pairs", add_pairs_options, args);
  return parsed ? pairs_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
