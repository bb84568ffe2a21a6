#include "machine_info.h"

#include <fstream>
#include <xsimd/xsimd.hpp>

namespace hail::bench {

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

std::string simd_path() { return xsimd::default_arch::name(); }

std::string build_flags() { return HAIL_BUILD_FLAGS; }

}  // namespace hail::bench
