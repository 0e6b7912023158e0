#!/usr/bin/env bash
# The 3D validation runs that do not fit the test budget (issue 34; docs/VALIDATION.md sections 28-31):
#   1. the still 3D tank and the 3D cantilever as shipped, and the cantilever at 10 x 10 particles;
#   2. SPHERIC Test 2 (cases/dam_break_obstacle_3d.toml) for its 6 s with ISPH at dx = 0.05 and 0.04 m and
#      with the weakly compressible comparator at 0.04 m, and ISPH at 0.03 m over the first impact (0.6 s);
#      the walls three particles thick at each dx;
#   3. the 3D elastic gate (cases/elastic_gate_3d.toml) as shipped (water 2.5 mm, gate 1.25 mm) beside the
#      2D gate at the same spacings in plane strain and plane stress (structure Courant 0.6, as in 3D), and
#      the water-5-mm study of docs/VALIDATION.md section 31 (gate 1.25 and 2.5 mm, 3D and 2D; walls
#      three water particles thick);
#   4. the 3D hydrostatic plate (cases/hydrostatic_plate_3d.toml) and its plate alone
#      (cases/hydrostatic_plate_3d_dry.toml), and the 3D continuum by finite elements (scripts/reference/fe_plate_3d.py);
# then the tables of scripts/validate/dam_break_3d_report.py, scripts/validate/gate_rmse.py and scripts/validate/plate_3d_report.py and
# their figures. About 7 hours on 2 cores.
#   bash scripts/validate/validate_3d.sh          # OUT=runs/validate_3d, THREADS=2
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${OUT:-runs/validate_3d}
source scripts/lib/run_case.sh
PY=/usr/bin/python3
mkdir -p "$OUT"

run() { run_case "$@"; }  # run NAME CASE [--set ...]
walls() {  # walls DX: --set options for SPHERIC Test 2's walls three particles thick at DX
  awk -v dx="$1" 'BEGIN {
    t = 3 * dx; X = 3.22; Y = 1; Z = 1
    printf "--set dx=%g ", dx
    printf "--set bodies.floor.shape={type=\"box\",min=[%g,%g,%g],max=[%g,%g,0]} ", -t, -t, -t, X + t, Y + t
    printf "--set bodies.wall_x0.shape={type=\"box\",min=[%g,0,0],max=[0,%g,%g]} ", -t, Y, Z
    printf "--set bodies.wall_x1.shape={type=\"box\",min=[%g,0,0],max=[%g,%g,%g]} ", X, X + t, Y, Z
    printf "--set bodies.wall_y0.shape={type=\"box\",min=[%g,%g,0],max=[%g,0,%g]} ", -t, -t, X + t, Z
    printf "--set bodies.wall_y1.shape={type=\"box\",min=[%g,%g,0],max=[%g,%g,%g]}\n", -t, Y, X + t, Y + t, Z }'
}
CASE=cases/dam_break_obstacle_3d.toml
NO_SNAPSHOTS=(--set output.snapshots=false)

run tank_3d cases/hydrostatic_tank_3d.toml "${NO_SNAPSHOTS[@]}"
run cantilever_3d cases/cantilever_3d.toml "${NO_SNAPSHOTS[@]}"
run cantilever_3d_dx1mm cases/cantilever_3d.toml --set dx=0.001 "${NO_SNAPSHOTS[@]}"
for dx in 0.05 0.04; do
  read -ra WALLS <<< "$(walls $dx)"
  run "isph_$dx" "$CASE" "${WALLS[@]}" "${NO_SNAPSHOTS[@]}"
done
read -ra WALLS <<< "$(walls 0.04)"
run wcsph_0.04 "$CASE" "${WALLS[@]}" --set 'fluid.model="wcsph"' "${NO_SNAPSHOTS[@]}"
read -ra WALLS <<< "$(walls 0.03)"
run isph_0.03_to_0.6s "$CASE" "${WALLS[@]}" --set end_time=0.6 "${NO_SNAPSHOTS[@]}"

