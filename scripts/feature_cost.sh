#!/usr/bin/env bash
# What a feature costs a scene that does not use it: builds hail with features compiled out and
# compares, in one run with the runs alternating, the median step time of
#   implosion    in the full build  vs  a spheres-only build (no terrain, no continuous
#                collision, no reference walks);
#   terrain-rain in the full build  vs  a build without continuous collision;
#   implosion    in the full build  vs  a build without rotation (frictionless: no angular
#                work either way);
#   terrain-rain with rotation off (--rotation off) in the full build  vs  the build without
#                rotation (friction on linear velocities in both).
# Each pair must also end in the same state (hash): compiling a feature out may not change a
# scene that does not use it. Release builds in build/feature-*; only hail-feature-cost is built.
#
#   ./scripts/feature_cost.sh [REPEATS=5] [SPHERES=4000] [THREADS=1]
set -euo pipefail
cd "$(dirname "$0")/.."
repeats="${1:-5}" spheres="${2:-4000}" threads="${3:-1}"
jobs=$(nproc 2>/dev/null || echo 2)

build() {  # build DIR CMAKE_OPTIONS...: configures DIR once, then builds hail-feature-cost there
  local dir="$1"; shift
  [ -f "$dir/CMakeCache.txt" ] || cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DHAIL_BUILD_TESTS=OFF "$@" > "$dir.configure.log"
  cmake --build "$dir" -j "$jobs" --target hail-feature-cost > "$dir.build.log"
}
mkdir -p build
# The full build: build/release when there is one (any Release build of the defaults will do).
full=build/feature-full
[ -f build/release/CMakeCache.txt ] && full=build/release
build "$full"
build build/feature-spheres -DHAIL_WITH_TERRAIN=OFF -DHAIL_WITH_CONTINUOUS_COLLISION=OFF -DHAIL_WITH_REFERENCE_WALKS=OFF
build build/feature-no-ccd -DHAIL_WITH_CONTINUOUS_COLLISION=OFF
build build/feature-no-rotation -DHAIL_WITH_ROTATION=OFF

# compare SCENE BUILD_A BUILD_B [FLAGS...]: ABBA-alternating runs, medians, ratio B / A, hashes.
compare() {
  local scene="$1" a="$2" b="$3" ta=() tb=() line ha hb
  shift 3
  for ((k = 0; k < repeats; ++k)); do
    for dir in $([ $((k % 2)) -eq 0 ] && echo "$a $b" || echo "$b $a"); do
      line=$("$dir/bench/feature_cost/hail-feature-cost" "$scene" --spheres "$spheres" --threads "$threads" "$@")
      echo "  $(basename "$dir"): $line" >&2
      ms=$(sed -E 's/.*median ([0-9.]+) ms.*/\1/' <<< "$line")
      hash=$(sed -E 's/.*hash ([0-9a-f]+).*/\1/' <<< "$line")
      if [ "$dir" = "$a" ]; then ta+=("$ms"); ha="$hash"; else tb+=("$ms"); hb="$hash"; fi
    done
  done
  local ma mb
  ma=$(printf '%s\n' "${ta[@]}" | sort -g | awk '{v[NR]=$1} END {print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}')
  mb=$(printf '%s\n' "${tb[@]}" | sort -g | awk '{v[NR]=$1} END {print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}')
  printf '%-13s %-16s %8.4f ms   %-21s %8.4f ms   ratio %.3f   hashes %s\n' "$scene${*:+ $*}" "$(basename "$a")" "$ma" \
    "$(basename "$b")" "$mb" "$(awk -v a="$ma" -v b="$mb" 'BEGIN {print b / a}')" \
    "$([ "$ha" = "$hb" ] && echo "equal ($ha)" || echo "DIFFER ($ha vs $hb)")"
  [ "$ha" = "$hb" ]
}
echo "feature_cost.sh: $repeats runs each, $spheres spheres, $threads thread(s), medians of per-run medians"
compare implosion "$full" build/feature-spheres
compare terrain-rain "$full" build/feature-no-ccd
compare implosion "$full" build/feature-no-rotation
compare terrain-rain "$full" build/feature-no-rotation --rotation off
