#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer + UBSan) in build/fuzz and runs each
# for SECONDS (default 60) on its seed corpus (tests/fuzz/corpus/), new finds going to a scratch
# folder. Fails on any crash, hang (10 s per input), leak or sanitizer report: libFuzzer then
# exits non-zero and writes the input that did it as crash-* / timeout-* in the current folder.
#
#   ./scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
command -v clang++ > /dev/null || { echo "fuzz.sh: clang++ not found (sudo apt-get install clang)" >&2; exit 1; }
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -fsanitize=fuzzer-no-link"
cmake -S . -B build/fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DHAIL_BUILD_FUZZERS=ON -DHAIL_BUILD_TESTS=OFF -DHAIL_WITH_BULLET=OFF > build/fuzz-configure.log
cmake --build build/fuzz -j "$(nproc 2>/dev/null || echo 2)" --target fuzz-heightmap fuzz-scene-file
for target in heightmap scene-file; do
  corpus="tests/fuzz/corpus/${target%-file}"
  scratch="build/fuzz/corpus-$target"
  mkdir -p "$scratch"
  echo "fuzz.sh: fuzz-$target for ${seconds} s (seed corpus $corpus)"
  "build/fuzz/tests/fuzz/fuzz-$target" "$scratch" "$corpus" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1
done
echo "fuzz.sh: no crash, hang or sanitizer report"
