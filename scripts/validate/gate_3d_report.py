#!/usr/bin/python3
"""The 3D elastic gate (cases/elastic_gate_3d.toml) beside the 2D case at the same spacings and the
references (../shared/reference/antoci_2007_elastic_gate): the tip's u_x at mid-width against time.
Each RUN is LABEL=FOLDER; a run still going or stopped is drawn as far as it got. The table is
scripts/validate/gate_rmse.py's.

  /usr/bin/python3 scripts/validate/gate_3d_report.py "3D T/dx=4=runs/g3d" "2D T/dx=4=runs/g2d" --figure F.png
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from coupled_report import GATE_REFS  # noqa: E402
from gate_rmse import references  # noqa: E402
from report_common import read_probes  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=FOLDER")
    ap.add_argument("--figure", required=True)
    args = ap.parse_args()
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    names = {row[0].split("_")[0]: (row[1], row[2]) for row in GATE_REFS}
    for (comp, key), ref in references().items():
        if comp == "x":
            label, marker = names[key]
            ax.plot(ref[:, 0], ref[:, 1] * 1e3, marker, ms=3, mfc="none", color="0.45", label=label)
    for run in args.runs:
        label, folder = run.split("=", 1)
        d = read_probes(folder)
        ax.plot(d["time"], d["tip.ux"] * 1e3, "--" if label.startswith("2D") else "-", label=label)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("tip u_x [mm]")
    ax.set_xlim(0, 0.4)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.figure, dpi=130)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
