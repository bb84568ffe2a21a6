#pragma once
// The SIMD instruction set that this translation unit's SIMD code is compiled for, and the
// namespace that keeps it apart from the same code compiled for another one.
//
// Every build holds the SIMD kernels three times (kernel/simd/, compiled once per path by
// kernel/CMakeLists.txt with -march=x86-64-v2, -v3 and -v4 and HAIL_SIMD_PATH_* defined), and
// kernel/dispatch/simd_dispatch.h picks one at start-up. Inline functions and templates compiled in
// several translation units with different -m flags are a trap: the linker keeps one copy of
// each (weak symbols), which may be the AVX-512 one, and every caller then runs it, on any CPU.
// So everything a SIMD header defines lives in `inline namespace HAIL_SIMD_NS`, a different
// namespace for each path (simd_sse4_2, simd_avx2, simd_avx512, and simd_base for ordinary
// translation units, which get xsimd's default architecture for their own flags): the copies
// have different names and are never merged. Code that includes these headers still names
// them hail::SpherePacket and so on. tests/check_simd_symbols.cmake checks the result.

#include <cstdint>
#include <type_traits>
#include <xsimd/xsimd.hpp>

#include "kernel/dispatch/simd_namespace.h"

#if defined(HAIL_SIMD_PATH_SSE4_2)
#define HAIL_SIMD_XSIMD_ARCH xsimd::sse4_2
#elif defined(HAIL_SIMD_PATH_AVX2)
// xsimd::avx2, not fma3<avx2>: no kernel may fuse a multiply and an add (every path must give
// the same bits), and -ffp-contract=off keeps the compiler from doing it either.
#define HAIL_SIMD_XSIMD_ARCH xsimd::avx2
#elif defined(HAIL_SIMD_PATH_AVX512)
#define HAIL_SIMD_XSIMD_ARCH xsimd::avx512bw
#else
#define HAIL_SIMD_XSIMD_ARCH xsimd::default_arch
#endif

namespace hail {
inline namespace HAIL_SIMD_NS {

/// The xsimd architecture of this translation unit's SIMD code.
using simd_arch = HAIL_SIMD_XSIMD_ARCH;
static_assert(simd_arch::supported(), "the -march flags of this translation unit do not enable its SIMD path");

/// Bit l set for each lane l of `mask` that is true: one movemask (SSE, AVX) or the mask
/// register itself (AVX-512); other instruction sets go through memory (same bits).
template <class T, class Arch>
[[nodiscard]] inline std::uint32_t lane_bits(const xsimd::batch_bool<T, Arch>& mask) {
  static_assert(xsimd::batch_bool<T, Arch>::size <= 32);
#if XSIMD_WITH_AVX512F
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch> && sizeof(T) == 4)
    return static_cast<std::uint32_t>(static_cast<__mmask16>(mask));
#endif
#if XSIMD_WITH_AVX
  if constexpr (std::is_base_of_v<xsimd::avx, Arch> && std::is_same_v<T, float>)
    return static_cast<std::uint32_t>(_mm256_movemask_ps(mask));
#endif
#if XSIMD_WITH_SSE2
  if constexpr (std::is_base_of_v<xsimd::sse2, Arch> && std::is_same_v<T, float>)
    return static_cast<std::uint32_t>(_mm_movemask_ps(mask));
#endif
  alignas(64) bool lanes[xsimd::batch_bool<T, Arch>::size];
  mask.store_aligned(lanes);
  std::uint32_t bits = 0;
  for (std::size_t l = 0; l < xsimd::batch_bool<T, Arch>::size; ++l) bits |= std::uint32_t(lanes[l]) << l;
  return bits;
}

/// Index of the lowest set bit; bits != 0.
[[nodiscard]] inline std::uint32_t lowest_lane(std::uint32_t bits) {
  return static_cast<std::uint32_t>(__builtin_ctz(bits));
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
