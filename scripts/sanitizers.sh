#!/usr/bin/env bash
# The sanitizer runs that CI (.ci/run) does after the release tests. Each fails on any test
# failure or sanitizer report.
#
#   ./scripts/sanitizers.sh asan   # `asan` preset (AddressSanitizer + UBSan, build/asan): every test
#   ./scripts/sanitizers.sh tsan   # `tsan` preset (ThreadSanitizer, build/tsan): the threaded tests
#
# asan builds hail-tests and hail-bench (not hail-micro) and runs the whole ctest suite, then
# every hail-bench command once on a small input (bench_smoke below: a few seconds each), so that
# the command-line parsing, file output (--json, --trace, CSV) and each command's own code run
# under the sanitizers too. A sanitizer report aborts the process that made it, so ctest or the
# command fails. The preset builds -O1 -g1 (the SIMD kernels -O2; -O1 compiles the largest file
# in a third of the time, docs/robustness.md) without ASan's use-after-scope checks, which made the
# SIMD kernels 7x slower (the whole suite took 5 minutes instead of 2 on 2 cores); every other
# ASan and UBSan check is on, and float-cast-overflow (an out-of-range float cast to an integer,
# which -fsanitize=undefined leaves out in GCC) besides.
#
# tsan first builds oneTBB with -fsanitize=thread: Debian's libtbb is not instrumented, so
# ThreadSanitizer cannot see its task hand-offs and reports every one as a race. It takes
# Debian's own source package of the installed libtbb-dev (`apt-get source onetbb`; as root it
# adds a deb-src entry for deb.debian.org when there is none, and runs apt-get update), builds
# libtbb alone (no tbbmalloc, tests or examples) in build/tbb-tsan/ and installs it into
# build/tbb-tsan/install, which later runs reuse. The `tsan` preset is configured against it
# (TBB_DIR), hail-tests carries its lib/ as RUNPATH, and the script checks with ldd that the test
# binary loads the instrumented libtbb before it runs `ctest --preset tsan` (the tests labelled
# "threads": those tagged [threads], which step a world or run a stage crew on more than one
# thread; tests/CMakeLists.txt) with TSAN_OPTIONS=halt_on_error=1: the first report ends the test
# with an error.
#
# As root, missing Debian packages are installed (apt-get); otherwise the sudo line is printed.
# Parallel jobs: HAIL_JOBS (default: nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/need_packages.sh

mode="${1:-}"
case "$mode" in asan|tsan) ;; *) echo "usage: $0 asan|tsan" >&2; exit 2 ;; esac
jobs=${HAIL_JOBS:-$(nproc 2>/dev/null || echo 2)}
say() { echo "sanitizers.sh $mode: $*"; }
fail() { echo "sanitizers.sh $mode: FAILED: $*" >&2; exit 1; }
timed() {  # timed LABEL COMMAND...: runs COMMAND, then prints how long it took
  local label=$1 t0=$SECONDS
  shift
  "$@"
  say "$label took $((SECONDS - t0)) s"
}

need_packages "${hail_test_packages[@]}"
# Only the SIMD paths this machine runs (scripts/host_simd_paths.sh): the others' code would be
# compiled under the sanitizer and never executed.
simd_paths=$(scripts/host_simd_paths.sh)
say "SIMD paths built: $simd_paths"

