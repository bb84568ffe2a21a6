#!/usr/bin/env bash
# The README's headline table: terrain-rain, 4,000 spheres, one thread, hail beside Bullet
# (`hail-bench compare`, engines alternating, REPEAT runs each, default 3). Writes
# docs/results/headline.json (the compare JSON with the date, the commit and the machine added)
# and prints the table as it stands in README.md. Needs a Release hail-bench built with Bullet
# (./scripts/quickstart.sh bench); about 2 minutes on 2 cores; keep the machine otherwise idle.
#
#   ./scripts/headline.sh [REPEAT=3]
set -euo pipefail
cd "$(dirname "$0")/.."
repeat="${1:-3}"
bench=./build/release/bench/hail-bench
[ -x "$bench" ] || { echo "headline.sh: no $bench: run ./scripts/quickstart.sh bench first" >&2; exit 1; }
mkdir -p docs/results
raw=$(mktemp)
trap 'rm -f "$raw"' EXIT
"$bench" compare terrain-rain --spheres 4000 --threads 1 --repeat "$repeat" --json "$raw" >&2
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
dirty=$(git status --porcelain --untracked-files=no 2>/dev/null | head -1)
python3 - "$raw" "$commit${dirty:+ (with uncommitted changes)}" <<'PY'
import json, sys, datetime
raw, commit = sys.argv[1], sys.argv[2]
doc = json.load(open(raw))
doc["date"] = datetime.date.today().isoformat()
doc["commit"] = commit
json.dump(doc, open("docs/results/headline.json", "w"), indent=2)
engines = {e["engine"]: e for e in doc["engines"]}
names = [n for n in ("hail", "Bullet", "Bullet no sleep") if n in engines]
def cell(name, text):
    return f"**{text}**" if name == "hail" else text
print("| terrain-rain, 4,000 spheres, 1 thread | " + " | ".join({"Bullet no sleep": "Bullet, no sleeping"}.get(n, n) for n in names) + " |")
print("|---|" + "---|" * len(names))
row = lambda label, f: print(f"| {label} | " + " | ".join(cell(n, f(engines[n])) for n in names) + " |")
row("ms/step (median over runs of each run's median)",
    lambda e: f"{e['ms_per_step_median']:.2f}" + ("" if e["engine"] == "hail" else f" ({e['ratio_to_hail']:.1f}x)"))
row("max penetration, spheres / ground (m)", lambda e: f"{e['max_sphere_penetration']:.3f} / {e['max_ground_penetration']:.3f}")
row("kinetic energy at 10 s (J)", lambda e: f"{e['kinetic_energy']:,.0f}")
row("tunnelled / fell off / NaN", lambda e: f"{e['tunnelled']} / {e['fell_off']} / {e['nan_spheres']}")
m = doc["machine"]
print(f"\n*Measured at commit {commit} on {doc['date']}, on {m['cpu']}, hail on its {m['simd']} path; "
      f"{doc['bullet']}; docs/results/headline.json.*")
PY
