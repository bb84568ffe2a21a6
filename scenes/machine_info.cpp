#include "scenes/machine_info.h"

#include <fstream>

#include "kernel/dispatch/simd_dispatch.h"

namespace hail::bench {

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

std::string simd_path() { return simd_path_name(active_simd_path()); }

std::string simd_origin() {
  const std::string origin = simd_path_origin();
  return origin == "set_simd_path" ? "--simd" : origin;
}

std::string simd_supported() { return supported_simd_paths(); }

std::string simd_flags() {
  switch (active_simd_path()) {
    case SimdPath::Sse42:
      return "-march=x86-64-v2";
    case SimdPath::Avx2:
      return "-march=x86-64-v3";
    case SimdPath::Avx512:
      break;
  }
  return "-march=x86-64-v4";
}

std::string simd_description() {
  return simd_path() + " (" + simd_origin() + "; CPU supports " + simd_supported() + ")";
}

std::string build_flags() { return HAIL_BUILD_FLAGS; }

}  // namespace hail::bench
