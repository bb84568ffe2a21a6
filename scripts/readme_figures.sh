#!/usr/bin/env bash
# Re-measures the README's figures: terrain-rain at 1k/4k/16k/64k spheres on 1 and 2 threads
# (full 600 steps each), the terrain query microbenchmark (3 runs) and the BVH build times.
# Needs a release build (./scripts/quickstart.sh bench makes one). Takes about 10 minutes on a
# 2-core machine; keep the machine otherwise idle. Raw outputs and JSON go to $1 (default
# build/figures); a markdown table of terrain-rain is printed at the end (needs python3).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-build/figures}"
bench=./build/release/bench/hail-bench
[ -x "$bench" ] || { echo "no $bench: build the release preset first" >&2; exit 1; }
mkdir -p "$out"
for n in 1000 4000 16000 64000; do
  for t in 1 2; do
    echo "terrain-rain $n spheres, $t threads" >&2
    "$bench" run terrain-rain --spheres "$n" --threads "$t" --json "$out/terrain-rain-$n-$t.json" > "$out/terrain-rain-$n-$t.txt"
  done
done
for r in 1 2 3; do "$bench" query > "$out/query-leaf4-$r.txt"; done
"$bench" query --leaf 8 > "$out/query-leaf8.txt"
"$bench" bvh-build > "$out/bvh-build.txt"
if command -v python3 >/dev/null; then
  python3 - "$out" <<'PY'
import json, sys, glob, os
out = sys.argv[1]
print("| spheres | threads | ms/step mean | median | detect-terrain | detect-pairs | solve | depenetrate | max pen. spheres / ground (m) | tunnelled | fell off | NaN | KE at 10 s (J) | hash |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for n in (1000, 4000, 16000, 64000):
    for t in (1, 2):
        j = json.load(open(os.path.join(out, f"terrain-rain-{n}-{t}.json")))
        p = j["phases_ms"]
        print(f"| {n:,} | {t} | {j['ms_per_step_mean']:.2f} | {j['ms_per_step_median']:.2f} | {p['detect_terrain']:.2f} | "
              f"{p['detect_pairs']:.2f} | {p['solve']:.2f} | {p['depenetrate']:.2f} | "
              f"{j['max_sphere_penetration']:.3f} / {j['max_terrain_penetration']:.3f} | {j['tunnelled']} | {j['fell_off']} | "
              f"{j['nan_count']} | {j['kinetic_energy']:.0f} | {j['state_hash']} |")
PY
fi
grep -h "time / grid" "$out"/query-*.txt
