#!/usr/bin/env bash
# The elastic wedge's water entry (cases/elastic_wedge.toml; docs/VALIDATION.md section 27, issue 37):
#   1. the shipped case (water 6 m x 2.2 m at 10 mm, the aluminium at 5 mm) and at twice the spacings,
#      with ISPH and with the weakly compressible comparator (c = 1500 m/s, water's), ISPH with Xu/Lind
#      shifting at the free surface too, and the panels held at their chines alone;
#   2. the tank's size at 20 mm: 3 m x 1 m (SPHinXsys's), 4 m x 1.6 m and the shipped 6 m x 2.2 m;
#   3. the small tank at 10 and 5 mm, ISPH and WCSPH (the spacing study the shipped tank cannot afford on
#      2 cores);
# then the tables of scripts/validate/wedge_report.py, the figure and the histories as CSV. About 1.5 hours on
# 2 cores, most of it the 5 mm ISPH run.
#   bash scripts/investigate/elastic_wedge.sh          # OUT=runs/elastic_wedge
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${OUT:-runs/elastic_wedge}
source scripts/lib/run_case.sh
PY=/usr/bin/python3
mkdir -p "$OUT"

run() { run_case "$1" elastic_wedge --set output.snapshots=false "${@:2}"; }  # run NAME [--set ...]
tank() {  # tank X0 X1 DEPTH: --set options for water from x0 to x1 and 1 - depth to 1 m, walls 0.06 m thick
  awk -v x0="$1" -v x1="$2" -v d="$3" 'BEGIN {
    y0 = 1 - d; t = 0.06
    printf "--set bodies.water.shape={type=\"rectangle\",min=[%g,%g],max=[%g,1]} ", x0, y0, x1
    printf "--set bodies.floor.shape={type=\"rectangle\",min=[%g,%g],max=[%g,%g]} ", x0 - t, y0 - t, x1 + t, y0
    printf "--set bodies.left_wall.shape={type=\"rectangle\",min=[%g,%g],max=[%g,1.3]} ", x0 - t, y0, x0
    printf "--set bodies.right_wall.shape={type=\"rectangle\",min=[%g,%g],max=[%g,1.3]}\n", x1, y0, x1 + t }'
}
WCSPH=(--set 'fluid.model="wcsph"' --set fluid.wcsph.sound_speed=1500)
read -ra SMALL <<< "$(tank 0 3 1)"
read -ra MIDDLE <<< "$(tank -0.5 3.5 1.6)"
run isph_10mm
run wcsph_10mm "${WCSPH[@]}"
run isph_20mm --set dx=0.02
run wcsph_20mm --set dx=0.02 "${WCSPH[@]}"
run isph_10mm_xu --set 'fluid.shifting.type="xu"'
run isph_10mm_chines_only --set 'bodies.wedge.clamps=[{type="rectangle",min=[0.88,1.0],max=[0.9,1.2]},{type="rectangle",min=[2.1,1.0],max=[2.12,1.2]}]'
run isph_20mm_tank_3x1 --set dx=0.02 "${SMALL[@]}"
run isph_20mm_tank_4x1.6 --set dx=0.02 "${MIDDLE[@]}"
run isph_10mm_tank_3x1 "${SMALL[@]}"
run wcsph_10mm_tank_3x1 "${SMALL[@]}" "${WCSPH[@]}"
run wcsph_5mm_tank_3x1 --set dx=0.005 "${SMALL[@]}" "${WCSPH[@]}"
run isph_5mm_tank_3x1 --set dx=0.005 "${SMALL[@]}"

echo "== the shipped tank"
$PY scripts/validate/wedge_report.py "ISPH 10 mm=$OUT/isph_10mm" "ISPH 20 mm=$OUT/isph_20mm" \
  "WCSPH 10 mm=$OUT/wcsph_10mm" "WCSPH 20 mm=$OUT/wcsph_20mm" \
  "ISPH 10 mm, Xu shifting=$OUT/isph_10mm_xu" "ISPH 10 mm, chines only=$OUT/isph_10mm_chines_only" \
  --csv docs/figures/data/elastic_wedge_histories.csv
$PY scripts/validate/wedge_report.py "ISPH 10 mm (as shipped)=$OUT/isph_10mm" "WCSPH 10 mm=$OUT/wcsph_10mm" \
  "ISPH 10 mm, Xu shifting=$OUT/isph_10mm_xu" "ISPH 10 mm, chines only=$OUT/isph_10mm_chines_only" \
  --figure docs/figures/elastic_wedge.png > /dev/null
echo "== the tank's size (ISPH, 20 mm)"
$PY scripts/validate/wedge_report.py "3 m x 1 m=$OUT/isph_20mm_tank_3x1" "4 m x 1.6 m=$OUT/isph_20mm_tank_4x1.6" \
  "6 m x 2.2 m=$OUT/isph_20mm"
echo "== the small tank at 10 and 5 mm"
$PY scripts/validate/wedge_report.py "ISPH 10 mm=$OUT/isph_10mm_tank_3x1" "ISPH 5 mm=$OUT/isph_5mm_tank_3x1" \
  "WCSPH 10 mm=$OUT/wcsph_10mm_tank_3x1" "WCSPH 5 mm=$OUT/wcsph_5mm_tank_3x1" \
  --figure docs/figures/elastic_wedge_small_tank.png
