#!/usr/bin/env bash
# Structural validation runs (issue: TLSPH structure solver). Long: about an hour on 2 cores.
# Writes every run under runs/validation/ and then the tables and plots of docs/VALIDATION.md:
#   bash scripts/validate_structure.sh            # all runs, then the report
#   bash scripts/validate_structure.sh report     # only the report, from existing runs
# Runs already completed are skipped; SKIP="name ..." skips others; THREADS sets --threads.
set -euo pipefail
cd "$(dirname "$0")/.."
ISPH=${ISPH:-build/isph}
OUT=${OUT:-runs/validation}
THREADS=${THREADS:-1}
mkdir -p "$OUT"

run() {  # run NAME CASE [--set ...]
  local name=$1 case=$2; shift 2
  if [ -f "$OUT/$name/summary.json" ] && grep -q '"completed"' "$OUT/$name/summary.json"; then
    echo "skip $name (done)"; return
  fi
  if [ -n "${SKIP:-}" ] && [[ " $SKIP " == *" $name "* ]]; then
    echo "skip $name (SKIP)"; return
  fi
  echo "run  $name"
  "$ISPH" run "$case" --out "$OUT/$name" --threads "$THREADS" --quiet "$@"
}

if [ "${1:-all}" != "report" ]; then
  # 1. cantilever: 5, 10, 17 particles through the thickness, full (elastica) and 1 % (linear) load
  for n in 5 10 17; do
    dx=$(python3 -c "print(0.01/$n)")
    run "cantilever_N$n" cases/cantilever.toml --set dx=$dx
    run "cantilever_linear_N$n" cases/cantilever.toml --set dx=$dx --set "loads.0.force=[0,-1.75e4]"
  done
  # 2. oscillating plate: T/dx = 10, 20, 40 (T/dx = 40 to PLATE40_END seconds, default 0.7)
  # Courant 1.0 (RK4 is stable to 1.33 here, see the stability study) halves the cost of T/dx = 40
  run op_N10 cases/oscillating_plate.toml --set dx=0.002 --set structure.courant=1.0
  run op_N20 cases/oscillating_plate.toml --set dx=0.001 --set structure.courant=1.0
  run op_N40 cases/oscillating_plate.toml --set dx=0.0005 --set structure.courant=1.0 --set end_time=${PLATE40_END:-0.7} --set output.snapshot_interval=0.1
  # 3. Turek-Hron CSM3: 4 and 8 particles through the thickness
  run csm3_N4 cases/csm3_beam.toml --set dx=0.005
  run csm3_N8 cases/csm3_beam.toml --set dx=0.0025
  # 4. hourglass control: effect of alpha
  for a in 0 1 2 5 10; do
    run "hg${a}_cantilever_linear_N5" cases/cantilever.toml --set dx=0.002 --set "loads.0.force=[0,-1.75e4]" --set structure.hourglass=$a
    run "hg${a}_cantilever_linear_N10" cases/cantilever.toml --set dx=0.001 --set "loads.0.force=[0,-1.75e4]" --set structure.hourglass=$a
    run "hg${a}_op_N10" cases/oscillating_plate.toml --set dx=0.002 --set structure.hourglass=$a --set output.snapshots=false
  done
  # 5. strain-energy quadrature over each particle's cell (section 22), against the runs above
  for n in 5 10 17; do
    dx=$(python3 -c "print(0.01/$n)")
    run "cell_cantilever_N$n" cases/cantilever.toml --set dx=$dx --set structure.quadrature=cell
    run "cell_cantilever_linear_N$n" cases/cantilever.toml --set dx=$dx --set "loads.0.force=[0,-1.75e4]" --set structure.quadrature=cell
  done
  for a in 0 10; do
    run "cell_hg${a}_cantilever_linear_N10" cases/cantilever.toml --set dx=0.001 --set "loads.0.force=[0,-1.75e4]" \
      --set structure.hourglass=$a --set structure.quadrature=cell
  done
  run cell_op_N10 cases/oscillating_plate.toml --set dx=0.002 --set structure.courant=1.0 --set structure.quadrature=cell
fi
/usr/bin/python3 scripts/structure_report.py "$OUT"
