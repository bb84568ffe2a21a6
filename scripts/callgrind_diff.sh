#!/usr/bin/env bash
# Instructions inside World::step, function by function, for two hail-bench builds: what a
# change costs a scene, in counts that do not drift (valgrind's callgrind; the AVX2 path, since
# valgrind runs no AVX-512). Only World::step is counted (--toggle-collect), not the bench's own
# checks after each step (the tunnel counter, the energy).
#
#   ./scripts/callgrind_diff.sh BASE_BENCH NEW_BENCH [OUT.csv] -- [hail-bench run arguments]
#   ./scripts/callgrind_diff.sh /tmp/old/hail-bench build/release/bench/hail-bench \
#       docs/results/callgrind_terrain_rain_4k.csv -- terrain-rain --spheres 4000 --threads 1 --steps 300
#
# The run arguments go to both builds; NEW_ARGS="..." adds arguments for the new build alone
# (settings the base did not have: NEW_ARGS="--integrator semi-implicit-euler --sleep off"). The
# CSV (default build/callgrind_diff.csv) has one row per function, largest change first, with
# both totals, and a comment line naming the machine, date, commit and command. Needs valgrind
# and python3; a 4k terrain-rain run of 300 steps takes about 2 minutes per build.
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,15p' "$0" >&2; exit 2; }
base="$1" new="$2"
shift 2
out=build/callgrind_diff.csv
if [ $# -gt 0 ] && [ "$1" != "--" ]; then out="$1"; shift; fi
[ "${1:-}" = "--" ] && shift
run_args=("$@")
[ ${#run_args[@]} -gt 0 ] || run_args=(terrain-rain --spheres 4000 --threads 1 --steps 300)
command -v valgrind > /dev/null || { echo "callgrind_diff.sh: needs valgrind (apt-get install valgrind)" >&2; exit 1; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for which in base new; do
  bench=$base
  extra=()
  if [ "$which" = new ]; then
    bench=$new
    read -r -a extra <<< "${NEW_ARGS:-}"
  fi
  echo "callgrind_diff.sh: $which: $bench run ${run_args[*]} ${extra[*]} --simd avx2" >&2
  valgrind --tool=callgrind --toggle-collect='hail::World::step(float)' --callgrind-out-file="$scratch/$which.out" \
    "$bench" run "${run_args[@]}" "${extra[@]}" --simd avx2 --quiet > "$scratch/$which.txt" 2> "$scratch/$which.err" ||
    { cat "$scratch/$which.err" >&2; exit 1; }
  callgrind_annotate "$scratch/$which.out" > "$scratch/$which.annotated"
done
mkdir -p "$(dirname "$out")"
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')
python3 - "$scratch" "$out" "$cpu" "$(date -u +%F)" "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)" \
  "${run_args[*]} (new: ${NEW_ARGS:-nothing more})" <<'EOF'
import csv, re, sys
scratch, out, cpu, date, commit, args = sys.argv[1:7]

def functions(path):
    """Instructions per function (parameter lists and the avx2 namespace dropped, so that a
    function keeps its name across builds)."""
    counts = {}
    for line in open(path):
        m = re.match(r'^\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)$', line)
        if not m or 'PROGRAM TOTALS' in m.group(2):
            continue
        name = re.sub(r'\s*\[[^\]]*\]$', '', m.group(2))
        name = re.sub(r'^[^:]*:', '', name, count=1)  # the file part, ???: without debug info
        depth, cut = 0, None
        for i, ch in enumerate(name):
            depth += ch == '<'
            depth -= ch == '>'
            if ch == '(' and depth == 0 and i > 0 and name[i - 1] not in ' :':
                cut = i
                break
        name = (name[:cut] if cut else name).replace('simd_avx2::', '').replace('(anonymous namespace)::', '')
        counts[name] = counts.get(name, 0) + int(m.group(1).replace(',', ''))
    return counts

base, new = functions(f'{scratch}/base.annotated'), functions(f'{scratch}/new.annotated')
rows = sorted(set(base) | set(new), key=lambda k: -abs(new.get(k, 0) - base.get(k, 0)))
with open(out, 'w', newline='') as f:
    f.write(f'# callgrind, World::step only, hail-bench run {args} --simd avx2; {cpu}; {date}; commit {commit}\n')
    w = csv.writer(f)
    w.writerow(['function', 'base_instructions', 'new_instructions', 'change'])
    w.writerow(['(total)', sum(base.values()), sum(new.values()), sum(new.values()) - sum(base.values())])
    for k in rows:
        w.writerow([k, base.get(k, 0), new.get(k, 0), new.get(k, 0) - base.get(k, 0)])
tb, tn = sum(base.values()), sum(new.values())
print(f'World::step: base {tb / 1e9:.3f} G, new {tn / 1e9:.3f} G instructions ({100.0 * (tn - tb) / tb:+.1f}%); {out}')
for k in rows[:12]:
    print(f'  {(new.get(k, 0) - base.get(k, 0)) / 1e6:+9.1f} M  {k[:100]}')
EOF