# Every hail-bench command once, small: a scene by name and one from a file, with --json and
# --trace; compare; accuracy at one dt; one stress case (tests/test_stress.cpp runs them all);
# scale over two counts; query, pairs, bvh-build and rays at their smallest sizes; sleep on a
# small pile; a run with the soft-step solver. Outputs (and the
# last command's log) go to build/asan/bench-smoke/. Each command's exit status counts: a failure
# or a sanitizer report fails.
bench_smoke() {
  local bench=build/asan/bench/hail-bench out=build/asan/bench-smoke
  rm -rf "$out" && mkdir -p "$out"
  local commands=(
    "run terrain-rain --spheres 200 --steps 5 --threads 2 --json $out/run.json --trace $out/trace.json"
    "run --scene data/scenes/bowl-pile.json --spheres 200 --steps 5 --threads 2 --dump-state $out/state.csv"
    "compare implosion --spheres 125 --steps 5 --threads 2 --repeat 1 --json $out/compare.json"
    "accuracy --dt 1/60 --spheres 100 --repeats 1 --no-plot --out $out/accuracy"
    "stress --case light-hit-by-heavy --json $out/stress.json"
    "scale terrain-rain --min 100 --max 200 --threads 2 --steps 3 --no-plot --out $out/scale"
    "query --queries 1000 --repeats 1"
    "pairs --max 256 --repeats 1"
    "bvh-build --max-side 256"
    "rays --sizes 500 --rays 256 --repeats 1"
    "sleep bowl-pile --sizes 200 --steps 40 --every 20 --drop-spheres 0 --no-plot --out $out/sleep"
    "run terrain-rain --spheres 200 --steps 5 --threads 2 --solver soft"
  )
  local c t0
  for c in "${commands[@]}"; do
    t0=$SECONDS
    # shellcheck disable=SC2086  # each entry is a command line of words without spaces inside
    "$bench" $c > "$out/log.txt" 2>&1 || { cat "$out/log.txt"; fail "hail-bench $c"; }
    say "hail-bench $c: ok, $((SECONDS - t0)) s"
  done
}

if [ "$mode" = asan ]; then
  timed "configure + build (hail-tests, hail-bench)" bash -c \
    "cmake --preset asan -DHAIL_SIMD_PATHS='$simd_paths' > /dev/null && cmake --build --preset asan -j $jobs --target hail-tests hail-bench"
  # halt_on_error: the first report of either sanitizer ends the process with an error.
  export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
  # The brute-force comparison tests draw a fifth of their random queries (tests/sample_count.h):
  # the same checks, and the BVH query test no longer takes half the stage (92 s of 179 here).
  export HAIL_TEST_SAMPLE_DIVISOR=${HAIL_TEST_SAMPLE_DIVISOR:-5}
  timed "ctest (every test)" ctest --preset asan -j "$jobs" --no-tests=error --timeout 1200
  timed "hail-bench commands" bench_smoke
  exit 0
fi

# --- tsan: oneTBB with -fsanitize=thread ------------------------------------------------------
need_packages dpkg-dev  # dpkg-source, which apt-get source unpacks with
tbb_root=build/tbb-tsan
tbb_prefix=$PWD/$tbb_root/install
tbb_version=$(dpkg-query -W -f='${source:Version}' libtbb-dev)
tbb_stamp=$tbb_prefix/hail-tsan-build.txt
tbb_want="onetbb $tbb_version, c++ $(c++ -dumpfullversion), -fsanitize=thread RelWithDebInfo"

has_source() {  # (no grep -q on a pipe: with pipefail, the writer's SIGPIPE would count as failure)
  [ "$(apt-cache showsrc onetbb 2>/dev/null | grep -cx "Version: $tbb_version")" -gt 0 ]
}
fetch_tbb_source() {
  if ! has_source; then
    if [ "$(id -u)" -ne 0 ]; then
      fail "apt has no source package onetbb $tbb_version. Add a deb-src line for your Debian mirror, run sudo apt-get update, and run this again."
    fi
    if ! grep -Eqs '^[[:space:]]*Types:.*deb-src' /etc/apt/sources.list.d/*.sources &&
       ! grep -Eqs '^[[:space:]]*deb-src[[:space:]]' /etc/apt/sources.list /etc/apt/sources.list.d/*.list; then
      local codename
      codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")
      say "adding /etc/apt/sources.list.d/hail-debsrc.sources (deb-src, $codename $codename-updates)"
      cat > /etc/apt/sources.list.d/hail-debsrc.sources <<EOF
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: $codename $codename-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    fi
    apt-get update
    has_source || fail "apt still has no source package onetbb $tbb_version after apt-get update"
  fi
  rm -rf "$tbb_root/src"
  mkdir -p "$tbb_root/src"
  (cd "$tbb_root/src" && apt-get source --only-source "onetbb=$tbb_version")
}

build_tbb() {
  fetch_tbb_source
  local src
  src=$(dirname "$(ls "$tbb_root"/src/*/CMakeLists.txt | head -1)")
  [ -f "$src/CMakeLists.txt" ] || fail "no unpacked onetbb source in $tbb_root/src"
  rm -rf "$tbb_root/build" "$tbb_prefix"
  cmake -S "$src" -B "$tbb_root/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_INSTALL_PREFIX="$tbb_prefix" \
    -DCMAKE_INSTALL_LIBDIR=lib -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBB_STRICT=OFF \
    -DTBBMALLOC_BUILD=OFF -DTBB_DISABLE_HWLOC_AUTOMATIC_SEARCH=ON > "$tbb_root/configure.log"
  cmake --build "$tbb_root/build" -j "$jobs" > "$tbb_root/build.log" 2>&1 || { tail -30 "$tbb_root/build.log"; fail "building oneTBB"; }
  cmake --install "$tbb_root/build" > /dev/null
  echo "$tbb_want" > "$tbb_stamp"
}

