#!/usr/bin/env bash
# Prints the SIMD paths this machine can run, as HAIL_SIMD_PATHS wants them (cmake/HailSimdPaths.cmake):
# sse4_2, then avx2 (x86-64-v3) and avx512 (x86-64-v4: F, BW, CD, DQ, VL) when /proc/cpuinfo lists
# their flags. The sanitizer and fuzz builds compile only these: code for a path the machine
# cannot run is never executed by their tests, and compiling it under a sanitizer costs minutes.
set -euo pipefail
flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
has() { for f in "$@"; do [[ " $flags " == *" $f "* ]] || return 1; done; }
paths="sse4_2"
if has avx avx2 bmi1 bmi2 f16c fma lzcnt movbe 2>/dev/null || has avx avx2 bmi1 bmi2 f16c fma abm movbe; then
  paths+=";avx2"
  has avx512f avx512bw avx512cd avx512dq avx512vl && paths+=";avx512"
fi
echo "$paths"
