#!/usr/bin/env bash
# ctest view_headless_picture (view/CMakeLists.txt): hail-view --headless (a picture, then an
# image sequence, then one with the debug lines) under Xvfb with Mesa's software OpenGL, each picture judged by
# hail-view-check-png; then the pictures refused or failed (an input overwritten, a full disk).
# Skipped (exit 77) where xvfb-run is not installed (apt-get install xvfb).
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
# The image sequence (--frames DIR --every K): step 0, 120 and 240, each a picture that passes.
frames="$out/frames"
rm -rf "$frames"
LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1024x768x24" \
  "$view" terrain-rain --spheres 1600 --threads 2 --headless --steps 240 --every 120 --frames "$frames" --width 480 --height 270
for k in 0 1 2; do "$check" "$(printf '%s/frame-%06d.png' "$frames" "$k")" 480 270; done
[ ! -e "$frames/frame-000003.png" ] || { echo "view_headless_picture: more pictures than steps 0, 120, 240" >&2; exit 1; }
# The debug lines (--draw-bvh DEPTH, --draw-normals, --draw-grid): the BVH's cyan boxes, the
# normals' yellow and the grid cells' white must each show (terrain-rain's 1,600 spheres use the
# grid search), and the scene still pass.
lines="$out/headless-lines.png"
rm -f "$lines"
LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1024x768x24" \
  "$view" terrain-rain --spheres 1600 --threads 2 --headless --steps 120 --draw-bvh 4 --draw-normals --draw-grid \
  --screenshot "$lines" --width 480 --height 270
"$check" "$lines" 480 270 00ffff:0.2 ffff00:0.05 ffffff:0.05
# A picture over the scene it shows is refused before the run (exit 2, the scene kept); a
# picture that cannot be written (/dev/full: the disk is full) is an error naming it (exit 1),
# never "picture written".
original="$(dirname "$0")/../docs/images/fast-sphere.json"
scene="$out/scene-kept.json"
cp "$original" "$scene"
status=0
LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1024x768x24" \
  "$view" --scene "$scene" --headless --screenshot "$scene" --width 128 --height 128 > "$out/refused.txt" 2>&1 ||
  status=$?
if [ "$status" != 2 ] || ! grep -q "refusing to write $scene" "$out/refused.txt" || ! cmp -s "$original" "$scene"; then
  echo "view_headless_picture: a picture over the scene file was not refused (exit $status):" >&2
  cat "$out/refused.txt" >&2
  exit 1
fi
if [ -e /dev/full ]; then
  status=0
  LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1024x768x24" \
    "$view" terrain-rain --spheres 100 --threads 2 --headless --screenshot /dev/full --width 128 --height 128 \
    > "$out/full.txt" 2>&1 || status=$?
  if [ "$status" != 1 ] || ! grep -q "cannot write /dev/full" "$out/full.txt" || grep -q "picture written" "$out/full.txt"; then
    echo "view_headless_picture: --screenshot /dev/full did not fail naming it (exit $status):" >&2
    cat "$out/full.txt" >&2
    exit 1
  fi
fi
