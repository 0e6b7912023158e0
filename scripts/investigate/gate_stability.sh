#!/usr/bin/env bash
# Stability of the coupled step where its variants fail (issue: coupled FSI, case 6): the elastic gate at
# uniform resolution, water and gate at T/dx = 4 (1.25 mm; the shipped case has the water twice as
# coarse), to t = 0.06 s, while the gate opens (minutes per run on one core; at T/dx = 2 even the
# defaults fail within 0.025 s: fluid goes through a gate two particles thick; END_TIME, DX and
# REFINEMENT override), with
#   reference   the case's defaults: Xu/Lind shifting, no FSI shifting layer (docs/VALIDATION.md section 14), substeps from
#               the structure's stability limit, velocity-Verlet, two interface iterations with the
#               structure's inertia in the PPE (since 2026-12-03; RK4 and converged iterations before);
#   fsi_on      the FSI shifting layer on (the default of the case before 2026-12-01);
#   seed_ratio  100 structure substeps per fluid step (the seed's fixed ratio);
#   large_step  1 substep per fluid step (the structure stepped at the fluid's step, beyond its limit);
#   rk4         RK4 at Courant 0.5 instead of velocity-Verlet at 0.8;
#   staggered   one interface iteration (coupling.max_iterations = 1).
# Runs go to runs/gate_stability/<variant> (OUT); finished ones are skipped. Then the report:
#   /usr/bin/python3 scripts/validate/coupled_report.py   (the table in docs/VALIDATION.md)
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${OUT:-runs/gate_stability}
THREADS=${THREADS:-1}
source scripts/lib/run_case.sh
mkdir -p "$OUT"

run() {  # run NAME [--set ...]
  run_case "$1" elastic_gate --set dx="${DX:-0.00125}" --set bodies.gate.refinement="${REFINEMENT:-1}" \
    --set end_time="${END_TIME:-0.06}" --set output.snapshots=false "${@:2}"
}

run large_step --set coupling.substeps=1
run staggered --set coupling.max_iterations=1
run reference
run fsi_on --set coupling.fsi_shifting=true
run rk4 --set structure.integrator=rk4 --set structure.courant=0.5
run seed_ratio --set coupling.substeps=100
