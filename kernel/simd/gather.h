#pragma once
// One float per lane from base[index[l]]: the hardware gather on AVX2 and AVX-512, element
// loads on SSE4.2; and from a table of one batch, a lane permute. xsimd 8.1's batch::gather
// never reaches its per-architecture overloads (it passes two template arguments to functions
// that take one) and inserts the elements one by one; in the terrain kernel that emulation took
// more time than the tests it fed (perf: docs/benchmarks.md, "Figures behind the code's choices").
// Pure data movement: every path loads the same floats.

#include <cstdint>

#include "kernel/dispatch/simd_arch.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

[[nodiscard]] inline xsimd::batch<float, simd_arch> gather_floats(const float* base,
                                                                  const xsimd::batch<std::int32_t, simd_arch>& index) {
  using batch = xsimd::batch<float, simd_arch>;
#if defined(HAIL_SIMD_PATH_AVX512)
  return batch(_mm512_i32gather_ps(index, base, 4));
#elif defined(HAIL_SIMD_PATH_AVX2)
  return batch(_mm256_i32gather_ps(base, index, 4));
#else
  alignas(64) std::int32_t at[batch::size];
  alignas(64) float lanes[batch::size];
  index.store_aligned(at);
  for (std::size_t l = 0; l < batch::size; ++l) lanes[l] = base[at[l]];
  return batch::load_aligned(lanes);
#endif
}

/// One int per lane from base[index[l]], as gather_floats.
[[nodiscard]] inline xsimd::batch<std::int32_t, simd_arch> gather_ints(
    const std::int32_t* base, const xsimd::batch<std::int32_t, simd_arch>& index) {
  using ibatch = xsimd::batch<std::int32_t, simd_arch>;
#if defined(HAIL_SIMD_PATH_AVX512)
  return ibatch(_mm512_i32gather_epi32(index, base, 4));
#elif defined(HAIL_SIMD_PATH_AVX2)
  return ibatch(_mm256_i32gather_epi32(base, index, 4));
#else
  alignas(64) std::int32_t at[ibatch::size];
  alignas(64) std::int32_t lanes[ibatch::size];
  index.store_aligned(at);
  for (std::size_t l = 0; l < ibatch::size; ++l) lanes[l] = base[at[l]];
  return ibatch::load_aligned(lanes);
#endif
}

/// table[index[l]] in lane l, for a table of one batch (W aligned floats) and indices below
/// W: a lane permute on AVX2 and AVX-512 (one instruction, where a gather loads each element).
[[nodiscard]] inline xsimd::batch<float, simd_arch> pick_lanes(const float* table,
                                                               const xsimd::batch<std::int32_t, simd_arch>& index) {
#if defined(HAIL_SIMD_PATH_AVX512)
  return xsimd::batch<float, simd_arch>(_mm512_permutexvar_ps(index, _mm512_load_ps(table)));
#elif defined(HAIL_SIMD_PATH_AVX2)
  return xsimd::batch<float, simd_arch>(_mm256_permutevar8x32_ps(_mm256_load_ps(table), index));
#else
  return gather_floats(table, index);
#endif
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
