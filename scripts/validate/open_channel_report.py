#!/usr/bin/python3
"""The open channel (cases/poiseuille_channel.toml, docs/VALIDATION.md "Open channel"): per run, the
fluid particles' u_x between x = 0.5 m and the outlet's plane against plane Poiseuille flow (largest and
RMS deviation, in per cent of the peak), the pressure gradient between the two pressure probes against
-12 rho nu U / H^2, the particles in against the profile's flow, and the wall time. Optionally a figure
of the profiles.

  /usr/bin/python3 scripts/validate/open_channel_report.py LABEL=RUN [LABEL=RUN ...] [--figure PNG]

The runs: `isph run cases/poiseuille_channel.toml --out RUN` (H/20), and at H/40 with
`--set dx=0.005 --set 'bodies.oil.shape={type="rectangle",min=[-0.02,0.0],max=[0.62,0.2]}'`.
"""
import argparse
import os
import sys

import numpy as np

sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib")]
from report_common import plt, read_probes, read_snapshot, snapshot_list, summary, table

H, U, RHO, NU = 0.2, 0.1, 1000.0, 0.01
STATION = (0.5, 0.6)  # x range before the outlet's plane
PROBES = (0.05, 0.55)  # x of p_inlet and p_outlet


def poiseuille(y):
    return 1.5 * U * 4 * y * (H - y) / H**2


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", help="LABEL=RUN")
    parser.add_argument("--figure", help="write the profiles here (PNG)")
    args = parser.parse_args()
    rows, curves = [], []
    for spec in args.runs:
        label, run = spec.split("=", 1)
        snap = read_snapshot(snapshot_list(run)[-1][1])
        x, u, kind = snap["position"], snap["velocity"], snap["kind"].ravel()
        near = (kind == 0) & (x[:, 0] >= STATION[0]) & (x[:, 0] <= STATION[1])
        err = (u[near, 0] - poiseuille(x[near, 1])) / poiseuille(H / 2)
        probes = read_probes(run)
        gradient = (probes["p_inlet.p"][-1] - probes["p_outlet.p"][-1]) / (PROBES[1] - PROBES[0])
        s = summary(run)
        b = s["particles"]["open_boundaries"]
        rows.append([label, f"{100 * np.abs(err).max():.2f}", f"{100 * np.sqrt(np.mean(err**2)):.2f}",
                     f"{gradient:.1f} ({100 * (gradient / (12 * RHO * NU * U / H**2) - 1):+.1f} %)",
                     f"{b['mass_in']:.2f} / {b['inlet']['mass_prescribed']:.2f}", f"{b['mass_balance']:.1e}",
                     f"{s['wall_time_s']:.0f}"])
        curves.append((label, x[near, 1], u[near, 0]))
    table(["run", "max dev. [% of peak]", "RMS dev. [%]", "-dp/dx [Pa/m] (vs 300)", "mass in / prescribed [kg]",
           "mass balance", "wall [s]"], rows)
    if args.figure:
        fig, ax = plt.subplots(figsize=(5.5, 4))
        y = np.linspace(0, H, 200)
        ax.plot(poiseuille(y), y, "k-", lw=1, label="plane Poiseuille")
        for (label, yy, uu), marker in zip(curves, "os^d"):
            ax.plot(uu, yy, marker, ms=3, mfc="none", label=f"{label}, x in [0.5, 0.6] m")
        ax.set_xlabel("u_x [m/s]")
        ax.set_ylabel("y [m]")
        ax.set_title("Open channel at t = 2 s: the profile before the outlet")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=120)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
