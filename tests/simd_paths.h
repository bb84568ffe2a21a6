#pragma once
// Tests that run something on every SIMD path this CPU supports (kernel/dispatch/simd_dispatch.h).

#include <vector>

#include "kernel/dispatch/simd_dispatch.h"

namespace hail::testing {

/// The SIMD paths this CPU supports, narrowest first.
inline std::vector<SimdPath> supported_paths() {
  std::vector<SimdPath> paths;
  for (SimdPath p : kSimdPaths)
    if (simd_path_supported(p)) paths.push_back(p);
  return paths;
}

/// Makes `path` the active SIMD path for its lifetime, then restores the one before.
class ScopedSimdPath {
 public:
  explicit ScopedSimdPath(SimdPath path) : previous_(active_simd_path()) { set_simd_path(path); }
  ~ScopedSimdPath() { set_simd_path(previous_); }
  ScopedSimdPath(const ScopedSimdPath&) = delete;
  ScopedSimdPath& operator=(const ScopedSimdPath&) = delete;

 private:
  SimdPath previous_;
};

}  // namespace hail::testing
