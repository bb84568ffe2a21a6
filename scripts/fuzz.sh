#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer + UBSan) in build/fuzz and runs each on
# its seed corpus (tests/fuzz/corpus/). Fails on any crash, hang (10 s per input), leak or
# sanitizer report: libFuzzer then exits non-zero and writes the input that did it as
# build/fuzz/artifacts/<target>-crash-* (or -timeout-*, -leak-*, -oom-*).
#
#   ./scripts/fuzz.sh ci          # what CI runs: the fixed, reproducible run below
#   ./scripts/fuzz.sh [SECONDS]   # explore: SECONDS (default 60) per target, random seed, and the
#                                 # finds kept in build/fuzz/corpus-<target> for the next run
#
# The CI run is the same on every machine: an empty scratch corpus, -seed fixed and a fixed
# number of inputs per target (-runs, about 60 s each on the 2-core development machine), with
# -max_total_time only as a safety cap (on a slower machine it stops early, after a prefix of the
# same inputs). So the run CI does is one that has been run here and seen to pass.
#
# As root, clang and libclang-rt-14-dev (libFuzzer and the sanitizer runtimes) and hail's build
# packages are installed when missing; otherwise the sudo line is printed.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/need_packages.sh

mode="${1:-60}"
# target:corpus:runs:max_len (CI run; seed below). A tests/fuzz/<corpus>.dict, when there is one,
# is passed as the libFuzzer dictionary (-dict). The scene-file target parses and then steps each
# small world, so it runs fewer inputs in about the same time; its inputs may be longer than 4 KB.
# The heightmap and scene-file runs are the first 600,000 and 170,000 inputs of the 1,500,000
# and 250,000 they once had (same seed, so prefixes of runs that passed), to keep the whole of CI
# under 40 minutes on a 2-core AVX2 machine as the test suite grows (900,000 heightmap inputs
# took 73 s there).
# The snapshot reader's run is short (CI time is tight): 100,000 inputs, each restored four ways, 14 s on
# a 2-core AVX2 machine (397 new units from the 3 seeds).
# The recording reader's run is shorter still: 30,000 inputs, each read twice, 3 s on a 2-core AVX2
# machine (311 new units from the 3 seeds; 100,000 inputs reach no more edges, 459).
ci_runs=(heightmap:heightmap:600000:8192 scene-file:scene:170000:65536 snapshot:snapshot:100000:16384
  recording:recording:30000:4096)
ci_seed=20261123
ci_cap=180  # seconds per target, a safety cap only

need_packages clang libclang-rt-14-dev cmake make libtbb-dev libxsimd-dev libeigen3-dev nlohmann-json3-dev libcli11-dev libstb-dev
command -v clang++ > /dev/null || { echo "fuzz.sh: clang++ not found (sudo apt-get install clang)" >&2; exit 1; }
flags="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=undefined -fno-omit-frame-pointer -fsanitize=fuzzer-no-link"
t0=$SECONDS
mkdir -p build
cmake -S . -B build/fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined,float-cast-overflow" \
  -DHAIL_BUILD_FUZZERS=ON -DHAIL_BUILD_TESTS=OFF -DHAIL_WITH_BULLET=OFF -DHAIL_PYTHON=OFF \
  -DHAIL_SIMD_PATHS="$(scripts/host_simd_paths.sh)" > build/fuzz-configure.log  # the paths this machine runs
cmake --build build/fuzz -j "${HAIL_JOBS:-$(nproc 2>/dev/null || echo 2)}" --target fuzz-heightmap fuzz-scene-file fuzz-snapshot fuzz-recording
echo "fuzz.sh: build took $((SECONDS - t0)) s"
mkdir -p build/fuzz/artifacts

if [ "$mode" = ci ]; then
  # Same inputs on every run: a fixed environment, and no address-space randomisation (libFuzzer's
  # compare tracing records pointer values, and with random addresses two runs from one -seed
  # drift apart after a few thousand inputs). -reload=0: no timed corpus re-reads.
  # The stack size limit places the shared libraries, so it is pinned too (Debian's default).
  fixed=(env -i PATH=/usr/bin:/bin LANG=C.UTF-8 UBSAN_OPTIONS=print_stacktrace=1)
  ulimit -s 8192 2> /dev/null || echo "fuzz.sh: note: cannot set the stack limit to 8192 KiB (ulimit -s), so this run may differ from the reference run"
  if setarch "$(uname -m)" -R true 2> /dev/null; then
    fixed+=(setarch "$(uname -m)" -R)
  else
    echo "fuzz.sh: note: cannot turn address-space randomisation off here (setarch -R), so this run may differ from the reference run"
  fi
  for entry in "${ci_runs[@]}"; do
    IFS=: read -r target corpus runs max_len <<< "$entry"
    dict=(); [ -f "tests/fuzz/$corpus.dict" ] && dict=(-dict="tests/fuzz/$corpus.dict")
    scratch="build/fuzz/ci-corpus-$target"
    rm -rf "$scratch" && mkdir -p "$scratch"
    echo "fuzz.sh: fuzz-$target, $runs inputs from seed $ci_seed (seed corpus tests/fuzz/corpus/$corpus)"
    log="build/fuzz/ci-$target.log"
    t0=$SECONDS
    if ! "${fixed[@]}" "build/fuzz/tests/fuzz/fuzz-$target" "$scratch" "tests/fuzz/corpus/$corpus" -seed="$ci_seed" \
        -runs="$runs" -reload=0 -max_total_time="$ci_cap" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" "${dict[@]}" -print_final_stats=1 \
        -artifact_prefix="build/fuzz/artifacts/$target-" > "$log" 2>&1; then
      tail -n 80 "$log"
      echo "fuzz.sh: FAILED: fuzz-$target (whole log: $log; the input is in build/fuzz/artifacts/)" >&2
      exit 1
    fi
    # The last progress line and the final stats; the whole log stays in $log.
    { grep -E '^#[0-9]+' "$log" | tail -n 1; grep -E '^(stat::|Done )' "$log"; } | sed 's/^/    /'
    done_runs=$(sed -n 's/^Done \([0-9]*\) runs.*/\1/p' "$log")
    if [ "${done_runs:-0}" -lt "$runs" ]; then
      echo "fuzz.sh: note: fuzz-$target stopped at the ${ci_cap} s safety cap after ${done_runs:-0} of $runs inputs" \
        "(the same inputs as the reference run, fewer of them)"
    fi
    echo "fuzz.sh: fuzz-$target took $((SECONDS - t0)) s"
  done
else
  seconds=$mode
  case "$seconds" in ''|*[!0-9]*) echo "usage: $0 ci | $0 [SECONDS]" >&2; exit 2 ;; esac
  for entry in "${ci_runs[@]}"; do
    IFS=: read -r target corpus runs max_len <<< "$entry"
    dict=(); [ -f "tests/fuzz/$corpus.dict" ] && dict=(-dict="tests/fuzz/$corpus.dict")
    scratch="build/fuzz/corpus-$target"
    mkdir -p "$scratch"
    echo "fuzz.sh: fuzz-$target for ${seconds} s (seed corpus tests/fuzz/corpus/$corpus)"
    "build/fuzz/tests/fuzz/fuzz-$target" "$scratch" "tests/fuzz/corpus/$corpus" -max_total_time="$seconds" \
      -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" "${dict[@]}" -print_final_stats=1 -artifact_prefix="build/fuzz/artifacts/$target-"
  done
fi
echo "fuzz.sh: no crash, hang or sanitizer report"
