#!/usr/bin/env bash
# Fluid validation runs (issue: ISPH free-surface fluid). About 40 minutes on 2 cores.
# Writes every run under runs/ (OUT) and then the tables and plots of docs/VALIDATION.md:
#   bash scripts/validate/validate_fluid.sh            # all runs, then the report
#   bash scripts/validate/validate_fluid.sh report     # only the report, from existing runs
# Runs already completed are skipped; SKIP="name ..." skips others; THREADS sets --threads;
# BACKEND sets the PPE backend (default hypre when the build has it, else eigen).
set -euo pipefail
cd "$(dirname "$0")/../.."
THREADS=${THREADS:-1}
source scripts/lib/run_case.sh
BACKEND=${BACKEND:-$(grep -q '^HYPRE_LIBRARY:FILEPATH=.*libHYPRE' build/CMakeCache.txt 2>/dev/null && echo hypre || echo eigen)}
mkdir -p "$OUT"

run() { run_case "$1" "$2" --set fluid.ppe.backend="$BACKEND" "${@:3}"; }  # run NAME CASE [--set ...]

if [ "${1:-all}" != "report" ]; then
  # 1. still water, H/dx = 40, 5 s
  run hydrostatic_tank cases/hydrostatic_tank.toml
  # 2. + 4. dam break to t sqrt(g/a) = 8 with the three shifting variants
  for s in ops xu none; do
    run "dam_break_$s" cases/dam_break.toml --set fluid.shifting.type=$s
  done
  # 3. Couette start-up at H/dx = 10, 20, 40 (walls stay 3e-4 m thick: three layers at H/10)
  for n in 10 20 40; do
    run "couette_$n" cases/couette.toml --set dx="$(/usr/bin/python3 -c "print(1e-3/$n)")" \
      --set output.snapshot_interval=0.05
  done
fi
/usr/bin/python3 scripts/validate/fluid_report.py --runs "$OUT"
