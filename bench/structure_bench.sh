#!/usr/bin/env bash
# Structure-solver benchmark: the oscillating plate at T/dx = 20 (4,400 particles), RK4, default
# hourglass control, 1 and 2 threads. Prints structure particle-substeps per second and neighbour
# pair evaluations per second (one pair visit of one neighbour loop; three loops per force
# evaluation with hourglass control, four evaluations per RK4 step).
#   bash bench/structure_bench.sh [END_TIME]
set -euo pipefail
cd "$(dirname "$0")/.."
ISPH=${ISPH:-build/isph}
END=${1:-0.02}
echo "| threads | particles | steps | wall in structure [s] | particle-substeps/s | pair evaluations/s | per core |"
echo "|---|---|---|---|---|---|---|"
for t in 1 2; do
  out=$(mktemp -d)
  "$ISPH" run cases/oscillating_plate.toml --out "$out" --threads "$t" --quiet \
    --set dx=0.001 --set end_time="$END" --set output.snapshots=false
  /usr/bin/python3 - "$out/summary.json" "$t" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); t = int(sys.argv[2]); p = s["performance"]
print(f"| {t} | {s['particles']['structure']} | {s['steps']['structure']} | {s['phases']['structure']:.2f} | "
      f"{p['particle_steps_per_s']:.3g} | {p['pair_evaluations_per_s']:.3g} | {p['pair_evaluations_per_s']/t:.3g} |")
PY
  rm -rf "$out"
done
