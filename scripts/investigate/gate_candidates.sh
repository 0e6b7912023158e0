#!/usr/bin/env bash
# The elastic gate's early closing, candidates one at a time (docs/VALIDATION.md section 25, issue 37):
#   1. the coupled gate as shipped and with one change each (about 15 s each on 2 cores; the uniform
#      water 80 s), then the RMSE table of scripts/validate/gate_rmse.py, one CSV of every tip history and the figure;
#   2. the gate alone, clamped as in the case, under a uniform traction on its upstream face, damped to
#      rest (about 2 minutes each on 1 core), beside the finite-element gate of scripts/reference/fe_beam.py;
#   3. the finite-element gate under the shipped run's own load history (scripts/reference/fe_gate_history.py);
#   4. the water's load on the gate at three water spacings (scripts/validate/gate_load.py).
#   About two hours on 2 cores, most of it the water at 0.625 mm.
#   bash scripts/investigate/gate_candidates.sh          # OUT=runs/gate_candidates
set -euo pipefail
cd "$(dirname "$0")/../.."
ISPH=${ISPH:-build/isph}
OUT=${OUT:-runs/gate_candidates}
PY=/usr/bin/python3
REF=../shared/reference/antoci_2007_elastic_gate
mkdir -p "$OUT"

coupled() {  # coupled NAME [--set ...]
  local name=$1; shift
  [ -f "$OUT/$name/summary.json" ] || "$ISPH" run cases/elastic_gate.toml --quiet --threads 2 \
    --set output.snapshots=false --out "$OUT/$name" "$@" || echo "$name stopped"
}
# Snapshots every 5 ms (a later --set wins), for the water's load (scripts/validate/gate_load.py).
SNAPSHOTS=(--set output.snapshots=true --set output.snapshot_interval=0.005)
coupled shipped
coupled hourglass_2.5 --set structure.hourglass=2.5
coupled hourglass_10 --set structure.hourglass=10
coupled cell --set 'structure.quadrature="cell"'
coupled quadratic --set 'structure.gradient="quadratic"' --set structure.hourglass=1
coupled gate_fine --set bodies.gate.refinement=4
coupled water_uniform --set dx=0.00125 --set bodies.gate.refinement=1 "${SNAPSHOTS[@]}"
coupled water_0.625 --set dx=0.000625 --set bodies.gate.refinement=1 "${SNAPSHOTS[@]}"   # about 35 minutes
# The finer water with the interface iterated to 1e-2 (the shipped two end far from converged there):
CONVERGED=(--set coupling.max_iterations=30 --set coupling.first_ppe_tolerance=0 --set coupling.tolerance=0.01)
coupled water_uniform_converged --set dx=0.00125 --set bodies.gate.refinement=1 "${CONVERGED[@]}"   # 3 minutes
coupled water_0.625_converged --set dx=0.000625 --set bodies.gate.refinement=1 "${CONVERGED[@]}" \
  --set end_time=0.26   # past the minimum after the peak; about 45 minutes
coupled surface_zero --set 'fluid.surface_pressure="zero"'
coupled ops --set 'fluid.shifting.type="ops"'
coupled converged --set coupling.max_iterations=30 --set coupling.first_ppe_tolerance=0
coupled plane_stress --set 'materials.rubber.plane="stress"'

NAMES=(shipped hourglass_2.5 hourglass_10 cell gate_fine water_uniform water_0.625 surface_zero ops converged plane_stress)
for name in "${NAMES[@]}"; do
  echo "== $name"; $PY scripts/validate/gate_rmse.py "$OUT/$name"
done
$PY - "$OUT" "${NAMES[@]}" > docs/figures/data/gate_candidates_tip.csv <<'PYEOF'
import csv, sys
out, names = sys.argv[1], sys.argv[2:]
print("candidate,time,tip.ux,tip.uy")
for name in names:
    for row in csv.DictReader(open(f"{out}/{name}/probes.csv")):
        print(f"{name},{row['time']},{row['tip.ux']},{row['tip.uy']}")
PYEOF
runs=$(printf "$OUT/%s," "${NAMES[@]}")
$PY scripts/validate/plot.py compare --runs "${runs%,}" --field tip.ux \
  --labels "as shipped,hourglass 2.5,hourglass 10,cell quadrature,gate T/dx = 8,water 1.25 mm,water 0.625 mm,surface p = 0,OPS shifting,converged interface,plane stress" \
  --reference "$REF/ng_2020_elastic_dam_break_x_displacement_khayyer_2018_isph_sph.csv:Khayyer 2018" \
  --reference "$REF/ng_2020_elastic_dam_break_x_displacement_yang_2012_sph_fem.csv:Yang 2012" \
  --out docs/figures/gate_candidates_ux.png