if [ -f "$tbb_stamp" ] && [ "$(cat "$tbb_stamp")" = "$tbb_want" ] && [ -f "$tbb_prefix/lib/cmake/TBB/TBBConfig.cmake" ]; then
  say "reusing $tbb_root/install ($tbb_want)"
else
  say "building $tbb_want into $tbb_root/install"
  timed "oneTBB download + build" build_tbb
fi
tbb_lib=$(ls "$tbb_prefix"/lib/libtbb.so.[0-9]* | head -1)
case "$(ldd "$tbb_lib")" in *libtsan*) ;; *) fail "$tbb_lib is not built with -fsanitize=thread" ;; esac

# --- tsan: hail against it --------------------------------------------------------------------
timed "configure + build (hail-tests)" bash -c \
  "cmake --preset tsan -DTBB_DIR='$tbb_prefix/lib/cmake/TBB' -DHAIL_SIMD_PATHS='$simd_paths' > /dev/null && cmake --build --preset tsan -j $jobs --target hail-tests"
loaded=$(ldd build/tsan/tests/hail-tests | grep -E 'libtbb\.so' || true)
say "hail-tests loads: ${loaded//$'\t'/}"
case "$loaded" in
  *"=> $tbb_prefix/lib/libtbb.so"*) ;;
  *) fail "build/tsan/tests/hail-tests does not load the instrumented libtbb from $tbb_prefix/lib" ;;
esac

# ASLR with more than 28 random bits (newer kernels' default) breaks GCC 12's ThreadSanitizer
# ("unexpected memory mapping"): run without ASLR there.
run=()
if [ "$(cat /proc/sys/vm/mmap_rnd_bits 2>/dev/null || echo 28)" -gt 28 ]; then run=(setarch "$(uname -m)" -R); fi
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1${TSAN_OPTIONS:+:$TSAN_OPTIONS}"

# Self-check (tests/tsan/tbb_handoff.cpp), against the same libtbb: work handed out and collected
# by parallel_for must give no report, and a planted race must be reported and fail.
check=build/tsan/tbb_handoff
c++ -std=c++20 -O1 -g -fsanitize=thread tests/tsan/tbb_handoff.cpp -I"$tbb_prefix/include" -L"$tbb_prefix/lib" \
  -Wl,-rpath,"$tbb_prefix/lib" -ltbb -o "$check"
"${run[@]}" "$check" > "$check.log" 2>&1 || { cat "$check.log"; fail "ThreadSanitizer reports TBB's own hand-offs (is libtbb instrumented?)"; }
if "${run[@]}" "$check" racy > "$check-racy.log" 2>&1; then
  cat "$check-racy.log"
  fail "ThreadSanitizer missed the planted race in tests/tsan/tbb_handoff.cpp, or it did not fail the run"
fi
case "$(cat "$check-racy.log")" in
  *"WARNING: ThreadSanitizer: data race"*) say "self-check: TBB hand-offs clean, planted race reported" ;;
  *) cat "$check-racy.log"; fail "the planted race failed without a ThreadSanitizer report" ;;
esac

export HAIL_TEST_SAMPLE_DIVISOR=${HAIL_TEST_SAMPLE_DIVISOR:-5}  # as in asan (tests/sample_count.h)
timed "ctest (tests labelled threads)" "${run[@]}" ctest --preset tsan -j "$jobs" --no-tests=error --timeout 1200
