#!/usr/bin/env bash
# The two solvers side by side (issue 33; docs/benchmarks.md, "Soft step"): terrain-rain at each
# sphere count and thread count, Solver::Passes and Solver::SoftStep alternating in one sitting
# (passes, soft; then soft, passes on the next repeat), each run's JSON kept. Then a table
# (ms/step, the solve and depenetrate phases, the mean of each step's deepest overlap, spheres
# and ground, the hash) and a gnuplot SVG of nanoseconds per sphere-step and overlap against the
# sphere count.
#
#   ./scripts/solver_sitting.sh [OUT=hail-out/solvers] [SIZES="4000 65536 262144 1000000"] [THREADS="1 2"] [REPEATS=1]
#
# Steps per run: 600 at 4,000 spheres, 300 up to 65,536, 240 above (the 1M run: about 2 minutes
# on two Zen 4 cores per solver, 4 on one). Needs a Release build in build/release, python3 for
# the table and gnuplot for the plot (each skipped with a note when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-hail-out/solvers}" sizes="${2:-4000 65536 262144 1000000}" threads="${3:-1 2}" repeats="${4:-1}"
bench=build/release/bench/hail-bench
[ -x "$bench" ] || { echo "no $bench: build first (cmake --preset release && cmake --build --preset release)" >&2; exit 1; }
mkdir -p "$out"

steps_for() { if [ "$1" -le 4000 ]; then echo 600; elif [ "$1" -le 65536 ]; then echo 300; else echo 240; fi; }

for n in $sizes; do
  for t in $threads; do
    for ((r = 0; r < repeats; ++r)); do
      order="passes soft"
      [ $((r % 2)) -eq 1 ] && order="soft passes"
      for solver in $order; do
        json="$out/terrain-rain-$n-t$t-$solver-r$r.json"
        echo "[$(date +%H:%M:%S)] $n spheres, $t threads, $solver (repeat $((r + 1)) of $repeats)" >&2
        "$bench" run terrain-rain --spheres "$n" --steps "$(steps_for "$n")" --threads "$t" --solver "$solver" \
          --json "$json" > "$out/terrain-rain-$n-t$t-$solver-r$r.txt"
      done
    done
  done
done

command -v python3 > /dev/null || { echo "python3 missing: the runs' JSON is in $out, no table" >&2; exit 0; }
python3 - "$out" << 'EOF'
import glob, json, os, statistics, sys
out = sys.argv[1]
runs = {}
for f in sorted(glob.glob(os.path.join(out, "terrain-rain-*.json"))):
    d = json.load(open(f))
    key = (d["spheres"], d["threads"], "soft" if d["solver"].startswith("soft") else "passes")
    runs.setdefault(key, []).append(d)
machine = next(iter(runs.values()))[0]["machine"]
rows, dat = [], []
print(f"machine: {machine['cpu']}, SIMD path {machine['simd']}")
print("| spheres | threads | solver | ms/step, median of runs (their means) | solve | depenetrate | "
      "mean deepest overlap, spheres / ground (mm) | ns per sphere-step | hash |")
print("|---|---|---|---|---|---|---|---|---|")
for (n, t, solver) in sorted(runs):
    ds = runs[(n, t, solver)]
    med = statistics.median(d["ms_per_step_median"] for d in ds)
    means = ", ".join(f"{d['ms_per_step_mean']:.3f}" for d in ds)
    solve = statistics.median(d["phases_ms"]["solve"] for d in ds)
    dep = statistics.median(d["phases_ms"]["depenetrate"] for d in ds)
    sph = ds[0]["mean_step_sphere_penetration"] * 1e3
    gnd = ds[0]["mean_step_static_penetration"] * 1e3
    ns = med * 1e6 / n
    print(f"| {n:,} | {t} | {solver} | {med:.3f} ({means}) | {solve:.3f} | {dep:.3f} | {sph:.2f} / {gnd:.2f} | "
          f"{ns:.0f} | {ds[0]['state_hash']} |")
    dat.append((solver, t, n, ns, sph, gnd))
with open(os.path.join(out, "solvers.dat"), "w") as f:
    for solver in ("passes", "soft"):
        for t in sorted({d[1] for d in dat}):
            f.write(f"# {solver} {t} thread(s): spheres ns_per_sphere_step deepest_sphere_mm deepest_ground_mm\n")
            for row in sorted(r for r in dat if r[0] == solver and r[1] == t):
                f.write(f"{row[2]} {row[3]:.1f} {row[4]:.3f} {row[5]:.3f}\n")
            f.write("\n\n")
EOF
command -v gnuplot > /dev/null || { echo "gnuplot missing: no plot" >&2; exit 0; }
cp docs/soft_step/solvers.gp "$out/solvers.gp"
(cd "$out" && gnuplot solvers.gp)
echo "table above; plot: $out/solvers.svg" >&2
