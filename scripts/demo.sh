#!/usr/bin/env bash
# Set-up, build, and the main demo: the free oscillating plate (seed 001 §3.1, T/dx = 10, 0.7 s),
# then plots of the tip history, the energies and the stress field in out/oscillating_plate/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/isph run cases/oscillating_plate.toml
/usr/bin/python3 scripts/plot.py probes out/oscillating_plate --fields tip.uy
/usr/bin/python3 scripts/plot.py energy out/oscillating_plate
/usr/bin/python3 scripts/plot.py snapshot out/oscillating_plate --field sigma_xx
echo "demo: results and plots in out/oscillating_plate/"
