#!/usr/bin/python3
"""The elastic wedge's water entry (cases/elastic_wedge.toml) against the references in
../shared/reference/zhang_2021_elastic_wedge_water_entry: per run, the mid-panel deflection's RMSE
against each reference curve, the peak pressures at A (keel) and C, and the pressure noise at A.
Optionally a figure of every run against the references and a CSV of the runs' histories.

  /usr/bin/python3 scripts/validate/wedge_report.py LABEL=RUN [LABEL=RUN ...] [--figure PNG] [--csv FILE]

The deflection is the probe's uy less the clamps' rigid motion, uy + V t (V = --speed, 30 m/s). The
references' pressures are in units of 10 MPa (Wagner's keel pressure rho V dc/dt = 8.0 MPa reads
0.80), and so are the pressures printed here.
"""
import argparse
import os
import sys

import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from coupled_report import read_reference, rmse_against
from report_common import ROOT, plt, read_probes, summary, table

REFERENCE = os.path.join(os.path.dirname(ROOT), "shared", "reference", "zhang_2021_elastic_wedge_water_entry")
PREFIX = "zhang_2021_high_speed_water_entry_of_an_elastic_wedge_"
DEFLECTION_REFS = {"analytical": "analytical", "Fourey 2010 SPH-FEM": "fourey_2010_sph_fem",
                   "Li 2015 SPH-FEM": "li_2015_sph_fem"}
PRESSURE_REFS = {"analytical": "analytical", "Khayyer 2018 ISPH-SPH": "khayyer_2018_sph",
                 "Oger 2010 SPH": "oger_2010_sph"}
UNIT = 1e7  # the references' pressure unit [Pa]
NOISE_WINDOW = 1e-4  # [s]: the moving average the noise is measured against
PEAK_WINDOW = 5e-5  # [s]: the moving average whose peak is given beside the raw one
NOISE_SPAN = (2e-4, 1.6e-3)  # [s]: the keel's pressure before the spray root reaches C


def reference(kind, key):
    return read_reference(os.path.join(REFERENCE, f"{PREFIX}{kind}_{key}.csv"))


def moving_average(t, p, window):
    """The centred moving average of p over `window` seconds (fewer samples at the ends), and its half
    width in samples."""
    half = max(1, int(round(0.5 * window / np.median(np.diff(t)))))
    kernel = np.ones(2 * half + 1)
    return np.convolve(p, kernel, mode="same") / np.convolve(np.ones_like(p), kernel, mode="same"), half


def noise(t, p):
    """RMS of p less its centred moving average over NOISE_WINDOW, over NOISE_SPAN, relative to the
    mean of p there."""
    smooth, half = moving_average(t, p, NOISE_WINDOW)
    k = np.arange(len(t))
    inside = (t >= NOISE_SPAN[0]) & (t <= NOISE_SPAN[1]) & (k >= half) & (k < len(t) - half)
    return float(np.sqrt(np.mean((p[inside] - smooth[inside]) ** 2)) / np.mean(p[inside]))


def peak(t, p):
    """'value (at ms)' of the largest p."""
    k = int(np.argmax(p))
    return f"{p[k]:.2f} ({t[k] * 1e3:.2f})"


def mean_keel(t, p):
    """The mean of p over NOISE_SPAN (sampled evenly, so that unevenly digitized curves count alike)."""
    grid = np.linspace(*NOISE_SPAN, 201)
    return float(np.mean(np.interp(grid, t, p)))


def arrival(t, p, level=0.5):
    """The first time p exceeds `level` (the spray root reaching the point)."""
    above = np.nonzero(p > level)[0]
    return float(t[above[0]]) if len(above) else float("nan")


