#pragma once
// The step's heuristics: how PairSearch::Automatic picks a pair search and how many solver
// tiles a world is cut into. Tuning, not API: each constant was measured (the comments say
// where), may change with the next measurement, and is read by the step alone (and the tests
// that pin its choices).

#include <algorithm>
#include <cstddef>

#include "hail/world_settings.h"

namespace hail {

/// PairSearch::Automatic: below this many spheres of similar radii brute force wins, above it
/// the grid (crossover measured with `hail-bench pairs`, in random and in Morton order:
/// docs/benchmarks.md, "Figures behind the code's choices").
inline constexpr std::size_t kPairSearchMinSpheres = 1000;
/// Radii are "mixed" when largest / smallest is above kMixedRadiusSpread: the grid's cells must
/// fit the largest, so it needs more spheres to pay; from this count on it beats brute force and
/// the sphere BVH on mixed piles in either slot order (`hail-bench pairs`: docs/benchmarks.md,
/// "Figures behind the code's choices").
inline constexpr std::size_t kMixedPairSearchMinSpheres = 4000;
inline constexpr float kMixedRadiusSpread = 4.0f;
/// Beyond this spread (not measured: the bench's piles stop at 20) a few giants would make
/// every grid cell giant; the sphere BVH, whose boxes fit each sphere, takes over from
/// kGiantPairSearchMinSpheres (its crossover with brute force on the mixed piles).
inline constexpr float kGiantRadiusSpread = 20.0f;
inline constexpr std::size_t kGiantPairSearchMinSpheres = 16000;

/// The tiles a world is cut into, at least, while each still holds kMinParallelTileSpheres: the
/// users' largest desktop CPUs (Ryzen 7 2700X: 8 cores, 16 threads) then have a tile per thread
/// from 4,096 spheres up. The tile stage is one parallel stage over all tiles, so a world of
/// fewer tiles than threads leaves threads idle through most of the solve.
inline constexpr std::size_t kSolverTilesWanted = 16;
/// Smallest tile the split for many threads makes (a smaller world gets fewer tiles): below it a
/// tile's contacts among themselves fill few SIMD batches and more of the contacts cross tiles.
inline constexpr std::size_t kMinParallelTileSpheres = 256;

/// Spheres per solver tile for `spheres` spheres: WorldSettings::solver_tile_spheres, or less for
/// a world of fewer than kSolverTilesWanted tiles of that size: a sixteenth of its spheres
/// (rounded up), at least kMinParallelTileSpheres, and at least half the world (rounded up, at
/// least kMinSolverTileSpheres) when that is smaller still, so that a small world gets two
/// tiles. 0 without tiles. It depends on the sphere count alone, never on the thread count.
/// For the default 2,048: 200 spheres give 2 tiles of 100, 1,000 give 4 of 256, 4,000 give 16
/// of 256, 16,000 give 16 of 1,000, and from 32,768 on the tiles hold 2,048.
[[nodiscard]] constexpr std::size_t solver_tile_size(std::size_t setting, std::size_t spheres) {
  if (setting == 0) return 0;
  const std::size_t half = std::max<std::size_t>((spheres + 1) / 2, kMinSolverTileSpheres);
  const std::size_t share = (spheres + kSolverTilesWanted - 1) / kSolverTilesWanted;
  return std::min(setting, std::max(share, std::min(half, kMinParallelTileSpheres)));
}

/// The search PairSearch::Automatic picks for n spheres with radii in [min_radius, max_radius].
/// The slot order (Morton or not) does not change the choice since the grid's rewrite.
[[nodiscard]] constexpr PairSearch automatic_pair_search(std::size_t n, float min_radius, float max_radius) {
  if (max_radius > kGiantRadiusSpread * min_radius)
    return n < kGiantPairSearchMinSpheres ? PairSearch::BruteForce : PairSearch::Bvh;
  const bool mixed = max_radius > kMixedRadiusSpread * min_radius;
  return n < (mixed ? kMixedPairSearchMinSpheres : kPairSearchMinSpheres) ? PairSearch::BruteForce : PairSearch::Grid;
}

}  // namespace hail
