#!/usr/bin/python3
"""The cylinder in a channel (cases/dfg_cylinder.toml, docs/VALIDATION.md section 35) against the DFG
benchmark 2D-1 of Schäfer & Turek (1996): per run, the time means over a window of the drag (all of the
fluid's force, the `cylinder` probe) and of its pressure part, the lift and the pressure difference
between the cylinder's front and back, with their standard deviations over the window's rows; the fluid
lost through the open boundaries; the wall time. Optionally a figure of the drag histories.

  /usr/bin/python3 scripts/validate/dfg_report.py LABEL=RUN [LABEL=RUN ...] [--window 3 8] [--figure PNG]

The runs of docs/VALIDATION.md (each fluid body starts 4 layers behind the inlet; the cylinder is on rings):
  D/10:  build/isph run cases/dfg_cylinder.toml --threads 2 --out D10
  D/20:  ... --set dx=0.005 --set 'bodies.fluid.shape={type="rectangle",min=[-0.02,0.0],max=[2.22,0.41]}'
  D/7.3: ... --set dx=0.013666666666666667 (0.41/30), the fluid from -0.054667 to 2.254667, and walls 0.041 m
             thick (three layers)

The benchmark's values at rho = 1 (FEATFLOW): c_D = 5.57953523384, c_L = 0.010618948146,
Delta p = 0.11752016697 Pa; at the case's rho = 1000, U = 0.2 m/s, D = 0.1 m: F_D = c_D rho U^2 D / 2 =
11.159 N/m, F_L = 0.0212 N/m, Delta p = 117.52 Pa.
"""
import argparse
import os
import sys

import numpy as np

sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib")]
from report_common import plt, read_probes, summary, table

RHO, U, D = 1000.0, 0.2, 0.1
SCALE = 0.5 * RHO * U**2 * D
DRAG, LIFT, DP = 5.57953523384 * SCALE, 0.010618948146 * SCALE, 0.11752016697 * RHO


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", help="LABEL=RUN")
    parser.add_argument("--window", nargs=2, type=float, default=(3.0, 8.0), help="time window [s] of the means")
    parser.add_argument("--figure", help="write the drag histories here (PNG)")
    args = parser.parse_args()
    lo, hi = args.window
    rows, curves = [], []
    for spec in args.runs:
        label, run = spec.split("=", 1)
        p = read_probes(run)
        t = np.asarray(p["time"])
        m = (t > lo) & (t <= hi)
        drag, pressure = np.asarray(p["cylinder.fx"]), np.asarray(p["cylinder_pressure.fx"])
        lift, dp = np.asarray(p["cylinder.fy"]), np.asarray(p["front.p"]) - np.asarray(p["back.p"])
        s = summary(run)
        b = s["particles"]["open_boundaries"]
        rows.append([label, f"{drag[m].mean():.3f} ± {drag[m].std():.2f} ({100 * (drag[m].mean() / DRAG - 1):+.1f} %)",
                     f"{pressure[m].mean() / drag[m].mean():.2f}", f"{lift[m].mean():.3f} ± {lift[m].std():.2f}",
                     f"{dp[m].mean():.1f} ± {dp[m].std():.0f} ({100 * (dp[m].mean() / DP - 1):+.1f} %)",
                     f"{-b['fluid_mass_change'] / b['mass_in'] * 100:.2f} %", f"{s['wall_time_s']:.0f}"])
        curves.append((label, t, drag, pressure))
    print(f"means over {lo:g}-{hi:g} s; the benchmark: drag {DRAG:.3f} N/m, lift {LIFT:.4f} N/m, Δp {DP:.2f} Pa")
    table(["run", "drag [N/m]", "pressure share", "lift [N/m]", "Δp front-back [Pa]", "fluid lost / inflow",
           "wall [s]"], rows)
    if args.figure:
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.axhline(DRAG, color="k", lw=1, label="Schäfer & Turek 1996, 2D-1")
        for label, t, drag, pressure in curves:
            line, = ax.plot(t, drag, lw=1, label=f"{label}: all terms")
            ax.plot(t, pressure, lw=1, ls="--", color=line.get_color(), label=f"{label}: pressure")
        ax.axvspan(lo, hi, color="0.92", zorder=0)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("drag [N/m] (0.1 s means)")
        ax.set_ylim(0, 2 * DRAG)
        ax.set_title("Cylinder in a channel, Re = 20: the drag")
        ax.legend(fontsize=8, ncol=2)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=120)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
