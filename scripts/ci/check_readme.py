#!/usr/bin/python3
"""Checks the figures README.md quotes for the shipped cases against runs of those cases as shipped.

  /usr/bin/python3 scripts/ci/check_readme.py [--runs runs/stability_table] [--readme README.md]

Each claim below names a case, the README's words with the figure (a regular expression whose groups
are the numbers quoted) and how to measure the same figures from the case's run folder:
<runs>/<case>/x1/ (scripts/validate/stability_table.py's run at the shipped settings), or <runs>/<case>/. A figure
agrees when the measured value, rounded as the README rounds it, is the quoted one (half a unit of its
last digit either way). Prints one line per figure: agrees, DIFFERS, not quoted (the README's words
changed) or no run; the exit status is 1 when a figure differs or is no longer quoted.
Figures that depend on the machine (wall times) or on runs other than the shipped case are not checked.
"""
import argparse
import json
import os
import re
import sys

import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from coupled_report import GATE_REFS, WALHORN_REFS, read_reference, rmse_against
from report_common import ROOT, read_probes

REFERENCE = os.path.join(os.path.dirname(ROOT), "shared", "reference")
# The three simulations the README's gate RMSEs name (GATE_REFS' fourth, PySPH's, is not quoted).
GATE = [os.path.join(REFERENCE, "antoci_2007_elastic_gate", f"ng_2020_elastic_dam_break_x_displacement_{row[0]}.csv")
        for row in GATE_REFS[:3]]
WALHORN = [os.path.join(REFERENCE, "walhorn_2005_dam_break_elastic_obstacle",
                        f"sun_2019_dam_breaking_flow_impacting_an_elastic_plate_x_displacement_{row[0]}.csv")
           for row in WALHORN_REFS]


def created(run):
    """The largest fraction of the energy scale created (summary.json's energy books)."""
    with open(os.path.join(run, "summary.json")) as f:
        return [json.load(f)["energy_books"]["peak_created_fraction"]]


def percent_off(probe, reference, scale=1.0, window=None):
    """The probe's last value (or its mean over the time window), times scale, in per cent off
    `reference`."""
    def measure(run):
        d = read_probes(run)
        u = d[probe] if window is None else d[probe][(d["time"] >= window[0]) & (d["time"] <= window[1])]
        value = scale * (u[-1] if window is None else u.mean())
        return [100 * (value - reference) / reference]
    return measure


def tip_peak_mm(run):
    return [1e3 * read_probes(run)["tip.ux"].max()]


def tip_rmse_mm(references, until=np.inf):
    """u_x RMSE of the tip against each reference curve, in mm."""
    def measure(run):
        d = read_probes(run)
        keep = d["time"] <= until
        return [1e3 * rmse_against(d["time"][keep], d["tip.ux"][keep], read_reference(p)) for p in references]
    return measure


def rmse_range(references, until=np.inf):
    """The least and the largest of the tip's u_x RMSEs against the references, in mm."""
    def measure(run):
        rmse = tip_rmse_mm(references, until)(run)
        return [min(rmse), max(rmse)]
    return measure


def gate_uy_rmse_mm(run):
    """u_y RMSE of the tip against each reference with a u_y curve (Khayyer, Yang, Ng), in mm."""
    d = read_probes(run)
    return [1e3 * rmse_against(d["time"], d["tip.uy"], read_reference(path.replace("_x_displacement_", "_y_displacement_")))
            for path in GATE]


def closing_mm(run):
    """The least opening after the peak."""
    ux = read_probes(run)["tip.ux"]
    return [1e3 * ux[np.argmax(ux):].min()]


NUMBER = r"([−+-]?\d+(?:\.\d+)?)"

# (case, what the figure is, README words with the quoted figures, measurement)
CLAIMS = [
    ("cantilever", "tip deflection from the elastica [%]", r"cell quadrature: " + NUMBER + r" % from the elastica",
     percent_off("tip.uy", 30.172e-3, scale=-1.0)),
    ("cantilever_3d", "tip deflection from Timoshenko [%]", r"5 × 5 particles across: " + NUMBER +
     r" % from Timoshenko", percent_off("tip.uz", 0.3435e-3, scale=-1.0)),
    ("dam_break", "energy created / scale", r"completes with " + NUMBER + r" of the energy scale created", created),
    ("hydrostatic_plate", "mean deflection over 0.1-0.5 s from Eq. 53 [%]",
     r"mean deflection over 0\.1-0\.5 s " + NUMBER + r" %",
     percent_off("midspan.uy", 6.86e-5, scale=-1.0, window=(0.1, 0.5))),
    ("elastic_gate", "peak tip u_x [mm]", r"peak tip u_x " + NUMBER + r" mm", tip_peak_mm),
    ("elastic_gate", "u_x and u_y RMSE Khayyer / Yang / Ng [mm]",
     r"u_x RMSE " + NUMBER + " / " + NUMBER + " / " + NUMBER + r" mm and u_y RMSE " + NUMBER + " / " + NUMBER + " / " +
     NUMBER + r" mm against Khayyer / Yang / Ng", lambda run: tip_rmse_mm(GATE)(run) + gate_uy_rmse_mm(run)),
    ("elastic_gate", "least opening after the peak [mm]", r"the gate closes early \(to " + NUMBER + " mm", closing_mm),
    ("baffle_walhorn", "first-swing and whole-run u_x RMSE, least and largest [mm]",
     r"u_x RMSE against the four references " + NUMBER + "-" + NUMBER + r" mm over the first swing and " + NUMBER +
     "-" + NUMBER + " mm over the run",
     lambda run: rmse_range(WALHORN, until=0.283)(run) + rmse_range(WALHORN)(run)),
    ("baffle_walhorn", "peak tip u_x [mm]", r"peak " + NUMBER + r" mm \(references 45\.0-48\.3\)", tip_peak_mm),
]


def as_float(text):
    return float(text.replace("−", "-"))


def agrees(quoted_text, measured):
    """measured, rounded as quoted_text is, equals it."""
    decimals = len(quoted_text.split(".")[1]) if "." in quoted_text else 0
    return abs(measured - as_float(quoted_text)) <= 0.5 * 10 ** -decimals + 1e-12


def run_folder(runs, case):
    for folder in (os.path.join(runs, case, "x1"), os.path.join(runs, case)):
        if os.path.exists(os.path.join(folder, "probes.csv")):
            return folder
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", default=os.path.join(ROOT, "runs", "stability_table"))
    ap.add_argument("--readme", default=os.path.join(ROOT, "README.md"))
    args = ap.parse_args()
    with open(args.readme) as f:
        readme = f.read()
    failed = False
    for case, what, words, measure in CLAIMS:
        match = re.search(words, readme)
        label = f"{case}, {what}"
        if match is None:
            print(f"not quoted  {label}: the README no longer has these words")
            failed = True
            continue
        folder = run_folder(args.runs, case)
        if folder is None:
            print(f"no run      {label}: quoted {', '.join(match.groups())}")
            continue
        measured = measure(folder)
        ok = all(agrees(q, m) for q, m in zip(match.groups(), measured))
        failed |= not ok
        shown = ", ".join(f"{q} (measured {m:.4g})" for q, m in zip(match.groups(), measured))
        print(f"{'agrees    ' if ok else 'DIFFERS   '}  {label}: {shown}  [{folder}]")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
