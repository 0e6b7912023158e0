#!/usr/bin/env bash
# The energy books (docs/RELIABILITY.md, "Energy books"): runs every bundled case as shipped (or to
# END_TIME_CAP seconds where that is shorter), then the two runs known to diverge unseen before the books
# existed (the interpolated plate under a 1 m column, the dam break without shifting), and with MAPS=1
# the two stability maps of docs/STUDIES.md. Prints, per run, how it ended and the largest fraction of
# its energy scale it created, beside the bound at which the books stop a run.
#
#   bash scripts/investigate/energy_books.sh [OUT_DIR [CASE.toml ...]]   # default out/energy_books, every bundled case;
#                                                            # THREADS (2), END_TIME_CAP (none) [s], MAPS (0)
#
# Needs build/isph (scripts/ci/build.sh). The markdown tables go to stdout and OUT_DIR/books.md. On the
# 2-core VM with THREADS=1: the bundled cases about 25 min (sloshing_baffle and baffle_liao capped at
# 0.3 s), the known bad runs 2 min, the maps about an hour.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/energy_books}
shift || true
files=("$@")
[ ${#files[@]} -gt 0 ] || files=(cases/*.toml)
OUT=$out
source scripts/lib/run_case.sh
mkdir -p "$out"
python=/usr/bin/python3

header() {
  {
    echo
    echo "| $1 | simulated [s] | status | peak created fraction | energy scale [J] | bound | wall time [s] | message |"
    echo "|---|---:|---|---:|---:|---:|---:|---|"
  } | tee -a "$out/books.md"
}

# One table row from a run folder's summary.json: $1 the folder, $2 the row's name.
row() {
  $python - "$1/summary.json" "$2" <<'PY' | tee -a "$out/books.md"
import json, sys
try:
    s = json.load(open(sys.argv[1]))
except OSError:
    print(f"| {sys.argv[2]} | | no summary.json | | | | | |")
    sys.exit()
b = s.get("energy_books", {})
message = s.get("message", "").replace("|", "/")[:140] if s["status"] != "completed" else ""
print(f"| {sys.argv[2]} | {s['simulated_time']:.4g} | {s['status']} | {b.get('peak_created_fraction', float('nan')):.3g} | "
      f"{b.get('scale', float('nan')):.4g} | {b.get('created_fraction_bound', float('nan')):g} | {s['wall_time_s']:.1f} | {message} |")
PY
}

run() {  # $1 name, $2 case, the rest: isph run arguments
  run_case "$@" > /dev/null || true
  row "$out/$1" "$1"
}

header "bundled case"
for file in "${files[@]}"; do
  name=$(basename "$file" .toml)
  sets=(--set output.snapshots=false)
  if [ -n "${END_TIME_CAP:-}" ]; then
    end=$($python -c "import tomllib,sys; print(min(tomllib.load(open(sys.argv[1],'rb'))['end_time'], float(sys.argv[2])))" \
      "$file" "$END_TIME_CAP")
    sets+=(--set "end_time=$end")
  fi
  run "$name" "$file" "${sets[@]}"
done

# The runs of tests/regression/test_energy_books.cpp, each beside its healthy twin.
header "known bad run, and its twin"
column=(--set dx=0.0125 --set end_time=0.02 --set output.interval=1e-7 --set output.snapshots=false
  --set 'bodies.water.shape={type="rectangle",min=[0.0,0.0],max=[1.0,1.0]}'
  --set 'bodies.left_wall.shape={type="rectangle",min=[-0.0375,0.0],max=[0.0,1.1]}'
  --set 'bodies.right_wall.shape={type="rectangle",min=[1.0,0.0],max=[1.0375,1.1]}')
for interaction in interpolated held; do
  run "plate_1m_$interaction" cases/hydrostatic_plate.toml "${column[@]}" --set coupling.substep_interaction="$interaction"
done
walls=(--set dx=0.0073 --set end_time=0.4 --set output.snapshot_interval=0.05
  --set 'bodies.floor.shape={type="rectangle",min=[-0.0219,-0.0219],max=[0.6059,0.0]}'
  --set 'bodies.left_wall.shape={type="rectangle",min=[-0.0219,0.0],max=[0.0,2.92]}'
  --set 'bodies.right_wall.shape={type="rectangle",min=[0.584,0.0],max=[0.6059,2.92]}'
  --set 'bodies.floor.lattice_origin=[0.0,0.0]' --set 'bodies.left_wall.lattice_origin=[0.0,0.0]'
  --set 'bodies.right_wall.lattice_origin=[0.0,0.0]')
for shifting in none ops; do
  run "dam_break_a20_$shifting" cases/dam_break.toml "${walls[@]}" --set fluid.shifting.type="$shifting"
done

[ "${MAPS:-0}" = 1 ] || exit 0
for map in stability_dam_break stability_gate; do
  $python scripts/validate/study.py "cases/studies/$map.toml" --out "$out/maps/$map" --threads "$THREADS" >"$out/$map.log" 2>&1 || true
  header "$map point"
  while IFS= read -r summary; do
    dir=$(dirname "$summary")
    row "$dir" "${dir#"$out/maps/$map/"}"
  done < <(find "$out/maps/$map" -name summary.json | sort)
done
