#!/usr/bin/env bash
# Set-up, build, and the main demos, with plots:
#  1. the free oscillating plate (TLSPH, seed 001 §3.1, T/dx = 10, 0.7 s): out/oscillating_plate/
#  2. the dam break (ISPH, a/dx = 40) up to the impact on the far wall, t = 0.4 s: out/dam_break/
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/isph run cases/oscillating_plate.toml
/usr/bin/python3 scripts/plot.py probes out/oscillating_plate --fields tip.uy
/usr/bin/python3 scripts/plot.py energy out/oscillating_plate
/usr/bin/python3 scripts/plot.py snapshot out/oscillating_plate --field sigma_xx
build/isph run cases/dam_break.toml --set end_time=0.4 --set output.snapshot_interval=0.1
/usr/bin/python3 scripts/plot.py probes out/dam_break --fields front.x,wall_p.p
/usr/bin/python3 scripts/plot.py snapshot out/dam_break --field pressure
echo "demo: results and plots in out/oscillating_plate/ and out/dam_break/"
