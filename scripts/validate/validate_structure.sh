#!/usr/bin/env bash
# Structural validation runs (issue: TLSPH structure solver). Long: about an hour on 2 cores.
# Writes every run under runs/validation/ and then the tables and plots of docs/VALIDATION.md:
#   bash scripts/validate/validate_structure.sh                      # every section's runs, then the report
#   bash scripts/validate/validate_structure.sh cantilever csm3      # only these sections (runs and report)
#   bash scripts/validate/validate_structure.sh report [SECTION...]  # only the report, from existing runs
# Sections: cantilever (1), plate (2), csm3 (3), hourglass (4), quadrature (22).
# Runs already completed are skipped; SKIP="name ..." skips others; THREADS sets --threads.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${OUT:-runs/validation}
THREADS=${THREADS:-1}
source scripts/lib/run_case.sh
mkdir -p "$OUT"

run() { run_case "$@"; }  # run NAME CASE [--set ...]

# The cantilever's earlier discretisations (sections 1, 4, 22): particles at cell centres in x too,
# with the one-point rule or the cell quadrature of the strain energy.
CELL_CENTRED=(--set 'bodies.0.lattice_offset=[0.5,0.5]')
POINT=(--set structure.quadrature=point)
CELL=(--set structure.quadrature=cell)
LINEAR_LOAD=(--set "loads.0.force=[0,-1.75e4]")

cantilever() {  # 1. 5, 10, 17 particles through the thickness, full (elastica) and 1 % (linear) load
  for n in 5 10 17; do
    dx=$(python3 -c "print(0.01/$n)")
    run "cantilever_N$n" cases/cantilever.toml --set dx=$dx
    run "cantilever_linear_N$n" cases/cantilever.toml --set dx=$dx "${LINEAR_LOAD[@]}"
    # what each choice of the case does: the lattice in x, the quadrature
    for variant in cc_point cc_cell node_point; do
      case $variant in
        cc_point) opts=("${CELL_CENTRED[@]}" "${POINT[@]}") ;;
        cc_cell) opts=("${CELL_CENTRED[@]}" "${CELL[@]}") ;;
        node_point) opts=("${POINT[@]}") ;;
      esac
      run "${variant}_cantilever_N$n" cases/cantilever.toml --set dx=$dx "${opts[@]}" --set output.snapshots=false
      run "${variant}_cantilever_linear_N$n" cases/cantilever.toml --set dx=$dx "${LINEAR_LOAD[@]}" "${opts[@]}" \
        --set output.snapshots=false
    done
  done
}

plate() {  # 2. oscillating plate: T/dx = 10, 20, 40 (T/dx = 40 to PLATE40_END seconds, default 0.7)
  # Courant 1.0 (RK4 is stable to 1.33 here, see the stability study) halves the cost of T/dx = 40
  run op_N10 cases/oscillating_plate.toml --set dx=0.002 --set structure.courant=1.0
  run op_N20 cases/oscillating_plate.toml --set dx=0.001 --set structure.courant=1.0
  run op_N40 cases/oscillating_plate.toml --set dx=0.0005 --set structure.courant=1.0 --set end_time=${PLATE40_END:-0.7} --set output.snapshot_interval=0.1
}

csm3() {  # 3. Turek-Hron CSM3: 4 and 8 particles through the thickness
  run csm3_N4 cases/csm3_beam.toml --set dx=0.005
  run csm3_N8 cases/csm3_beam.toml --set dx=0.0025
}

hourglass() {  # 4. hourglass control: effect of alpha (cantilever on cell centres with the one-point rule)
  for a in 0 1 2 5 10; do
    run "hg${a}_cantilever_linear_N5" cases/cantilever.toml --set dx=0.002 "${LINEAR_LOAD[@]}" "${CELL_CENTRED[@]}" "${POINT[@]}" \
      --set structure.hourglass=$a
    run "hg${a}_cantilever_linear_N10" cases/cantilever.toml --set dx=0.001 "${LINEAR_LOAD[@]}" "${CELL_CENTRED[@]}" "${POINT[@]}" \
      --set structure.hourglass=$a
    run "hg${a}_op_N10" cases/oscillating_plate.toml --set dx=0.002 --set structure.hourglass=$a --set output.snapshots=false
  done
}

quadrature() {  # 22. cell quadrature of the strain energy, against the one-point rule (cantilever runs of section 1)
  cantilever
  for a in 0 10; do
    run "cell_hg${a}_cantilever_linear_N10" cases/cantilever.toml --set dx=0.001 "${LINEAR_LOAD[@]}" "${CELL_CENTRED[@]}" "${CELL[@]}" \
      --set structure.hourglass=$a
  done
  run cell_op_N10 cases/oscillating_plate.toml --set dx=0.002 --set structure.courant=1.0 "${CELL[@]}"
}

sections=(cantilever plate csm3 hourglass quadrature)
if [ "${1:-}" = "report" ]; then
  shift
  /usr/bin/python3 scripts/validate/structure_report.py "$OUT" "$@"
  exit
fi
[ $# -gt 0 ] && sections=("$@")
for s in "${sections[@]}"; do
  [[ " cantilever plate csm3 hourglass quadrature " == *" $s "* ]] || { echo "unknown section '$s'" >&2; exit 2; }
  "$s"
done
/usr/bin/python3 scripts/validate/structure_report.py "$OUT" "$@"
