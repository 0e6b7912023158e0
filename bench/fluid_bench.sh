#!/usr/bin/env bash
# Fluid-solver benchmark: the dam break (cases/dam_break.toml) scaled to about 10k, 100k and 1M fluid
# particles (dx = a sqrt(2/N)), with walls three particles thick at each dx, on 1 and 2 threads.
# A few steps from rest each (the first steps have the full neighbour count; PPE iterations grow a
# little once the flow develops). Prints fluid particle-steps per second and the share of each phase.
#   bash bench/fluid_bench.sh [SIZES] [THREADS] [BACKEND]     e.g.  bash bench/fluid_bench.sh "1e4 1e5" "1 2" hypre
set -euo pipefail
cd "$(dirname "$0")/.."
ISPH=${ISPH:-build/isph}
SIZES=${1:-"1e4 1e5 1e6"}
THREADS=${2:-"1 2"}
BACKEND=${3:-eigen}
echo "| fluid particles | wall | threads | PPE solver | steps | wall time [s] | particle-steps/s | neighbours | predictor | free surface | assembly | solve | projection | shifting | PPE iterations |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for n in $SIZES; do
  read -r dx steps t wall_set <<<"$(/usr/bin/python3 - "$n" <<'PY'
import math, sys
n = float(sys.argv[1]); a = 0.146
dx = a * math.sqrt(2 / n)
steps = 20 if n < 5e4 else (8 if n < 5e5 else 3)
t = 3 * dx  # walls three particles thick
shapes = {"floor": ([-t, -t], [4 * a + t, 0.0]), "left_wall": ([-t, 0.0], [0.0, 8 * a]),
          "right_wall": ([4 * a, 0.0], [4 * a + t, 8 * a])}
sets = " ".join(f"bodies.{k}.shape={{type=\"rectangle\",min=[{lo[0]:.9g},{lo[1]:.9g}],max=[{hi[0]:.9g},{hi[1]:.9g}]}}"
                for k, (lo, hi) in shapes.items())
# dt = courant h / U_ref at rest: 0.1 * 1.2 dx / sqrt(2 g 2a)
dt = 0.1 * 1.2 * dx / math.sqrt(2 * 9.81 * 2 * a)
print(f"{dx:.9g} {steps} {(steps - 0.5) * dt:.9g} {sets}")
PY
)"
  for th in $THREADS; do
    out=$(mktemp -d)
    args=(--set dx="$dx" --set end_time="$t" --set output.snapshots=false --set fluid.ppe.backend="$BACKEND")
    while read -r s; do args+=(--set "$s"); done < <(/usr/bin/python3 -c "
import re, sys
for m in re.finditer(r'bodies\.[a-z_]+\.shape=\{[^}]*\}', sys.argv[1]): print(m.group(0))" "$wall_set")
    "$ISPH" run cases/dam_break.toml --out "$out" --threads "$th" --quiet "${args[@]}" || true  # a failed run is a row too
    /usr/bin/python3 - "$out/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); ph = s["phases"]; p = s["performance"]
stepping = sum(v for k, v in ph.items() if k not in ("setup", "output"))
share = lambda k: f"{100 * ph.get(k, 0) / stepping:.0f} %"
print(f"| {s['particles']['fluid']} | {s['particles']['wall']} | {p['threads']} | {s['ppe']['solver']} | {s['steps']['fluid']} | "
      f"{stepping:.2f} | {p['fluid_particle_steps_per_s']:.3g}{'' if s['status'] == 'completed' else ' (' + s['status'] + ')'} | " +
      " | ".join(share(k) for k in ("neighbours", "predictor", "free_surface", "ppe_assembly", "ppe_solve", "projection", "shifting")) +
      f" | {s['ppe']['mean_iterations']:.1f} |")
PY
    rm -rf "$out"
  done
done