def histories(run, speed):
    d = read_probes(run)
    t = d["time"]
    return t, d["deflection.uy"] + speed * t, d["pressure_A.p"] / UNIT, d["pressure_C.p"] / UNIT


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=RUN_FOLDER")
    ap.add_argument("--speed", type=float, default=30.0, help="the wedge's speed [m/s]")
    ap.add_argument("--figure", help="write the comparison figure here")
    ap.add_argument("--csv", help="write the runs' histories here")
    args = ap.parse_args()
    runs = [r.split("=", 1) for r in args.runs]
    deflection = {name: reference("y_displacement", key) for name, key in DEFLECTION_REFS.items()}
    pressure = {point: {name: reference(f"pressure_point_{point}", key) for name, key in PRESSURE_REFS.items()}
                for point in "AC"}

    header = ["run"] + [f"deflection RMSE {name} [mm]" for name in deflection] + [
        "deflection at 2.2 ms [mm]", "p_A RMSE analytical [10 MPa]", "mean p_A 0.2-1.6 ms [10 MPa]",
        "peak p_A [10 MPa] (at ms)", "peak p_C [10 MPa] (at ms)", "peak p_C, 0.05 ms mean", "p_C > 0.5 from [ms]",
        "noise p_A [%]", "wall [s]"]
    rows = []
    for name, ref in deflection.items():
        at = np.interp(2.2e-3, ref[:, 0], ref[:, 1])
        rows.append([f"reference: {name}"] + ["-"] * len(deflection) + [f"{at * 1e3:.2f}"] + ["-"] * 8)
    for name in PRESSURE_REFS:
        ra, rc = pressure["A"][name], pressure["C"][name]
        rows.append([f"reference: {name}"] + ["-"] * (len(deflection) + 2) + [
            f"{mean_keel(*ra.T):.2f}", peak(*ra.T), peak(*rc.T), "-", f"{arrival(*rc.T) * 1e3:.2f}", "-", "-"])
    series = []
    for label, run in runs:
        t, w, pa, pc = histories(run, args.speed)
        series.append((label, t, w, pa, pc))
        rows.append([label] + [f"{rmse_against(t, w, ref) * 1e3:.2f}" for ref in deflection.values()] + [
            f"{np.interp(2.2e-3, t, w) * 1e3:.2f}", f"{rmse_against(t, pa, pressure['A']['analytical']):.3f}",
            f"{mean_keel(t, pa):.3f}", peak(t, pa), peak(t, pc), peak(t, moving_average(t, pc, PEAK_WINDOW)[0]),
            f"{arrival(t, pc) * 1e3:.2f}", f"{100 * noise(t, pa):.1f}", f"{summary(run)['wall_time_s']:.1f}"])
    table(header, rows)

    if args.figure:
        fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
        panels = [(axes[0], deflection, 2, 1e3, "mid-panel deflection [mm]"),
                  (axes[1], pressure["A"], 3, 1.0, "pressure at A (keel) [10 MPa]"),
                  (axes[2], pressure["C"], 4, 1.0, "pressure at C [10 MPa]")]
        for ax, refs, column, scale, ylabel in panels:
            for (name, ref), marker in zip(refs.items(), "os^"):
                ax.plot(ref[:, 0] * 1e3, ref[:, 1] * scale, marker + "--", ms=3, lw=0.8, label=name)
            for s in series:
                ax.plot(s[1] * 1e3, s[column] * scale, lw=1.2, label=s[0])
            ax.set_xlabel("t [ms]")
            ax.set_ylabel(ylabel)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7)
        axes[1].legend(fontsize=7)
        fig.tight_layout()
        os.makedirs(os.path.dirname(os.path.abspath(args.figure)), exist_ok=True)
        fig.savefig(args.figure, dpi=120)
        print(f"\nfigure: {args.figure}")
    if args.csv:
        with open(args.csv, "w") as f:
            f.write("run,time_s,deflection_m,pressure_A_10MPa,pressure_C_10MPa\n")
            for label, t, w, pa, pc in series:
                for row in zip(t, w, pa, pc):
                    f.write(f"{label}," + ",".join(f"{v:.6g}" for v in row) + "\n")
        print(f"histories: {args.csv}")


if __name__ == "__main__":
    main()
