#!/usr/bin/env bash
# Checks hail as an embedder sees it (docs/embedding.md); exits non-zero on any failure.
#
#   scripts/check_package.sh [--full] [--fetchcontent] [BUILD_DIR]
#
#  1. Builds the `hail` library target in a Release tree: BUILD_DIR if given, else build/release
#     when it is configured (CI has just built it), else build/pkg-check. A tree that is not
#     configured yet is configured as Release, library only (about 2.5 min to build on 2 cores).
#  2. Installs it into a temporary prefix and moves that prefix elsewhere (the package must be
#     relocatable), then checks the installed tree: headers only under include/hail, no sources,
#     every include of an installed header resolves inside the installed tree or a dependency,
#     all headers compile together against the prefix, no hail compile flag (-march, warnings,
#     -ffp-contract) and no build or source path in the exported CMake files, and the version
#     file accepts 0.2 / 0.2.0 and refuses 0.1, 0.3 and 1.0.
#  3. Configures examples/ in a separate tree with find_package(hail CONFIG REQUIRED) against the
#     moved prefix, builds it (its link line must not carry Debian's bogus -lxtl, nor its compile
#     line -march) and runs it on a function heightmap and on data/'s SRTM DEM.
#  4. The add_subdirectory route: examples/ configured with -DHAIL_SOURCE_DIR=<this tree>. hail's
#     tests, benchmark and install rules must default to OFF below it, hail's objects keep their
#     -march, and the example's own file, compiled, gets none. That takes seconds; building hail
#     from source again takes minutes, so linking and running the example this way happens only
#     with --full. --fetchcontent adds the FetchContent route (implies --full).
#
# Temporary trees go to a mktemp directory under ${TMPDIR:-/tmp}, removed at the end unless
# HAIL_CHECK_KEEP=1. Parallel jobs: HAIL_CHECK_JOBS (default: nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
src=$(pwd)

full=0
fetchcontent=0
build=""
for arg in "$@"; do
  case "$arg" in
    --full) full=1 ;;
    --fetchcontent) fetchcontent=1; full=1 ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    -*) echo "check_package: unknown option $arg" >&2; exit 2 ;;
    *) build="$arg" ;;
  esac
done
jobs=${HAIL_CHECK_JOBS:-$(nproc 2>/dev/null || echo 2)}
start=$(date +%s)

step() { echo "check_package [$(($(date +%s) - start)) s]: $*"; }
fail() { echo "check_package: FAILED: $*" >&2; exit 1; }

# --- 1. the library -----------------------------------------------------------------------------
if [ -z "$build" ]; then
  build=build/pkg-check
  [ -f build/release/CMakeCache.txt ] && build=build/release
fi
if [ ! -f "$build/CMakeCache.txt" ]; then
  step "configuring $build (Release, library only)"
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DHAIL_BUILD_TESTS=OFF -DHAIL_BUILD_BENCH=OFF >/dev/null ||
    fail "configuring $build"
fi
step "building target hail in $build"
cmake --build "$build" --target hail -j "$jobs" >/dev/null || fail "building hail in $build"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/hail-pkg.XXXXXX")
if [ "${HAIL_CHECK_KEEP:-0}" = 1 ]; then
  step "keeping $tmp"
else
  trap 'rm -rf "$tmp"' EXIT
fi

# --- 2. install, relocate, inspect --------------------------------------------------------------
step "installing into a temporary prefix, then moving it"
cmake --install "$build" --prefix "$tmp/staged" >/dev/null || fail "cmake --install $build"
mv "$tmp/staged" "$tmp/prefix"
prefix=$tmp/prefix
cmakedir=$(dirname "$(find "$prefix" -name hailConfig.cmake -print -quit)")
[ -f "$cmakedir/hailConfig.cmake" ] ||
  fail "no hailConfig.cmake installed (was $build configured with -DHAIL_INSTALL=OFF?)"
for f in hailConfigVersion.cmake hailTargets.cmake; do
  [ -f "$cmakedir/$f" ] || fail "$f not installed"
