#!/usr/bin/env bash
# Finds the commit that broke a case: `git bisect run` with this script builds the isph command at each
# commit it visits (no CUDA, no tests, in BUILD) and runs the case as that commit ships it. A run is
# good when it reaches its end_time and its fastest particle (a max_speed probe) stays below MAX_SPEED;
# a commit that does not build is skipped. Each visit appends one line to BUILD/results.txt: status,
# time reached, fastest particle, the largest gain of the total energy up to GAIN_UNTIL [s] (energy.csv,
# so commits without the energy books are judged alike) and the wall time.
#
#   git worktree add /tmp/bisect/wt GOOD && cd /tmp/bisect/wt
#   git bisect start BAD GOOD && git bisect run bash /path/to/scripts/investigate/bisect_case.sh cases/dam_break.toml
#   BUILD (/tmp/bisect/build), THREADS (2), MAX_SPEED (15 m/s), GAIN_UNTIL (0.85 s), SETS (extra --set)
#
# The dam break's bisection of 2026-12-06 (docs/VALIDATION.md section 10) took 7 steps, about 50 min on
# the 2-core VM.
set -u
case_file=${1:?usage: bisect_case.sh CASE.toml}
build=${BUILD:-/tmp/bisect/build}
threads=${THREADS:-2}
commit=$(git rev-parse --short HEAD)
mkdir -p "$build"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DISPH_CUDA=OFF -DISPH_BUILD_TESTS=OFF > "$build/configure.log" 2>&1 || exit 125
cmake --build "$build" -j "$threads" --target isph > "$build/build.log" 2>&1 || exit 125
out="$build/out_$commit"
rm -rf "$out"
start=$(date +%s)
# shellcheck disable=SC2086
"$build/isph" run "$case_file" --out "$out" --threads "$threads" ${SETS:-} > "$out.log" 2>&1
wall=$(($(date +%s) - start))
/usr/bin/python3 - "$out" "$commit" "$wall" "$build/results.txt" "${MAX_SPEED:-15}" "${GAIN_UNTIL:-0.85}" <<'PY'
import csv, json, sys
out, commit, wall, results, max_speed, gain_until = sys.argv[1:]
s = json.load(open(out + "/summary.json"))
probes = list(csv.DictReader(open(out + "/probes.csv")))
speed = [k for k in probes[0] if k.endswith(".u")]
fastest = max((float(r[speed[0]]) for r in probes if r[speed[0]] not in ("", "nan")), default=float("nan"))
energy = list(csv.DictReader(open(out + "/energy.csv")))
first = float(energy[0]["total"])
gain = max(float(r["total"]) - first for r in energy if float(r["time"]) <= float(gain_until))
line = (f"{commit} status={s['status']} t={s['simulated_time']:.4f} fastest={fastest:.2f} "
        f"gain_to_{gain_until}={gain:.3f}J wall={wall}s")
print(line)
open(results, "a").write(line + "\n")
sys.exit(1 if s["status"] != "completed" or not fastest < float(max_speed) else 0)
PY
