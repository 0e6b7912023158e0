#!/usr/bin/env bash
# The elastic gate's early closing, candidates one at a time (docs/VALIDATION.md section 25, issue 37):
#   1. the coupled gate as shipped and with one change each (about 15 s each on 2 cores; the uniform
#      water 80 s), then the RMSE table of scripts/gate_rmse.py, one CSV of every tip history and the figure;
#   2. the gate alone, clamped as in the case, under a uniform traction on its upstream face, damped to
#      rest (about 2 minutes each on 1 core), beside the finite-element gate of scripts/fe_beam.py.
#   bash scripts/gate_candidates.sh          # OUT=runs/gate_candidates
set -euo pipefail
cd "$(dirname "$0")/.."
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
coupled shipped
coupled hourglass_2.5 --set structure.hourglass=2.5
coupled hourglass_10 --set structure.hourglass=10
coupled cell --set 'structure.quadrature="cell"'
coupled quadratic --set 'structure.gradient="quadratic"' --set structure.hourglass=1
coupled gate_fine --set bodies.gate.refinement=4
coupled water_uniform --set dx=0.00125 --set bodies.gate.refinement=1
coupled surface_zero --set 'fluid.surface_pressure="zero"'
coupled ops --set 'fluid.shifting.type="ops"'
coupled converged --set coupling.max_iterations=30 --set coupling.first_ppe_tolerance=0
coupled plane_stress --set 'materials.rubber.plane="stress"'

NAMES=(shipped hourglass_2.5 hourglass_10 cell gate_fine water_uniform surface_zero ops converged plane_stress)
for name in "${NAMES[@]}"; do
  echo "== $name"; $PY scripts/gate_rmse.py "$OUT/$name"
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
$PY scripts/plot.py compare --runs "${runs%,}" --field tip.ux \
  --labels "as shipped,hourglass 2.5,hourglass 10,cell quadrature,gate T/dx = 8,water 1.25 mm,surface p = 0,OPS shifting,converged interface,plane stress" \
  --reference "$REF/ng_2020_elastic_dam_break_x_displacement_khayyer_2018_isph_sph.csv:Khayyer 2018" \
  --reference "$REF/ng_2020_elastic_dam_break_x_displacement_yang_2012_sph_fem.csv:Yang 2012" \
  --out docs/figures/gate_candidates_ux.png

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
  $PY scripts/fe_beam.py gate --elements 40 4 --load $q
  dry hg5 $q
  dry hg2.5 $q --set structure.hourglass=2.5
  dry hg10 $q --set structure.hourglass=10
  dry cell $q --set 'structure.quadrature="cell"'
  dry fine $q --set dx=0.000625 --set 'loads.0.region={type="rectangle",min=[0.1,0.0],max=[0.1006,0.079]}'
done
