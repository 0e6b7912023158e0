#!/usr/bin/env bash
# The seed's FSI shifting layer (Eqs. 27-30), off and with each reading of its Eq. 27
# (coupling.fsi_shifting_law, and our relative law), on the elastic gate, the Walhorn obstacle and the hydrostatic plate to
# 0.5 s (docs/VALIDATION.md section 26; about 5 minutes on 2 cores).
#   bash scripts/investigate/fsi_layer.sh          # OUT=runs/fsi_layer
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${OUT:-runs/fsi_layer}
source scripts/lib/run_case.sh
PY=/usr/bin/python3
mkdir -p "$OUT"
run() { run_case "$1" "$2" --set output.snapshots=false "${@:3}"; }  # run NAME CASE [--set ...]
for layer in off literal derived relative; do
  if [ $layer = off ]; then set_layer=(--set coupling.fsi_shifting=false)
  else set_layer=(--set coupling.fsi_shifting=true --set "coupling.fsi_shifting_law=\"$layer\""); fi
  run gate_$layer elastic_gate "${set_layer[@]}"
  run walhorn_$layer baffle_walhorn "${set_layer[@]}"
  run plate_$layer hydrostatic_plate --set end_time=0.5 "${set_layer[@]}"
done
$PY scripts/validate/gate_rmse.py "$OUT"/gate_off "$OUT"/gate_literal "$OUT"/gate_derived "$OUT"/gate_relative
$PY - "$OUT" <<'PYEOF'
import json, os, sys
sys.path[:0] = ["scripts/validate", "scripts/lib"]
import numpy as np
import study
from coupled_report import WALHORN_REFS, read_reference, rmse_against
from report_common import read_probes
out = sys.argv[1]
reference = os.path.join("..", "shared", "reference", "walhorn_2005_dam_break_elastic_obstacle")
for layer in ("off", "literal", "derived", "relative"):
    gate = json.load(open(f"{out}/gate_{layer}/summary.json"))["performance"]["coupling"]
    print(f"gate, {layer}: closest fluid to the gate {gate['min_fluid_structure_distance'] * 1e3:.2f} mm")
    d = read_probes(f"{out}/walhorn_{layer}")
    t, u = d["time"], d["tip.ux"]
    rows = []
    for key, _, _ in WALHORN_REFS:
        ref = read_reference(os.path.join(reference, f"sun_2019_dam_breaking_flow_impacting_an_elastic_plate_x_displacement_{key}.csv"))
        rows.append(f"{key.split('_')[0]} {rmse_against(t, u, ref[ref[:, 0] <= 0.283]) * 1e3:.2f} / {rmse_against(t, u, ref) * 1e3:.2f}")
    print(f"walhorn, {layer}: peak {u.max() * 1e3:.1f} mm at {t[np.argmax(u)]:.3f} s; RMSE first swing / whole [mm]: " + ", ".join(rows))
    plate = study.plate_deflection(f"{out}/plate_{layer}", None)
    print(f"plate, {layer}: mean deflection {plate['deflection_error_pct']:+.2f} %, pressure noise {plate['pressure_noise'] * 100:.1f} %")
PYEOF
