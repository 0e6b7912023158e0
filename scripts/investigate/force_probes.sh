#!/usr/bin/env bash
# The force probes against hydrostatics and the lattice sum of the pairwise force (docs/VALIDATION.md
# section 33; about 5 minutes on 2 cores): the 2D tank at H/dx = 20 with h = 1.0, 1.2 and 1.5 dx and at
# H/dx = 40, the weakly compressible 2D tank, the 3D tank, and the shipped elastic gate with its
# snapshots every 0.5 ms (1 GB) to check the probe's interval means against the step's forces.
#   bash scripts/investigate/force_probes.sh          # OUT=runs/force_probes
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${OUT:-runs/force_probes}
source scripts/lib/run_case.sh
mkdir -p "$OUT"
run() { run_case "$@"; }  # run NAME CASE [--set ...]
coarse=(--set dx=0.05 --set end_time=2 --set output.snapshots=false
        --set 'bodies.floor.shape={type="rectangle",min=[-0.15,-0.15],max=[1.15,0.0]}'
        --set 'bodies.left_wall.shape={type="rectangle",min=[-0.15,0.0],max=[0.0,1.2]}'
        --set 'bodies.right_wall.shape={type="rectangle",min=[1.0,0.0],max=[1.15,1.2]}')
for h in 1.0 1.2 1.5; do run tank_h$h hydrostatic_tank "${coarse[@]}" --set kernel.h_factor=$h; done
run tank_wcsph hydrostatic_tank "${coarse[@]}" --set 'fluid.model="wcsph"'
run tank_dx0.025 hydrostatic_tank --set end_time=2 --set output.snapshots=false
run tank_3d hydrostatic_tank_3d --set end_time=0.6 --set output.snapshots=false
run gate elastic_gate --set output.snapshot_interval=0.0005
/usr/bin/python3 scripts/validate/force_probe_report.py "$OUT"
