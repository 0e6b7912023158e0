#!/usr/bin/env bash
# Coupled ISPH-TLSPH validation runs (issue: coupled FSI). On 2 cores, the cases as shipped (structures
# twice as fine as the water): the hydrostatic plate (T/dx = 4) for 1 s about 2 minutes, the elastic gate
# for 0.4 s about half a minute, the Walhorn obstacle as long (and several minutes with OPS shifting, for
# comparison), the rolling tank at T/dx = 2 about
# 7 minutes to 0.6 s and an hour for the whole 4.9 s (and 10 minutes for the tank without its baffle); the plate at
# T/dx = 8, 10 and 12 under the same water (PLATE_FINE=1) an hour or more each, the Liao plate about 10 hours (LIAO=1), the rolling tank as shipped (T/dx = 4) to
# 1.2 s about 1.5 hours (SLOSHING_T4=1), and on to the whole 4.9 s about 4.5 hours more (SLOSHING_T4=1 SLOSHING_T4_FULL=1). The gate's stability variants: scripts/investigate/gate_stability.sh.
# Writes every run under runs/ (OUT) and then the tables and plots of docs/VALIDATION.md:
#   bash scripts/validate/validate_coupled.sh            # the runs, then the report
#   bash scripts/validate/validate_coupled.sh report     # only the report, from existing runs
# Runs already completed are skipped, stopped ones continue from their last snapshot; THREADS sets --threads. The hydrostatic plate's PPE is solved by
# hypre BoomerAMG-BiCGSTAB when the build has it (PLATE_BACKEND; 3.8 times faster than Eigen's ILUT there).
set -euo pipefail
cd "$(dirname "$0")/../.."
THREADS=${THREADS:-1}
source scripts/lib/run_case.sh
mkdir -p "$OUT"
PLATE_BACKEND=${PLATE_BACKEND:-$(grep -q '^HYPRE_LIBRARY:FILEPATH=.*libHYPRE' build/CMakeCache.txt 2>/dev/null && echo hypre || echo eigen)}
PLATE=(--set fluid.ppe.backend=$PLATE_BACKEND --set output.snapshot_interval=0.05)
[ "$PLATE_BACKEND" = eigen ] || PLATE+=(--set fluid.ppe.fallback=eigen)

run() { run_case "$@"; }  # run NAME CASE [--set ...]; a stopped run continues from its last snapshot

if [ "${1:-all}" != "report" ]; then
  run plate_T4 cases/hydrostatic_plate.toml "${PLATE[@]}" &
  run gate_T4 cases/elastic_gate.toml &
  run plate_dry cases/hydrostatic_plate_dry.toml
  wait
  run gate_stress cases/elastic_gate.toml --set end_time=0.12 --set output.snapshot_interval=0.005 &
  # walhorn_ops: the same case with OPS shifting, for the energy figure (it gains energy from 0.55 s)
  { run walhorn cases/baffle_walhorn.toml; run walhorn_ops cases/baffle_walhorn.toml --set fluid.shifting.type=ops --set end_time=0.6; } &
  run sloshing_T2 cases/sloshing_baffle.toml --set dx=0.002 --set end_time=0.6 --set output.snapshot_interval=0.05
  wait
  # The same tank with oil in the baffle's place (its clamp's slot in the floor closed): the energy the oil
  # gains without the baffle (docs/VALIDATION.md section 18).
  /usr/bin/python3 - "$OUT/sloshing_no_baffle.toml" <<'PY'
import os, re, sys
text = open("cases/sloshing_baffle.toml").read().replace('file = "data/', f'file = "{os.path.abspath("cases/data")}/')
text = text.replace("structure = true", "structure = false").replace('name = "sloshing_baffle"', 'name = "sloshing_no_baffle"')
blocks = text.split("[[bodies]]")
keep = [b for b in blocks[1:] if not re.search(r'name = "(oil_left|oil_right|baffle|floor_left|floor_right)"', b)]
motion = re.search(r"motion = .*", blocks[-1]).group(0)
oil = '\nname = "oil"\nkind = "fluid"\nmaterial = "oil"\nshape = { type = "rectangle", min = [0.0, 0.0], max = [0.612, 0.115] }\n\n'
floor = ('\nname = "floor"\nkind = "wall"\nshape = { type = "rectangle", min = [-0.006, -0.006], max = [0.618, 0.0] }\n'
         + motion + "\n\n")
