#!/usr/bin/env bash
# hail quick start: installs the Debian packages hail needs (when missing), builds the
# `release` preset, then either runs the main benchmark or the whole test suite.
#
#   ./scripts/quickstart.sh bench   # main benchmark (terrain-rain, 4,000 spheres): speed and error
#   ./scripts/quickstart.sh test    # every test through ctest
#
# As root it runs apt-get itself; otherwise it prints the exact sudo line and stops.
set -euo pipefail
cd "$(dirname "$0")/.."

mode="${1:-bench}"
case "$mode" in bench|test) ;; *) echo "usage: $0 bench|test" >&2; exit 2 ;; esac

packages=(build-essential cmake libtbb-dev libxsimd-dev libeigen3-dev catch2 nlohmann-json3-dev libcli11-dev libstb-dev)
# hail-view (view/) and its headless picture test: GLFW, Dear ImGui (its GLFW and OpenGL3
# backends ship in the package), libepoxy, and Xvfb with xauth and Mesa's software OpenGL.
packages+=(libglfw3-dev libimgui-dev libepoxy-dev xvfb xauth libgl1-mesa-dri)
# The Python module (python/, docs/python.md) and its tests: Debian's pybind11, numpy and pytest
# for /usr/bin/python3; meshio reads the ParaView frames back, matplotlib draws the example's plot.
packages+=(pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-dev)
if [ "$mode" = test ]; then packages+=(python3-meshio python3-matplotlib); fi
# The benchmark side also wants the peers and tools it compares with; the tests never need them.
if [ "$mode" = bench ]; then packages+=(libbullet-dev libbenchmark-dev gnuplot-nox); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ]; then
    echo "quickstart: installing ${missing[*]}"
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
  else
    echo "quickstart: missing Debian packages. Install them with:" >&2
    echo "    sudo apt-get install -y ${missing[*]}" >&2
    echo "then run $0 $mode again." >&2
    exit 1
  fi
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake --preset release
if [ "$mode" = bench ]; then
  # The benchmark needs hail-bench alone: the tests and the viewer are built by `test`.
  cmake --build --preset release -j "$jobs" --target hail-bench
  ./build/release/bench/hail-bench run terrain-rain --spheres 4000
else
  cmake --build --preset release -j "$jobs"
  ctest --preset release -j "$jobs"
fi
