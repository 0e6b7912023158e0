#!/usr/bin/python3
"""The elastic gate's tip against the reference curves (../shared/reference/antoci_2007_elastic_gate):
RMSE of u_x and u_y per reference over the run (or up to --until), the peak u_x and its time, and the
run's wall time. One line per run folder; --against RUN adds each run's u_x and u_y RMSE against that run's
tip (a convergence study: the finest run); --csv writes the table as CSV, --figure plots every run's tip
against the references (u_x and u_y; --labels names the runs there). In a 3D run (the tip's u_z
exists) the references' vertical u_y is compared with u_z, the vertical there.

  /usr/bin/python3 scripts/validate/gate_rmse.py RUN [RUN ...] [--until T] [--against RUN] [--csv FILE]
      [--figure PNG] [--labels A B ...]
"""
import argparse
import json
import math
import os
import sys

import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from coupled_report import GATE_REFS, read_reference, rmse_against
from report_common import ROOT, read_probes

REFERENCE = os.path.join(os.path.dirname(ROOT), "shared", "reference", "antoci_2007_elastic_gate")


def references():
    """{(component, short name): curve} of every reference that exists."""
    out = {}
    for row in GATE_REFS:
        key, shift = row[0], (row[3] if len(row) > 3 else 0.0)
        for comp in ("x", "y"):
            path = os.path.join(REFERENCE, f"ng_2020_elastic_dam_break_{comp}_displacement_{key}.csv")
            if os.path.exists(path):
                ref = read_reference(path)
                ref[:, 0] += shift
                out[(comp, key.split("_")[0])] = ref
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--until", type=float, default=math.inf, help="RMSE up to this time [s]")
    ap.add_argument("--against", help="also the RMSE of each run's tip against this run's")
    ap.add_argument("--csv", help="also write the table to this CSV file")
    ap.add_argument("--figure", help="also plot the runs' tips against the references (PNG)")
    ap.add_argument("--labels", nargs="+", help="the runs' names in the figure (default: their folders)")
    args = ap.parse_args()
    refs = references()
    against = {}
    if args.against:
        a = read_probes(args.against)
        vertical = "tip.uz" if "tip.uz" in a else "tip.uy"
        against = {"x": np.column_stack([a["time"], a["tip.ux"]]), "y": np.column_stack([a["time"], a[vertical]])}
    header = (["run"] + [f"u{c} {name} [mm]" for c, name in refs] + [f"u{c} against it [mm]" for c in against] +
              ["peak ux [mm]", "at [s]", "end [s]", "wall [s]"])
    rows = []
    for run in args.runs:
        d = read_probes(run)
        t = d["time"]
        keep = t <= args.until
        row = [run]
        vertical = "tip.uz" if "tip.uz" in d else "tip.uy"
        for (comp, _), ref in refs.items():
            u = d["tip.ux"] if comp == "x" else d[vertical]
            row.append(f"{rmse_against(t[keep], u[keep], ref) * 1e3:.2f}")
        for comp, ref in against.items():
            u = d["tip.ux"] if comp == "x" else d[vertical]
            row.append(f"{rmse_against(t[keep], u[keep], ref) * 1e3:.2f}")
        ux = d["tip.ux"]
        row += [f"{ux.max() * 1e3:.1f}", f"{t[np.argmax(ux)]:.3f}", f"{t[-1]:.3f}"]
        summary = os.path.join(run, "summary.json")
        row.append(f"{json.load(open(summary))['wall_time_s']:.1f}" if os.path.exists(summary) else "-")
        rows.append(row)
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in rows:
        print("| " + " | ".join(row) + " |")
    if args.csv:
        with open(args.csv, "w") as f:
            f.write(",".join(header) + "\n")
            for row in rows:
                f.write(",".join(row) + "\n")
    if args.figure:
        figure(args.runs, args.labels or args.runs, refs, args.figure)


def figure(runs, labels, refs, path):
    """u_x and u_y of each run's tip beside the reference curves."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    markers = {}
    for (comp, name), ref in refs.items():
        marker = markers.setdefault(name, "os^d"[len(markers) % 4])
        axes[0 if comp == "x" else 1].plot(ref[:, 0], 1e3 * ref[:, 1], marker, ms=3.5, color="0.45", mfc="none",
                                           label=name)
    for k, (run, label) in enumerate(zip(runs, labels)):
        d = read_probes(run)
        vertical = "tip.uz" if "tip.uz" in d else "tip.uy"
        axes[0].plot(d["time"], 1e3 * d["tip.ux"], lw=1.3, color=f"C{k}", label=label)
        axes[1].plot(d["time"], 1e3 * d[vertical], lw=1.3, color=f"C{k}", label=label)
    for ax, comp in zip(axes, ("u_x", "u_y")):
        ax.set_xlabel("t [s]")
        ax.set_ylabel(f"tip {comp} [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