done
inc=$prefix/include
[ -f "$inc/hail/hail.h" ] && [ -f "$inc/hail/version.h" ] || fail "hail/hail.h or hail/version.h not installed"
[ -f "$prefix/share/doc/hail/LICENSE" ] || fail "LICENSE not installed"

stray=$(find "$prefix" -type f \( -name '*.cpp' -o -name '*.cc' -o -name 'CMakeLists.txt' \) | sed "s|$prefix/||")
[ -z "$stray" ] || fail "sources installed: $stray"
stray=$(find "$inc" -mindepth 1 -maxdepth 1 ! -name hail | sed "s|$prefix/||")
[ -z "$stray" ] || fail "installed outside include/hail: $stray"

# Every include of hail's own must be an installed public header, written "hail/<name>.h" or
# <hail/<name>.h> (the only include directory a consumer gets is <prefix>/include); none may
# name the library's internal folders.
missing=""
while IFS= read -r header; do
  while IFS= read -r included; do
    case "$included" in
      \"*|\<hail/*|\<kernel/*|\<soa/*|\<jobs/*)
           name=${included#[<\"]}; name=${name%[>\"]}
           [ -f "$inc/$name" ] && [[ "$name" == hail/* ]] ||
             missing+="  ${header#"$inc"/} includes $included"$'\n' ;;
    esac
  done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*\([<"][^>"]*[>"]\).*/\1/p' "$header")
done < <(find "$inc" -name '*.h' | sort)
[ -z "$missing" ] || fail "installed headers include files that are not installed:"$'\n'"$missing"
header_count=$(find "$inc" -name '*.h' | wc -l)

hail_flags='-march|-mavx|-W(all|extra)|ffp-contract'
if grep -rqE -- "$hail_flags" "$cmakedir"; then
  fail "the exported CMake files pass hail's compile flags on: $(grep -rlE -- "$hail_flags" "$cmakedir")"
fi
if grep -rqF -e "$src" -e "$tmp/staged" "$cmakedir"; then
  fail "the exported CMake files name the source tree or the install prefix (not relocatable)"
fi

# A consumer of every installed header, and the version rules.
mkdir -p "$tmp/headers"
{
  echo 'cmake_minimum_required(VERSION 3.25)'
  echo 'project(hail_headers LANGUAGES CXX)'
  echo 'find_package(hail ${REQUEST} CONFIG REQUIRED)'
  echo 'add_library(all_headers OBJECT all_headers.cpp)'
  echo 'target_link_libraries(all_headers PRIVATE hail::hail)'
} > "$tmp/headers/CMakeLists.txt"
(cd "$inc/hail" && find . -name '*.h' | sort | sed 's|^\./|#include <hail/|; s|$|>|') > "$tmp/headers/all_headers.cpp"
echo '#include <hail/hail.h>' >> "$tmp/headers/all_headers.cpp"
step "compiling all $header_count installed headers in one file against the moved prefix"
cmake -S "$tmp/headers" -B "$tmp/headers/build" -DCMAKE_PREFIX_PATH="$prefix" -DREQUEST=0.2 >/dev/null ||
  fail "find_package(hail 0.2) failed"
cmake --build "$tmp/headers/build" >/dev/null || fail "the installed headers do not compile on their own"
for request in "0.2.0;EXACT" 0.1 0.3 1.0; do
  if cmake -S "$tmp/headers" -B "$tmp/headers/v" -DCMAKE_PREFIX_PATH="$prefix" "-DREQUEST=$request" \
      >/dev/null 2>&1; then
    [ "$request" = "0.2.0;EXACT" ] || fail "find_package(hail $request) accepted version 0.2.x"
  else
    [ "$request" != "0.2.0;EXACT" ] || fail "find_package(hail 0.2.0 EXACT) refused"
  fi
  rm -rf "$tmp/headers/v"
done

# --- 3. examples/ against the installed package -------------------------------------------------
# Runs the example and checks what the tree's compile commands say about flags.
check_example_flags() {  # <example build dir> <route>
  local dir=$1 route=$2 cmd file
  for file in drop_spheres paddle_game; do
    cmd=$(grep "\"command\".*$file\\.cpp" "$dir/compile_commands.json") || fail "$route: no compile command for $file.cpp"
    if grep -qE -- '-march|-ffp-contract|-Wall|-Wextra' <<<"$cmd"; then
      fail "$route: the example was compiled with hail's flags: $cmd"
    fi
    # It sees the public headers only: hail's source root (kernel/, soa/, jobs/) is not on its path.
    if grep -qE -- "-I$src( |\"|$)|-isystem $src( |\"|$)" <<<"$cmd"; then
      fail "$route: the example sees hail's internal folders (-I$src): $cmd"
    fi
  done
}
check_example() {  # <example build dir> <route>
  local dir=$1 route=$2
  check_example_flags "$dir" "$route"
  if grep -rqE -- '(^| )(-lxtl|xtl)( |$)' "$dir"/CMakeFiles/hail-{example,game}.dir/link.txt; then
    fail "$route: the example links xtl (the xsimd fix-up is missing)"
  fi
  step "$route: running hail-example (function heightmap)"
  "$dir/hail-example" > "$dir/run.log" || { cat "$dir/run.log"; fail "$route: hail-example failed"; }
  tail -3 "$dir/run.log" | sed 's/^/    /'
  step "$route: running hail-game (kinematic paddle, filters, ray picks, events, rollback)"
  "$dir/hail-game" > "$dir/game.log" || { cat "$dir/game.log"; fail "$route: hail-game failed"; }
  tail -5 "$dir/game.log" | sed 's/^/    /'
}

step "package: configuring examples/ with find_package(hail CONFIG REQUIRED)"
cmake -G "Unix Makefiles" -S examples -B "$tmp/example-package" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >"$tmp/example-package.log" ||
  { cat "$tmp/example-package.log"; fail "package: configuring the example"; }
cmake --build "$tmp/example-package" -j "$jobs" >/dev/null || fail "package: building the example"
check_example "$tmp/example-package" package
step "package: running hail-example on data/jacksboro_srtm3_403x344.pgm"
"$tmp/example-package/hail-example" data/jacksboro_srtm3_403x344.pgm > "$tmp/example-package/dem.log" ||
  { cat "$tmp/example-package/dem.log"; fail "package: hail-example on the DEM failed"; }
tail -2 "$tmp/example-package/dem.log" | sed 's/^/    /'
version=$(sed -n 's/^hail \([0-9.]*\) example$/\1/p' "$tmp/example-package/run.log")
project_version=$(sed -n 's/^project(hail VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
[ "$version" = "$project_version" ] || fail "hail/version.h says $version, project() says $project_version"

# --- 4. examples/ with hail's source tree below it ----------------------------------------------
routes=(subdirectory)
[ "$fetchcontent" = 1 ] && routes+=(fetchcontent)
for route in "${routes[@]}"; do
  dir=$tmp/example-$route
  step "$route: configuring examples/ with -DHAIL_SOURCE_DIR=$src"
  cmake -G "Unix Makefiles" -S examples -B "$dir" -DCMAKE_BUILD_TYPE=Release -DHAIL_SOURCE_DIR="$src" \
    -DHAIL_EMBED="$route" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >"$dir.log" ||
    { cat "$dir.log"; fail "$route: configuring the example"; }
  for option in HAIL_BUILD_TESTS HAIL_BUILD_BENCH HAIL_INSTALL; do
    grep -q "^$option:BOOL=OFF" "$dir/CMakeCache.txt" || fail "$route: $option is not OFF below a parent project"
  done
  grep -q '"command".*-march=.*kernel/world/world\.cpp' "$dir/compile_commands.json" ||
    fail "$route: hail's own objects lost their -march flag"
  if [ "$full" = 1 ]; then
    step "$route: building hail from source and the example"
    cmake --build "$dir" -j "$jobs" >/dev/null || fail "$route: building the example"
    check_example "$dir" "$route"
  else
    step "$route: compiling the example's own file (--full also builds hail this way and runs it)"
    for file in drop_spheres paddle_game; do
      cmake --build "$dir" --target $file.cpp.o >/dev/null || fail "$route: compiling the example $file.cpp"
    done
    check_example_flags "$dir" "$route"
  fi
done

step "OK: $header_count headers; package and ${routes[*]} routes"
