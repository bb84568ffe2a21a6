#pragma once
// Which SIMD path the kernels run. One binary holds every SIMD kernel three times, compiled for
// SSE4.2 (x86-64-v2, 4 floats per batch), AVX2 (x86-64-v3, 8) and AVX-512 (x86-64-v4:
// F/BW/CD/DQ/VL, 16); the rest of hail is compiled for the base level (HAIL_ARCH, x86-64-v2 by
// default). The first kernel call, or the first World, picks the widest path the CPU and OS
// support, unless the environment variable HAIL_SIMD names one (sse4.2, avx2, avx512);
// set_simd_path() forces one from code (hail-bench --simd). The choice is a table of function
// pointers (kernel/dispatch/kernel_table.h), called once per block of work, never per sphere.
//
// Every path performs the scalar reference's float operations lane by lane, with no fused
// multiply-add and no reordered sums, and the batch width never decides anything a result
// depends on, so a step gives bitwise the same state on every path (tests/test_simd_dispatch.cpp).
//
// A path that cannot be had is an error, never a quiet fallback: a benchmark that asked for
// AVX-512 must not time SSE4.2 and call it AVX-512.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace hail {

/// A SIMD instruction set the kernels are compiled for.
enum class SimdPath : std::uint8_t {
  Sse42,   ///< "sse4.2": SSE4.2 (x86-64-v2), 4 floats per batch
  Avx2,    ///< "avx2": AVX2 (x86-64-v3), 8 floats per batch
  Avx512,  ///< "avx512": AVX-512 F/BW/CD/DQ/VL (x86-64-v4), 16 floats per batch
};

/// Every path, narrowest first.
inline constexpr SimdPath kSimdPaths[] = {SimdPath::Sse42, SimdPath::Avx2, SimdPath::Avx512};

/// "sse4.2", "avx2" or "avx512": the names HAIL_SIMD and hail-bench --simd take.
[[nodiscard]] const char* simd_path_name(SimdPath path);
/// The path called `name` (as simd_path_name gives it); InvalidArgument naming it otherwise.
[[nodiscard]] SimdPath parse_simd_path(std::string_view name);
/// Floats per SIMD batch on `path`: 4, 8 or 16.
[[nodiscard]] std::size_t simd_path_width(SimdPath path);
/// True when this build compiled `path` (HAIL_SIMD_PATHS, cmake/HailSimdPaths.cmake) and this
/// CPU has every instruction it was compiled for and the OS saves its registers (cpuid and xgetbv).
[[nodiscard]] bool simd_path_supported(SimdPath path);
/// The widest path simd_path_supported accepts. Every x86-64-v2 CPU supports sse4.2.
[[nodiscard]] SimdPath best_simd_path();
/// The supported paths, narrowest first, separated by spaces ("sse4.2 avx2").
[[nodiscard]] std::string supported_simd_paths();

/// The path the kernels use now. The first call (World's constructor makes one) chooses it:
/// the path HAIL_SIMD names if it is set and not empty, else best_simd_path(). Throws
/// InvalidArgument if HAIL_SIMD names no path or one this CPU lacks (and again on later calls,
/// until set_simd_path chooses one).
[[nodiscard]] SimdPath active_simd_path();
/// Makes `path` the active one, overriding HAIL_SIMD; InvalidArgument (nothing changes) if this
/// CPU lacks it. Switch between steps, not while a World steps on another thread: a step
/// keeps the table it started its solve with, but its other phases read the active one.
void set_simd_path(SimdPath path);
/// How the active path was chosen: "auto", "HAIL_SIMD" or "set_simd_path".
[[nodiscard]] const char* simd_path_origin();

}  // namespace hail
