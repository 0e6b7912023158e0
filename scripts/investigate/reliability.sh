#!/usr/bin/env bash
# Reproduces every table of docs/RELIABILITY.md, one part after another, with a log per part in OUT_DIR
# (default out/reliability):
#   signals   the signal and restart tests (RunControl.*, CoupledPlate.Restart*), then KILLS (10) runs of
#             the oscillating plate killed with SIGKILL while writing a snapshot at every step, each
#             continued with --restart DIR and checked to complete;
#   schema    the case-schema tests (CaseSchema.*) and the loader's bad-input tests (CaseLoaderTest.*,
#             Bad*), and the refusals of the fuzz corpus counted by kind (FuzzCorpus.*);
#   sanitize  scripts/ci/sanitize.sh (AddressSanitizer, LeakSanitizer, UndefinedBehaviorSanitizer);
#   fuzz      scripts/ci/fuzz.sh FUZZ_SECONDS (default 1800), which adds what it finds to tests/fuzz/;
#   books     scripts/investigate/energy_books.sh (MAPS=1 adds the stability maps).
#   bash scripts/investigate/reliability.sh [PART ...]    # every part by default; OUT_DIR, KILLS, FUZZ_SECONDS, THREADS
# Needs build/ (scripts/ci/build.sh) and, for fuzz, clang. On the 2-core VM: signals and schema a few
# minutes, sanitize about 10, fuzz 30, books 25 (the maps another hour).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${OUT_DIR:-out/reliability}
kills=${KILLS:-10}
parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=(signals schema sanitize fuzz books)
mkdir -p "$out"

signals() {
  build/isph_regression_tests --gtest_brief=1 --gtest_filter='RunControl.*:CoupledPlate.Restart*'
  local run="$out/killed" survived=0
  for k in $(seq 1 "$kills"); do
    rm -rf "$run"
    # a snapshot at every step (0.2 ms); killed after a varying number of them
    build/isph run cases/oscillating_plate.toml --quiet --out "$run" --threads 1 --set end_time=0.05 \
      --set output.snapshot_interval=0.0002 --set output.interval=0.0002 &
    local pid=$!
    sleep "$(awk -v k="$k" 'BEGIN { print 0.8 + 0.13 * k }')"
    kill -9 "$pid" 2> /dev/null || true
    wait "$pid" 2> /dev/null || true
    local whole tmp
    whole=$(find "$run/snapshots" -name 'snapshot_*.h5' | wc -l)
    tmp=$(find "$run" -name '*.tmp' | tr '\n' ' ')
    rm -rf "$run.continued"
    if build/isph run cases/oscillating_plate.toml --quiet --out "$run.continued" --threads 1 --set end_time=0.05 \
      --set output.snapshot_interval=0.0002 --set output.interval=0.0002 --restart "$run" \
      && grep -q '"status": "completed"' "$run.continued/summary.json"; then
      survived=$((survived + 1))
      echo "kill $k: $whole snapshots, left ${tmp:-no .tmp file}; continued to the end"
    else
      echo "kill $k: $whole snapshots, left ${tmp:-no .tmp file}; the restart FAILED"
    fi
  done
  echo "signals: $survived of $kills runs killed with SIGKILL continued to their end"
  [ "$survived" -eq "$kills" ]
}

schema() {
  build/isph_unit_tests --gtest_brief=1 --gtest_filter='CaseSchema.*:CaseLoaderTest.*:ShapeTest.*'
  build/isph_regression_tests --gtest_brief=1 --gtest_filter='Bad*'
  build/isph_unit_tests --gtest_filter='FuzzCorpus.*' | grep -E '^(corpus|\|)'
}

run_part() {
  echo "== $1 (log: $out/$1.log)"
  case "$1" in
    signals) signals ;;
    schema) schema ;;
    sanitize) bash scripts/ci/sanitize.sh ;;
    fuzz) bash scripts/ci/fuzz.sh "${FUZZ_SECONDS:-1800}" ;;
    books) bash scripts/investigate/energy_books.sh "$out/energy_books" ;;
    *) echo "unknown part '$1' (signals, schema, sanitize, fuzz, books)" >&2; return 2 ;;
  esac
}

for part in "${parts[@]}"; do
  run_part "$part" 2>&1 | tee "$out/$part.log"
done
