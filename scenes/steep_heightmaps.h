#pragma once
// Generated steep and folded heightmaps (issue 28): the kinds of ground that broke contacts on
// real elevation models, small enough to test against brute force. Deterministic from a seed.
// Used by tests/test_steep_terrain.cpp (property tests) and the stability battery.

#include <array>
#include <cstdint>

#include "hail/heightmap.h"

namespace hail::bench {

enum class SteepKind : std::uint8_t {
  Noise,   ///< independent heights +-8 m on 1 m cells: slopes up to 86 degrees everywhere
  Cliffs,  ///< terraces with 6-10 m vertical steps between neighbouring vertices
  Spikes,  ///< flat ground with one vertex in twelve raised or sunk 5-15 m
  Folds,   ///< a zig-zag of +-6 m between neighbours: sharp folds between every cell
};
inline constexpr std::array<SteepKind, 4> kSteepKinds = {SteepKind::Noise, SteepKind::Cliffs, SteepKind::Spikes,
                                                         SteepKind::Folds};
[[nodiscard]] const char* steep_kind_name(SteepKind kind);

/// A cols x rows map of `kind` (1 m cells in x, 0.8 m in z: non-square on purpose).
[[nodiscard]] Heightmap steep_heightmap(SteepKind kind, std::uint32_t seed, std::uint32_t cols = 33,
                                        std::uint32_t rows = 33);

}  // namespace hail::bench
