#pragma once
// The permute table that packs the set lanes of an 8-lane mask to the front on AVX2, which has
// no compress instruction (AVX-512's vpcompressd does it in one): kSetLanes[m] holds the
// numbers of the set bits of m, lowest first, one per byte, the unused bytes 0. Widened to
// 32-bit lane numbers (_mm256_cvtepu8_epi32) it is a _mm256_permutevar8x32 order, or itself
// the lane numbers. Used where a batch's hits are appended without a branch per hit
// (kernel/simd/sphere_grid.cpp, kernel/simd/terrain_contacts.cpp).

#include <array>
#include <cstdint>

#include "kernel/simd_arch.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

inline constexpr std::array<std::uint64_t, 256> kSetLanes = [] {
  std::array<std::uint64_t, 256> table{};
  for (std::uint32_t mask = 0; mask < 256; ++mask) {
    std::uint32_t n = 0;
    for (std::uint32_t lane = 0; lane < 8; ++lane)
      if (mask & (1u << lane)) table[mask] |= std::uint64_t{lane} << (8 * n++);
  }
  return table;
}();

}  // namespace HAIL_SIMD_NS
}  // namespace hail
