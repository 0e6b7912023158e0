#!/usr/bin/env bash
# Stability of the coupled step where its variants fail (issue: coupled FSI, case 6): the elastic gate at
# its own resolution (T/dx = 4) to t = 0.06 s, while the gate opens (about 15 minutes per run on one
# core; at T/dx = 2 even the defaults fail within 0.025 s: fluid goes through a gate two particles
# thick; END_TIME and DX override), with
#   reference   the case's defaults: Xu/Lind shifting, no FSI shifting layer (docs/VALIDATION.md section 14), substeps from
#               the structure's stability limit, RK4, interface iterations;
#   fsi_on      the FSI shifting layer on (the default of the case before 2026-12-01);
#   seed_ratio  100 structure substeps per fluid step (the seed's fixed ratio);
#   large_step  1 substep per fluid step (the structure stepped at the fluid's step, beyond its limit);
#   verlet      the second-order structure integrator (velocity-Verlet) instead of RK4;
#   staggered   no interface iterations (coupling.max_iterations = 1).
# Runs go to runs/gate_stability/<variant> (OUT); finished ones are skipped. Then the report:
#   /usr/bin/python3 scripts/coupled_report.py   (the table in docs/VALIDATION.md)
set -euo pipefail
cd "$(dirname "$0")/.."
ISPH=${ISPH:-build/isph}
OUT=${OUT:-runs/gate_stability}
mkdir -p "$OUT"

run() {  # run NAME [--set ...]
  local name=$1; shift
  if [ -f "$OUT/$name/summary.json" ]; then echo "skip $name (done)"; return; fi
  echo "run  $name"
  # a diverged run (exit 3) is a result
  "$ISPH" run cases/elastic_gate.toml --out "$OUT/$name" --threads 1 --quiet --set dx="${DX:-0.00125}" \
    --set end_time="${END_TIME:-0.06}" --set output.snapshots=false "$@" || [ $? -eq 3 ]
}

run large_step --set coupling.substeps=1
run staggered --set coupling.max_iterations=1
run reference
run fsi_on --set coupling.fsi_shifting=true
run verlet --set structure.integrator=verlet
run seed_ratio --set coupling.substeps=100
