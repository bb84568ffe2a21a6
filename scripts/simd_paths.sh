#!/usr/bin/env bash
# Compares the SIMD paths of one hail-bench binary on this machine (docs/simd.md):
# terrain-rain with 4,000 spheres on 1 thread, each supported path R times (default 5), the
# paths alternating run by run so that a drift in machine speed falls on all of them alike.
# Prints each run's median ms/step and state hash, then per path the median of the runs'
# medians. The hashes must all be equal: every path gives bitwise the same state.
#
#   ./scripts/simd_paths.sh            # R = 5, about 1.5 minutes per path here
#   ./scripts/simd_paths.sh 7 --spheres 16000 --threads 2   # extra arguments go to hail-bench run
#
# Builds the release preset's hail-bench first if needed; HAIL_BUILD_DIR picks another build.
# Keep the machine otherwise idle while it runs.
set -euo pipefail
cd "$(dirname "$0")/.."
repeats="${1:-5}"
[ $# -gt 0 ] && shift
build="${HAIL_BUILD_DIR:-build/release}"
bench="$build/bench/hail-bench"
[ -f "$build/CMakeCache.txt" ] || cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" --target hail-bench -j "$(nproc 2>/dev/null || echo 2)"
paths=()
for p in sse4.2 avx2 avx512; do
  if "$bench" run terrain-rain --spheres 16 --steps 1 --quiet --simd "$p" > /dev/null 2>&1; then paths+=("$p"); fi
done
echo "paths this CPU supports: ${paths[*]}"
declare -A runs
for ((r = 1; r <= repeats; ++r)); do
  for p in "${paths[@]}"; do
    # The full summary (--quiet prints one line, without the median); progress goes to stderr.
    out=$("$bench" run terrain-rain --spheres 4000 --threads 1 "$@" --simd "$p")
    median=$(sed -n 's/.* ms\/step mean, \([0-9.]*\) median.*/\1/p' <<< "$out")
    hash=$(sed -n 's/.*state     hash \([0-9a-f]*\).*/\1/p' <<< "$out")
    echo "run $r  $p  median $median ms/step  hash $hash"
    runs[$p]+="$median "
  done
done
for p in "${paths[@]}"; do
  read -r -a values <<< "${runs[$p]}"
  median=$(printf '%s\n' "${values[@]}" | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}')
  echo "$p: median of $repeats runs' medians $median ms/step"
done
