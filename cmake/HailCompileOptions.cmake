# Flags every hail target shares. Determinism depends on them: no fast-math, and
# -ffp-contract=off so the compiler never fuses a*b+c differently in two code paths.
add_library(hail_compile_options INTERFACE)
if(HAIL_NATIVE)
  set(hail_arch_flag -march=native)
else()
  set(hail_arch_flag -march=${HAIL_ARCH})
endif()
target_compile_options(hail_compile_options INTERFACE
  $<BUILD_INTERFACE:${hail_arch_flag}>
  $<BUILD_INTERFACE:-ffp-contract=off>
  $<BUILD_INTERFACE:-fno-math-errno>
  $<BUILD_INTERFACE:-Wall> $<BUILD_INTERFACE:-Wextra> $<BUILD_INTERFACE:-Wno-unused-parameter>)

# HAIL_ARCH (or -march=native) is the base level of everything above; the SIMD kernels are
# compiled once more per SIMD path, each with its own level, and chosen at start-up.
include(HailSimdPaths)