$PY scripts/validate/plot.py compare --field tip.ux \
  --runs "$OUT/shipped,$OUT/water_uniform,$OUT/water_uniform_converged,$OUT/water_0.625,$OUT/water_0.625_converged" \
  --labels "water 2.5 mm (shipped),1.25 mm,1.25 mm converged interface,0.625 mm,0.625 mm converged interface" \
  --reference "$REF/ng_2020_elastic_dam_break_x_displacement_khayyer_2018_isph_sph.csv:Khayyer 2018" \
  --reference "$REF/ng_2020_elastic_dam_break_x_displacement_yang_2012_sph_fem.csv:Yang 2012" \
  --reference "$REF/ng_2020_elastic_dam_break_x_displacement_ng_2020_sph_vcpm_alpha_1.csv:Ng 2020" \
  --out docs/figures/gate_water_spacing_ux.png
$PY scripts/validate/gate_rmse.py --until 0.26 "$OUT/shipped" "$OUT/water_uniform" "$OUT/water_uniform_converged" \
  "$OUT/water_0.625" "$OUT/water_0.625_converged"

dry() {  # dry NAME TRACTION [--set ...]: the gate of cases/elastic_gate.toml without water
  local name=$1 q=$2; shift 2
  local dir="$OUT/dry_${name}_$q"
  [ -f "$dir/summary.json" ] || "$ISPH" run cases/liao_plate_dry.toml --quiet --threads 1 --out "$dir" \
    --set dx=0.00125 --set end_time=0.6 --set structure.damping=60 \
    --set materials.plate.density=1100 --set materials.plate.youngs_modulus=12e6 --set materials.plate.poisson_ratio=0.4 \
    --set 'bodies.plate.shape={type="rectangle",min=[0.1,0.0],max=[0.105,0.16]}' \
    --set 'bodies.plate.clamps=[{type="rectangle",min=[0.1,0.079],max=[0.105,0.16]}]' \
    --set 'loads.0.region={type="rectangle",min=[0.1,0.0],max=[0.1012,0.079]}' --set "loads.0.traction=[$q,0.0]" \
    --set loads.0.ramp_time=0.1 --set 'probes.tip.point=[0.1025,0.0]' "$@"
  $PY -c "import csv,sys; r=list(csv.DictReader(open('$dir/probes.csv')))[-1]; print('$name', $q, 'Pa: deflection', 1e3*float(r['tip.ux']), 'mm, shortening', 1e3*float(r['tip.uy']), 'mm')"
}
for q in 500 1000; do
  $PY scripts/reference/fe_beam.py gate --elements 40 4 --load $q
  dry hg5 $q
  dry hg2.5 $q --set structure.hourglass=2.5
  dry hg10 $q --set structure.hourglass=10
  dry cell $q --set 'structure.quadrature="cell"'
  dry fine $q --set dx=0.000625 --set 'loads.0.region={type="rectangle",min=[0.1,0.0],max=[0.1006,0.079]}'
done

# 3. The finite-element gate under the coupled run's own load: the run as shipped with snapshots every
#    0.5 ms (about 40 s, 1 GB of snapshots), then scripts/reference/fe_gate_history.py on them.
coupled shipped_load --set output.snapshots=true --set output.snapshot_interval=0.0005
load_run="$OUT/shipped_load"
for mesh in "20 2" "40 4"; do
  fe="$OUT/fe_gate_history_${mesh// /x}"
  [ -f "$fe.csv" ] || $PY scripts/reference/fe_gate_history.py "$load_run" --elements $mesh --csv "$fe.csv" --figure "$fe.png" | tee "$fe.txt"
done
cp "$OUT/fe_gate_history_40x4.csv" docs/figures/data/gate_fe_under_coupled_load.csv
cp "$OUT/fe_gate_history_40x4.png" docs/figures/gate_fe_under_coupled_load.png

# 4. The water's load on the gate, its reservoir and the water passed under it, at three water spacings.
$PY scripts/validate/gate_load.py "$load_run" "$OUT/water_uniform" "$OUT/water_0.625" --labels "water 2.5 mm,1.25 mm,0.625 mm" \
  --csv docs/figures/data/gate_load_by_water_spacing.csv --figure docs/figures/gate_load_by_water_spacing.png