GATE_2D=(cases/elastic_gate.toml --set structure.courant=0.6 "${NO_SNAPSHOTS[@]}")
GATE_3D=(cases/elastic_gate_3d.toml "${NO_SNAPSHOTS[@]}")
run gate_3d "${GATE_3D[@]}"
run gate_2d "${GATE_2D[@]}"
run gate_2d_plane_stress "${GATE_2D[@]}" --set 'materials.rubber.plane="stress"'
WATER_5MM_2D=(--set dx=0.005
  --set 'bodies.floor.shape={type="rectangle",min=[-0.015,-0.015],max=[0.515,0]}'
  --set 'bodies.left_wall.shape={type="rectangle",min=[-0.015,0],max=[0,0.2]}'
  --set 'bodies.right_wall.shape={type="rectangle",min=[0.5,0],max=[0.515,0.2]}')
WATER_5MM_3D=(--set dx=0.005
  --set 'bodies.floor.shape={type="box",min=[-0.015,-0.015,-0.015],max=[0.515,0.065,0]}'
  --set 'bodies.upstream_wall.shape={type="box",min=[-0.015,0,0],max=[0,0.05,0.2]}'
  --set 'bodies.downstream_wall.shape={type="box",min=[0.5,0,0],max=[0.515,0.05,0.2]}'
  --set 'bodies.side_wall_near.shape={type="box",min=[-0.015,-0.015,0],max=[0.515,0,0.2]}'
  --set 'bodies.side_wall_far.shape={type="box",min=[-0.015,0.05,0],max=[0.515,0.065,0.2]}')
for r in 4 2; do  # the gate 1.25 and 2.5 mm under water 5 mm
  run "gate_3d_water_5mm_refinement_$r" "${GATE_3D[@]}" "${WATER_5MM_3D[@]}" --set "bodies.gate.refinement=$r"
  run "gate_2d_water_5mm_refinement_$r" "${GATE_2D[@]}" "${WATER_5MM_2D[@]}" --set "bodies.gate.refinement=$r"
done

run plate_3d cases/hydrostatic_plate_3d.toml "${NO_SNAPSHOTS[@]}"
run plate_3d_dry cases/hydrostatic_plate_3d_dry.toml

echo "== SPHERIC Test 2"
$PY scripts/validate/dam_break_3d_report.py "ISPH 0.05 m=$OUT/isph_0.05" "ISPH 0.04 m=$OUT/isph_0.04" \
  "WCSPH 0.04 m=$OUT/wcsph_0.04" "ISPH 0.03 m (to 0.6 s)=$OUT/isph_0.03_to_0.6s" \
  --figure docs/figures/dam_break_obstacle_3d.png --pareto docs/figures/dam_break_obstacle_3d_pareto.png

echo "== The 3D elastic gate"
$PY scripts/validate/gate_rmse.py "$OUT"/gate_{3d,2d,2d_plane_stress} "$OUT"/gate_{3d,2d}_water_5mm_refinement_{4,2}
$PY scripts/validate/gate_3d_report.py "3D, water 2.5 mm, gate 1.25 mm (as shipped)=$OUT/gate_3d" \
  "2D plane strain, same spacings (the 2D case)=$OUT/gate_2d" "2D plane stress, same spacings=$OUT/gate_2d_plane_stress" \
  "3D, water 5 mm, gate 1.25 mm=$OUT/gate_3d_water_5mm_refinement_4" --figure docs/figures/elastic_gate_3d.png

echo "== The 3D hydrostatic plate"
for elements in "8 1" "12 2" "16 2" "12 4"; do
  # shellcheck disable=SC2086 # two numbers
  $PY scripts/reference/fe_plate_3d.py --elements $elements | grep -E "^elements|continuum"
done
$PY scripts/validate/plate_3d_report.py "$OUT/plate_3d" --dry "$OUT/plate_3d_dry" --figure docs/figures/hydrostatic_plate_3d.png