last = keep[-1].split("[[probes]]")[0]  # no baffle, no tip probe
open(sys.argv[1], "w").write("[[bodies]]".join([blocks[0], oil, floor] + keep[:-1] + [last]))
PY
  run sloshing_T2_full cases/sloshing_baffle.toml --set dx=0.002 --set output.snapshot_interval=0.1  # the 4.9 s: about an hour
  for shifting in ops none xu; do  # the case's shifting (OPS), none and Xu/Lind: 2.5-4 minutes each
    run sloshing_no_baffle_T2_$shifting "$OUT/sloshing_no_baffle.toml" --set dx=0.002 --set end_time=0.6 \
      --set fluid.shifting.type=$shifting
  done
  if [ -n "${SLOSHING_T4:-}" ]; then  # its energy books beside T/dx = 2 (docs/VALIDATION.md section 18)
    run sloshing_T4 cases/sloshing_baffle.toml --set end_time=1.2 --set output.snapshot_interval=0.05
    # then the rest of the 4.9 s, from its 1.2 s snapshot (about 4.5 more hours of one core alone; stopped, it
    # continues from its last snapshot the next time)
    if [ -n "${SLOSHING_T4_FULL:-}" ]; then
      if [ -d "$OUT/sloshing_T4_full" ]; then
        run sloshing_T4_full cases/sloshing_baffle.toml --set output.snapshot_interval=0.05
      else
        "$ISPH" run cases/sloshing_baffle.toml --out "$OUT/sloshing_T4_full" --threads "$THREADS" --quiet \
          --restart "$(ls "$OUT"/sloshing_T4/snapshots/snapshot_*.h5 | tail -n 1)" --set output.snapshot_interval=0.05 \
          || [ $? -eq 3 ]
      fi
    fi
  fi
  if [ -n "${PLATE_FINE:-}" ]; then  # the plate finer under the shipped water (1/60 m)
    run plate_T8 cases/hydrostatic_plate.toml --set bodies.plate.dx=0.00625 --set coupling.max_iterations=3 "${PLATE[@]}" &
    run plate_T12 cases/hydrostatic_plate.toml --set bodies.plate.dx=0.004166666666666667 --set coupling.max_iterations=3 "${PLATE[@]}"
    wait
    run plate_T10 cases/hydrostatic_plate.toml --set bodies.plate.dx=0.005 --set coupling.max_iterations=3 "${PLATE[@]}"
  fi
  if [ -n "${LIAO:-}" ]; then  # the Liao plate at dx = 1 mm, 0.6 s: about 2 hours of one core to the impact at 0.24 s, then about 8 (rates measured beside a second run)
    # without structure-wall contact to 0.31 s (the flow lays the plate flat and pushes it through the
    # floor), then continued from its 0.27 s snapshot with the contact (docs/VALIDATION.md section 19)
    run liao cases/baffle_liao.toml --set coupling.wall_contact=false --set end_time=0.31 --set output.snapshot_interval=0.01
    [ -f "$OUT/liao_contact/summary.json" ] || "$ISPH" run cases/baffle_liao.toml --out "$OUT/liao_contact" \
      --threads "$THREADS" --quiet --restart "$OUT/liao/snapshots/snapshot_00027.h5" --set end_time=0.34 \
      --set output.snapshot_interval=0.005
    # the column 0.2 m high of SPHinXsys's example and Zhang et al. 2021 (docs/VALIDATION.md section 19)
    run liao_H02 cases/baffle_liao.toml --set 'bodies.water.shape={type="rectangle", min=[0.0,0.0], max=[0.2,0.2]}' \
      --set output.snapshot_interval=0.01
  fi
fi
/usr/bin/python3 scripts/validate/coupled_report.py --runs "$OUT"
