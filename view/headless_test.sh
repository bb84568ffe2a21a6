#!/usr/bin/env bash
# ctest view_headless_picture (view/CMakeLists.txt): hail-view --headless under Xvfb with Mesa's
# software OpenGL, then hail-view-check-png on the picture. Skipped (exit 77) where xvfb-run is
# not installed (apt-get install xvfb).
#   headless_test.sh HAIL_VIEW CHECK_PNG OUT_DIR
set -euo pipefail
view=$1 check=$2 out=$3
if ! command -v xvfb-run > /dev/null; then
  echo "view_headless_picture: SKIPPED: xvfb-run not found (sudo apt-get install xvfb)"
  exit 77
fi
mkdir -p "$out"
picture="$out/headless-terrain-rain.png"
rm -f "$picture"
LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1024x768x24" \
  "$view" terrain-rain --spheres 1600 --threads 2 --headless --steps 240 --screenshot "$picture" --width 480 --height 270
"$check" "$picture" 480 270
