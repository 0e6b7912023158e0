# Sourced by the validation and investigation scripts: one way to run a point of a study.
#
#   run_case NAME CASE [isph run options ...]
#
# runs `$ISPH run CASE --out $OUT/NAME --threads $THREADS --quiet [options]` (CASE: a path, or the name
# of a file in cases/), unless $OUT/NAME already holds a finished run (its summary.json): a script can be
# stopped and run again, and goes on where it stopped. A run stopped before its end continues from its
# last snapshot (isph run --restart): its folder becomes NAME.partK, and NAME carries the earlier rows
# (report_common.snapshot_list joins the parts). A diverged run (exit 3) is a result, not an error of
# the script; names listed in $SKIP are skipped. Settings: ISPH (build/isph), OUT (runs), THREADS (2).
ISPH=${ISPH:-build/isph}
OUT=${OUT:-runs}
THREADS=${THREADS:-2}

run_case() {
  local name=$1 case=$2
  shift 2
  [ -f "$case" ] || case=cases/$case.toml
  if [ -f "$OUT/$name/summary.json" ]; then
    echo "skip $name (done)"
    return
  fi
  if [ -n "${SKIP:-}" ] && [[ " $SKIP " == *" $name "* ]]; then
    echo "skip $name (SKIP)"
    return
  fi
  local restart=() last
  last=$(ls "$OUT/$name"/snapshots/snapshot_*.h5 2> /dev/null | tail -n 1 || true)
  if [ -n "$last" ]; then
    local k=1
    while [ -e "$OUT/$name.part$k" ]; do k=$((k + 1)); done
    mv "$OUT/$name" "$OUT/$name.part$k"
    restart=(--restart "$OUT/$name.part$k/snapshots/$(basename "$last")")
    echo "run  $name (continuing from $OUT/$name.part$k, $(basename "$last"))"
  else
    echo "run  $name"
  fi
  "$ISPH" run "$case" --out "$OUT/$name" --threads "$THREADS" --quiet "${restart[@]}" "$@" || [ $? -eq 3 ]
}
