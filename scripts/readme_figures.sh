#!/usr/bin/env bash
# Re-measures the figures of docs/benchmarks.md: terrain-rain at 1k/4k/16k/64k spheres on 1 and 2 threads,
# and at 4k/64k on 1 thread with the AVX2 path forced (what the users' AVX2-only CPUs run; only
# where this CPU has AVX2) (full 600 steps each, REPEATS rounds, default 3: each round runs every row once, so a slow
# spell of a shared machine spreads over the rows instead of hitting one), the terrain query
# microbenchmark (3 runs at leaf size 8, one at 4) and the BVH build times. Needs a release build
# (./scripts/quickstart.sh bench makes one). Takes about 4 minutes on a 2-core machine; keep
# the machine otherwise idle. Raw outputs and JSON go to $1 (default build/figures); a markdown
# table of terrain-rain is printed at the end and written to docs/results/terrain_rain.csv (needs
# python3): per row the median over the rounds of the mean ms/step, its range, and the median
# phase times, with the machine, date and commit.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-build/figures}"
bench=./build/release/bench/hail-bench
[ -x "$bench" ] || { echo "no $bench: build the release preset first" >&2; exit 1; }
mkdir -p "$out"
repeats="${REPEATS:-3}"
avx2=0
grep -qw avx2 /proc/cpuinfo 2>/dev/null && avx2=1
for r in $(seq "$repeats"); do
  for n in 1000 4000 16000 64000; do
    for t in 1 2; do
      echo "round $r/$repeats: terrain-rain $n spheres, $t threads" >&2
      "$bench" run terrain-rain --spheres "$n" --threads "$t" --json "$out/terrain-rain-$n-$t-$r.json" > "$out/terrain-rain-$n-$t-$r.txt"
    done
    if [ "$avx2" = 1 ] && { [ "$n" = 4000 ] || [ "$n" = 64000 ]; }; then
      echo "round $r/$repeats: terrain-rain $n spheres, 1 thread, AVX2 path" >&2
      "$bench" run terrain-rain --spheres "$n" --threads 1 --simd avx2 --json "$out/terrain-rain-$n-1avx2-$r.json" > "$out/terrain-rain-$n-1avx2-$r.txt"
    fi
  done
done
# The query table: the terrain's default leaf size (8), three runs, and leaf size 4 once; on
# the AVX2 path where the CPU has it (what the users' CPUs run), else the active one.
query_path=()
[ "$avx2" = 1 ] && query_path=(--simd avx2)
for r in 1 2 3; do "$bench" query "${query_path[@]}" > "$out/query-leaf8-$r.txt"; done
"$bench" query "${query_path[@]}" --leaf 4 > "$out/query-leaf4.txt"
"$bench" bvh-build > "$out/bvh-build.txt"
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
dirty=$(git status --porcelain --untracked-files=no 2>/dev/null | head -1)
if command -v python3 >/dev/null; then
  mkdir -p docs/results
  python3 - "$out" "$repeats" "$commit${dirty:+ (with uncommitted changes)}" <<'PY'
import csv, datetime, json, sys, os, statistics
out, repeats, commit = sys.argv[1], int(sys.argv[2]), sys.argv[3]
# docs/results/terrain_rain.csv: one row per count and threads, with the machine, date and commit.
rows = []
print("| spheres | threads | ms/step mean (median of rounds) | range | detect-terrain | detect-pairs | solve | sweep | depenetrate | max pen. spheres / ground (m) | tunnelled | fell off | NaN | KE at 10 s (J) | hash |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for n in (1000, 4000, 16000, 64000):
    for t in ("1", "2", "1avx2"):
        paths = [os.path.join(out, f"terrain-rain-{n}-{t}-{r}.json") for r in range(1, repeats + 1)]
        if not all(os.path.exists(p) for p in paths):
            continue  # the AVX2 rows: only 4k and 64k, only where the CPU has AVX2
        runs = [json.load(open(p)) for p in paths]
        hashes = {j["state_hash"] for j in runs}
        means = [j["ms_per_step_mean"] for j in runs]
        phase = lambda name: statistics.median(j["phases_ms"][name] for j in runs)
        j = runs[0]  # the error figures do not depend on the run (the same hash)
        label = "1 (AVX2 path)" if t == "1avx2" else t
        rows.append({"spheres": n, "threads": t[0], "simd": j["machine"]["simd"], "cpu": j["machine"]["cpu"],
                     "rounds": repeats, "ms_per_step_mean_median": round(statistics.median(means), 4),
                     "ms_per_step_mean_min": round(min(means), 4), "ms_per_step_mean_max": round(max(means), 4),
                     **{f"{name}_ms": round(phase(name), 4) for name in ("detect_terrain", "detect_pairs", "solve", "sweep", "depenetrate")},
                     "max_sphere_penetration_m": j["max_sphere_penetration"], "max_terrain_penetration_m": j["max_terrain_penetration"],
                     "tunnelled": j["tunnelled"], "fell_off": j["fell_off"], "nan_count": j["nan_count"],
                     "kinetic_energy_j": round(j["kinetic_energy"], 1), "state_hash": "/".join(sorted(hashes)),
                     "date": datetime.date.today().isoformat(), "commit": commit})
        print(f"| {n:,} | {label} | {statistics.median(means):.2f} | {min(means):.2f}-{max(means):.2f} | {phase('detect_terrain'):.2f} | "
              f"{phase('detect_pairs'):.2f} | {phase('solve'):.2f} | {phase('sweep'):.2f} | {phase('depenetrate'):.2f} | "
              f"{j['max_sphere_penetration']:.3f} / {j['max_terrain_penetration']:.3f} | {j['tunnelled']} | {j['fell_off']:,} | "
              f"{j['nan_count']} | {j['kinetic_energy']:,.0f} | {'/'.join(sorted(hashes))} |")
with open("docs/results/terrain_rain.csv", "w", newline="") as f:
    writer = csv.DictWriter(f, fieldnames=list(rows[0]))
    writer.writeheader()
    writer.writerows(rows)
print("written: docs/results/terrain_rain.csv")
PY
fi
grep -h "time / grid" "$out"/query-*.txt
