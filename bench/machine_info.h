#pragma once
// What a benchmark number was measured on: printed next to every time.

#include <string>

namespace hail::bench {

std::string cpu_model();
std::string simd_path();   ///< the xsimd architecture this binary's kernels use
std::string build_flags();

}  // namespace hail::bench
