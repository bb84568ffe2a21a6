#pragma once
// HAIL_SIMD_NS: the namespace of the SIMD path this translation unit is compiled for
// (simd_sse4_2, simd_avx2, simd_avx512 for kernel/simd/, simd_base for everything else). Headers
// whose inline code a per-path translation unit compiles with its own -march flags wrap it in
// `inline namespace HAIL_SIMD_NS`, so that the linker never merges two paths' copies; see
// kernel/dispatch/simd_arch.h. Without xsimd, for headers that only need the namespace.

#if defined(HAIL_SIMD_PATH_SSE4_2)
#define HAIL_SIMD_NS simd_sse4_2
#elif defined(HAIL_SIMD_PATH_AVX2)
#define HAIL_SIMD_NS simd_avx2
#elif defined(HAIL_SIMD_PATH_AVX512)
#define HAIL_SIMD_NS simd_avx512
#else
#define HAIL_SIMD_NS simd_base
#endif
