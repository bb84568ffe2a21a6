#pragma once
// compress_lanes: a SIMD batch's hit lanes packed to the front and stored at once, where a loop
// over the set lanes would take a branch per hit. Whether a batch holds a hit (a grid slot
// within reach, a leaf triangle touched) is close to a coin toss in the pair search and the
// terrain walk, so that loop mispredicted about once per hit (what the packing saves:
// docs/benchmarks.md, "Figures behind the code's choices"). AVX-512 has a compress instruction; AVX2 has none, so
// a 256-entry table (kSetLanes) gives the permutation; SSE4.2 keeps the loop, the reference.
// Included only by kernel/simd/ translation units.

#include <array>
#include <cstdint>

#include "kernel/dispatch/simd_arch.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

/// kSetLanes[m]: the numbers of the set bits of the 8-bit mask m, lowest first, one per byte,
/// the unused bytes 0: widened to 32 bits, a _mm256_permutevar8x32 order that packs those lanes.
inline constexpr std::array<std::uint64_t, 256> kSetLanes = [] {
  std::array<std::uint64_t, 256> table{};
  for (std::uint32_t mask = 0; mask < 256; ++mask) {
    std::uint32_t n = 0;
    for (std::uint32_t lane = 0; lane < 8; ++lane)
      if (mask & (1u << lane)) table[mask] |= std::uint64_t{lane} << (8 * n++);
  }
  return table;
}();

/// Lane numbers 0, 1, 2, ...: compress_lanes of these gives the set lanes themselves.
alignas(64) inline constexpr std::int32_t kLaneNumbers[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};

/// Stores value[l] for each set lane l of `lanes` (the path's batch width of them), lowest lane
/// first, at out[0], out[1], ...; returns how many. Writes a whole batch: `out` must have room
/// for one (what lies past the returned count is unspecified). T is a 32-bit integer.
template <class T>
[[gnu::always_inline]] inline std::uint32_t compress_lanes(T* out, const T* value, std::uint32_t lanes) {
  static_assert(sizeof(T) == 4);
#if defined(HAIL_SIMD_PATH_AVX512)
  // Into a register, then one store: the compress-to-memory form is slow on some CPUs (Zen 4).
  const __m512i all = _mm512_loadu_si512(value);
  _mm512_storeu_si512(out, _mm512_maskz_compress_epi32(static_cast<__mmask16>(lanes), all));
  return static_cast<std::uint32_t>(__builtin_popcount(lanes));
#elif defined(HAIL_SIMD_PATH_AVX2)
  const __m256i all = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(value));
  const __m256i order = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(kSetLanes[lanes & 0xFFu])));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_permutevar8x32_epi32(all, order));
  return static_cast<std::uint32_t>(__builtin_popcount(lanes));
#else
  std::uint32_t count = 0;
  for (; lanes != 0; lanes &= lanes - 1) out[count++] = value[lowest_lane(lanes)];
  return count;
#endif
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
