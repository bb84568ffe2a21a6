#pragma once
// What a benchmark number was measured on: printed next to every time.

#include <string>

namespace hail::bench {

std::string cpu_model();
/// The active SIMD path of the kernels (kernel/dispatch/simd_dispatch.h): "avx2", "avx512", "sse4.2".
std::string simd_path();
/// simd_path() with how it was chosen and what this CPU offers, e.g.
/// "avx2 (auto; CPU supports sse4.2 avx2)" or "sse4.2 (--simd/HAIL_SIMD ...)".
std::string simd_description();
/// "auto", "HAIL_SIMD" or "--simd": how simd_path() was chosen.
std::string simd_origin();
/// The SIMD paths this CPU supports, e.g. "sse4.2 avx2 avx512".
std::string simd_supported();
/// The -march level the active path's kernels are compiled for (cmake/HailSimdPaths.cmake).
std::string simd_flags();
/// The flags of the base code (HAIL_ARCH).
std::string build_flags();

}  // namespace hail::bench
