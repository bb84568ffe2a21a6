#include "kernel/dispatch/simd_dispatch.h"

#include <cpuid.h>
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <mutex>

#include "hail/errors.h"
#include "kernel/dispatch/kernel_table.h"

namespace hail {
namespace {

/// What cpuid and xgetbv say, once.
struct CpuFeatures {
  bool v2 = false;  // x86-64-v2: SSE3, SSSE3, SSE4.1, SSE4.2, POPCNT, CX16, LAHF/SAHF
  bool v3 = false;  // x86-64-v3: v2 + AVX, AVX2, BMI1, BMI2, F16C, FMA, LZCNT, MOVBE, with YMM state saved by the OS
  bool v4 = false;  // x86-64-v4: v3 + AVX-512 F, BW, CD, DQ, VL, with opmask/ZMM state saved by the OS

  CpuFeatures() {
    unsigned a = 0, b = 0, c = 0, d = 0;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return;
    auto bit = [](unsigned reg, int k) { return (reg >> k & 1u) != 0; };
    const unsigned c1 = c;
    unsigned b7 = 0;
    if (__get_cpuid_max(0, nullptr) >= 7) {
      __cpuid_count(7, 0, a, b, c, d);
      b7 = b;
    }
    unsigned c81 = 0;
    if (__get_cpuid(0x80000001u, &a, &b, &c, &d)) c81 = c;
    v2 = bit(c1, 0) && bit(c1, 9) && bit(c1, 13) && bit(c1, 19) && bit(c1, 20) && bit(c1, 23) && bit(c81, 0);
    // The OS must save the wider registers on a context switch (XCR0), or AVX code faults.
    std::uint64_t xcr0 = 0;
    if (bit(c1, 27)) {  // OSXSAVE
      unsigned lo = 0, hi = 0;
      __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
      xcr0 = (std::uint64_t(hi) << 32) | lo;
    }
    const bool ymm_state = (xcr0 & 0x6u) == 0x6u;    // SSE and AVX state
    const bool zmm_state = (xcr0 & 0xE6u) == 0xE6u;  // and opmask, ZMM_Hi256, Hi16_ZMM
    v3 = v2 && ymm_state && bit(c1, 12) && bit(c1, 22) && bit(c1, 28) && bit(c1, 29) && bit(b7, 3) && bit(b7, 5) &&
         bit(b7, 8) && bit(c81, 5);
    v4 = v3 && zmm_state && bit(b7, 16) && bit(b7, 17) && bit(b7, 28) && bit(b7, 30) && bit(b7, 31);
  }
};

const CpuFeatures& cpu_features() {
  static const CpuFeatures features;
  return features;
}

// The paths this build compiled (HAIL_SIMD_PATHS, kernel/CMakeLists.txt); sse4.2 always.
#ifdef HAIL_BUILT_SIMD_PATH_AVX2
constexpr bool kBuiltAvx2 = true;
#else
constexpr bool kBuiltAvx2 = false;
#endif
#ifdef HAIL_BUILT_SIMD_PATH_AVX512
constexpr bool kBuiltAvx512 = true;
#else
constexpr bool kBuiltAvx512 = false;
#endif

/// Only for a path simd_path_supported accepts (so one that was built).
const SimdKernels& table_of(SimdPath path) {
  switch (path) {
    case SimdPath::Sse42:
      break;
    case SimdPath::Avx2:
#ifdef HAIL_BUILT_SIMD_PATH_AVX2
      return simd_kernels_avx2();
#else
      break;
#endif
    case SimdPath::Avx512:
#ifdef HAIL_BUILT_SIMD_PATH_AVX512
      return simd_kernels_avx512();
#else
      break;
#endif
  }
  return simd_kernels_sse4_2();
}

[[noreturn]] void unsupported(SimdPath path, const char* asked_by) {
  throw InvalidArgument(std::string("hail: ") + asked_by + " asks for the SIMD path " + simd_path_name(path) +
                        ", which this CPU or build does not support (it supports: " + supported_simd_paths() + ")");
}

// The active table. Null until the first active_simd_path() resolves it; the mutex only
// orders that resolution against set_simd_path, every kernel call reads the pointer alone.
std::atomic<const SimdKernels*> g_active{nullptr};
std::atomic<const char*> g_origin{"auto"};
std::mutex g_choose;

const SimdKernels& resolve_active() {
  if (const SimdKernels* k = g_active.load(std::memory_order_acquire)) return *k;
  const std::lock_guard<std::mutex> lock(g_choose);
  if (const SimdKernels* k = g_active.load(std::memory_order_acquire)) return *k;
  SimdPath path = best_simd_path();
  const char* origin = "auto";
  if (const char* env = std::getenv("HAIL_SIMD"); env != nullptr && *env != '\0') {
    bool known = false;
    for (SimdPath p : kSimdPaths)
      if (std::string_view(env) == simd_path_name(p)) path = p, known = true;
    if (!known)
      throw InvalidArgument(std::string("hail: HAIL_SIMD=") + env +
                            " names no SIMD path (expected sse4.2, avx2 or avx512)");
    if (!simd_path_supported(path)) unsupported(path, "HAIL_SIMD");
    origin = "HAIL_SIMD";
  }
  const SimdKernels& k = table_of(path);
  g_origin.store(origin, std::memory_order_relaxed);
  g_active.store(&k, std::memory_order_release);
  return k;
}

}  // namespace

const char* simd_path_name(SimdPath path) {
  switch (path) {
    case SimdPath::Sse42:
      return "sse4.2";
    case SimdPath::Avx2:
      return "avx2";
    case SimdPath::Avx512:
      return "avx512";
  }
  return "?";
}

SimdPath parse_simd_path(std::string_view name) {
  for (SimdPath p : kSimdPaths)
    if (name == simd_path_name(p)) return p;
  throw InvalidArgument("hail: unknown SIMD path '" + std::string(name) + "' (expected sse4.2, avx2 or avx512)");
}

std::size_t simd_path_width(SimdPath path) { return path == SimdPath::Sse42 ? 4 : path == SimdPath::Avx2 ? 8 : 16; }

bool simd_path_supported(SimdPath path) {
  const CpuFeatures& f = cpu_features();
  switch (path) {
    case SimdPath::Sse42:
      return f.v2;
    case SimdPath::Avx2:
      return kBuiltAvx2 && f.v3;
    case SimdPath::Avx512:
      return kBuiltAvx512 && f.v4;
  }
  return false;
}

SimdPath best_simd_path() {
  // x86-64-v2 is the floor the base code needs anyway: on an older CPU hail does not run at all.
  return simd_path_supported(SimdPath::Avx512) ? SimdPath::Avx512
         : simd_path_supported(SimdPath::Avx2) ? SimdPath::Avx2
                                               : SimdPath::Sse42;
}

std::string supported_simd_paths() {
  std::string names;
  for (SimdPath p : kSimdPaths) {
    if (!simd_path_supported(p)) continue;
    if (!names.empty()) names += ' ';
    names += simd_path_name(p);
  }
  return names.empty() ? "none" : names;
}

SimdPath active_simd_path() { return resolve_active().path; }

void set_simd_path(SimdPath path) {
  if (!simd_path_supported(path)) unsupported(path, "set_simd_path");
  const std::lock_guard<std::mutex> lock(g_choose);
  g_origin.store("set_simd_path", std::memory_order_relaxed);
  g_active.store(&table_of(path), std::memory_order_release);
}

const char* simd_path_origin() {
  (void)resolve_active();
  return g_origin.load(std::memory_order_relaxed);
}

const SimdKernels& simd_kernels() { return resolve_active(); }

const SimdKernels& simd_kernels(SimdPath path) {
  if (!simd_path_supported(path)) unsupported(path, "simd_kernels");
  return table_of(path);
}

}  // namespace hail
