#!/usr/bin/env bash
# Runs the Google Benchmark microbenchmarks (bench/micro/, the hail-micro executable): single
# kernels on fixed seeds, SIMD next to scalar, each BVH walk, each pair search. Every benchmark
# runs 5 times and reports the median, mean, standard deviation and coefficient of variation;
# the JSON (with the machine, SIMD path and flags in its "context") goes to build/micro.json.
#
#   ./scripts/micro.sh                                   # everything (about 5 minutes on 2 cores)
#   ./scripts/micro.sh --benchmark_filter='terrain/'     # extra arguments go to hail-micro
#   ./scripts/micro.sh --benchmark_min_time=0.05         # a quick look
#
# Builds the release preset's hail-micro first if needed (needs libbenchmark-dev:
# sudo apt-get install libbenchmark-dev). HAIL_BUILD_DIR picks another build directory.
# Keep the machine otherwise idle while it runs.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${HAIL_BUILD_DIR:-build/release}"
micro="$build/bench/micro/hail-micro"
[ -f "$build/CMakeCache.txt" ] || cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" --target hail-micro -j "$(nproc 2>/dev/null || echo 2)"
[ -x "$micro" ] || { echo "no $micro: is libbenchmark-dev installed? (sudo apt-get install libbenchmark-dev)" >&2; exit 1; }
mkdir -p build
"$micro" --benchmark_out=build/micro.json --benchmark_out_format=json --benchmark_repetitions=5 \
  --benchmark_report_aggregates_only=true "$@"
