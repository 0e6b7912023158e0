#!/usr/bin/python3
"""The 3D hydrostatic plate (cases/hydrostatic_plate_3d.toml) against the static centre deflection of the
3D continuum (scripts/reference/fe_plate_3d.py) and of thin-plate theory: the table of docs/VALIDATION.md section 32
and its figure. The coupled run's mean deflection is taken over whole periods of its oscillation, from the
first upward crossing of the mean after --from to the last one.

  /usr/bin/python3 scripts/validate/plate_3d_report.py runs/plate_3d --dry runs/plate_3d_dry --figure F.png
"""
import argparse
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from fe_plate_3d import GRAVITY, HEAD, WATER_DENSITY, thin_plate  # noqa: E402
from report_common import pct, read_probes, summary, table  # noqa: E402

# scripts/reference/fe_plate_3d.py --elements 16 2 under 0.5 m of water and the plate's weight (section 32); 12 x 12 x 2
# elements give 1.0284e-5 m, 12 x 12 x 4 1.0291e-5.
CONTINUUM = 1.0309e-5
COLUMN = WATER_DENSITY * GRAVITY * HEAD  # the water's pressure on the plate, and its weight over the 1 m^2 [N]
THIN_PLATE = thin_plate(1.0, COLUMN)


def whole_periods(t, u, start):
    """The mean of u over whole periods after start, the period, and the window, found from the upward
    crossings of the mean over t >= start (iterated once, as the mean moves the crossings)."""
    late = t >= start
    mean = u[late].mean()
    for _ in range(2):
        up = np.flatnonzero(late[1:] & (u[:-1] < mean) & (u[1:] >= mean)) + 1
        if len(up) < 2:
            return mean, float("nan"), (t[late][0], t[-1])
        window = slice(up[0], up[-1])
        mean = u[window].mean()
    return mean, (t[up[-1]] - t[up[0]]) / (len(up) - 1), (t[up[0]], t[up[-1]])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("coupled", help="the run of cases/hydrostatic_plate_3d.toml")
    ap.add_argument("--dry", help="the run of cases/hydrostatic_plate_3d_dry.toml")
    ap.add_argument("--from", dest="start", type=float, default=0.02, help="the mean's window starts here [s]")
    ap.add_argument("--figure", required=True)
    args = ap.parse_args()

    d, s = read_probes(args.coupled), summary(args.coupled)
    t, w = d["time"], -d["centre.uz"]
    mean, period, (t0, t1) = whole_periods(t, w, args.start)
    force = s["performance"]["coupling"]["mean_force_on_structure"]["fz"]
    rows = [["3D continuum (finite elements)", f"{CONTINUUM:.4g}", "", "", ""],
            ["thin-plate theory", f"{THIN_PLATE:.4g}", f"{pct(THIN_PLATE, CONTINUUM):+.2f}", "", ""]]
    dry = -read_probes(args.dry)["centre.uz"][-1] if args.dry else None
    if dry is not None:
        ds = summary(args.dry)
        rows.append(["the plate alone, at rest (T/dx = 4)", f"{dry:.4g}", f"{pct(dry, CONTINUUM):+.2f}", "",
                     f"{ds['wall_time_s']:.0f} s, {ds['performance'].get('threads', '')} threads"])
    rows.append([f"coupled, mean over {t0:.4f}-{t1:.4f} s", f"{mean:.4g}", f"{pct(mean, CONTINUUM):+.2f}",
                 f"{w.max():.4g} ({w.max() / CONTINUUM:.2f} of static)",
                 f"{s['wall_time_s']:.0f} s, {s['performance']['threads']} threads"])
    table(["run", "centre deflection [m]", "against the continuum %", "peak [m]", "wall time"], rows)
    print(f"\nperiod of the coupled oscillation {period * 1e3:.2f} ms; mean force on the plate over the run "
          f"{-force:.1f} N (the column's weight {COLUMN:.1f} N)")

    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t, w * 1e6, lw=0.8, marker="o", ms=2.5,
            label="ISPH-TLSPH, centre (water 1/60 m, plate T/dx = 4), at the fluid steps")
    ax.axhline(mean * 1e6, color="tab:blue", ls="-.", lw=1, label=f"its mean over {t0:.3f}-{t1:.3f} s")
    ax.axhline(CONTINUUM * 1e6, color="tab:red", ls=":", lw=1.2, label="static, 3D continuum (finite elements)")
    ax.axhline(THIN_PLATE * 1e6, color="k", ls="--", lw=1, label="static, thin-plate theory")
    if dry is not None:
        ax.axhline(dry * 1e6, color="tab:green", ls="--", lw=1, label="the plate alone at rest (T/dx = 4)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("centre deflection −u_z [µm]")
    ax.set_ylim(0, 1.6 * w.max() * 1e6)  # room above the history for the legend
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.figure, dpi=120)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
