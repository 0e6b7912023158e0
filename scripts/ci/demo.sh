#!/usr/bin/env bash
# Set-up, build, and the main demos, with plots (axes in SI units):
#  1. the elastic gate (Antoci et al. 2007; ISPH-TLSPH, the water at 2.5 mm and the gate twice as
#     fine, the whole 0.4 s, about 13 s on 2 cores): out/elastic_gate/, with the gate tip's
#     displacement against the reference curves (tip_ux.png, tip_uy.png) and a snapshot at the largest
#     opening, the water coloured by pressure and the gate by its vertical stress (snapshot.png);
#  2. the dam break (ISPH, a/dx = 40) up to the impact on the far wall, t = 0.4 s: out/dam_break/, with
#     its surge front against Martin & Moyce's experiments (front.png) and the last pressure field.
# The reference curves are read from ../shared/reference (or ISPH_REFERENCE_DIR); without them the
# plots show the runs alone.
set -euo pipefail
cd "$(dirname "$0")/../.."
bash scripts/ci/build.sh
python=/usr/bin/python3
reference="${ISPH_REFERENCE_DIR:-../shared/reference}"
[ -d "$reference" ] || reference=/work/shared/reference

# The reference curves of one figure, as plot.py --reference options, where the files exist.
references() {
  local option
  for option in "$@"; do
    if [ -f "$reference/${option%%:*}" ]; then printf -- '--reference\n%s\n' "$reference/$option"; fi
  done
}

build/isph run cases/elastic_gate.toml --set output.snapshot_interval=0.01
gate=antoci_2007_elastic_gate/ng_2020_elastic_dam_break
mapfile -t gate_x < <(references "${gate}_x_displacement_khayyer_2018_isph_sph.csv:Khayyer et al. 2018 (ISPH-SPH)" \
                                 "${gate}_x_displacement_yang_2012_sph_fem.csv:Yang et al. 2012 (SPH-FEM)" \
                                 "${gate}_x_displacement_ng_2020_sph_vcpm_alpha_1.csv:Ng et al. 2020 (SPH-VCPM)")
mapfile -t gate_y < <(references "${gate}_y_displacement_khayyer_2018_isph_sph.csv:Khayyer et al. 2018 (ISPH-SPH)" \
                                 "${gate}_y_displacement_yang_2012_sph_fem.csv:Yang et al. 2012 (SPH-FEM)" \
                                 "${gate}_y_displacement_ng_2020_sph_vcpm_alpha_1.csv:Ng et al. 2020 (SPH-VCPM)")
$python scripts/validate/plot.py probes out/elastic_gate --fields tip.ux "${gate_x[@]}" --out out/elastic_gate/tip_ux.png
$python scripts/validate/plot.py probes out/elastic_gate --fields tip.uy "${gate_y[@]}" --out out/elastic_gate/tip_uy.png
$python scripts/validate/plot.py snapshot out/elastic_gate --time 0.11 --field pressure --structure-field sigma_yy \
  --xlim -0.01 0.3 --ylim -0.01 0.17 --out out/elastic_gate/snapshot.png

# Martin & Moyce give x/a against t sqrt(2g/a); for a = 0.146 m, x = 0.146 Z and t = 0.08627 T.
build/isph run cases/dam_break.toml --set end_time=0.4 --set output.snapshot_interval=0.1
mapfile -t front < <(references "dam_break_2d/pysph/pysph_db_exp_data_mm_data_1.txt:Martin & Moyce 1952, a = 1.125 in:0.146:0:0.08627" \
                                "dam_break_2d/pysph/pysph_db_exp_data_mm_data_2.txt:Martin & Moyce 1952, a = 2.25 in:0.146:0:0.08627")
$python scripts/validate/plot.py probes out/dam_break --fields front.x "${front[@]}" --out out/dam_break/front.png
$python scripts/validate/plot.py snapshot out/dam_break --field pressure --out out/dam_break/snapshot.png
echo "demo: results and plots in out/elastic_gate/ and out/dam_break/"
