#!/usr/bin/python3
"""The force probes' table and figure for docs/VALIDATION.md section 33, from the runs of
scripts/investigate/force_probes.sh: the hydrostatic tanks' wall forces against rho g H A (floor) and rho g H^2 W / 2
(side walls) and against the lattice sum of the pairwise force (scripts/validate/lattice_wall_force.py), and the
elastic gate's force probe against the force of each step in its snapshots (m times the interaction
acceleration of seed Eq. 48, summed over the gate).

    /usr/bin/python3 scripts/validate/force_probe_report.py RUNS [--figure docs/figures/force_probes.png]
"""
import argparse
import glob
import os
import sys
import tomllib

import h5py
import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from gate_load import STRUCTURE, GateRun
from lattice_wall_force import lattice_factor
from report_common import read_probes

RHO_G = 1000 * 9.81


def tank_rows(runs):
    """(run, dimension, h/dx, H/dx, floor/(rho g H A), side/(rho g H^2 W / 2), lattice factor) per tank run,
    the means from the first second (the 3D tank: from 0.25 s) on."""
    rows = []
    for name, dim, side_key, settle in (("tank_h1.0", 2, "left_force.fx", 1.0), ("tank_h1.2", 2, "left_force.fx", 1.0),
                                        ("tank_h1.5", 2, "left_force.fx", 1.0), ("tank_dx0.025", 2, "left_force.fx", 1.0),
                                        ("tank_wcsph", 2, "left_force.fx", 1.0), ("tank_3d", 3, "side_force.fx", 0.25)):
        case = tomllib.load(open(f"{runs}/{name}/case.resolved.toml", "rb"))
        d = read_probes(f"{runs}/{name}")
        after = d["time"] >= settle
        width = 1.0 if dim == 2 else 0.5
        area = width ** (dim - 1)                  # the floor, 1 m or 0.5 m x 0.5 m; H = 1 m
        floor = d[f"floor_force.f{'yz'[dim - 2]}"][after].mean() / -(RHO_G * area)
        side = d[side_key][after].mean() / -(RHO_G * 0.5 * width ** (dim - 2))
        hf = case["kernel"]["h_factor"]
        wcsph = case["fluid"].get("model") == "wcsph"
        rows.append((name, dim, hf, round(1.0 / case["dx"]), floor, side, None if wcsph else lattice_factor(hf, dim)))
    return rows


def gate_check(run):
    """The gate's probe rows, and the largest difference between a row that holds one step and that step's
    force in the snapshots; with the snapshots' forces for the figure."""
    gate = GateRun(run)
    mass = gate.material["density"] * gate.gate_dx**2
    snapshot = {}
    for path in sorted(glob.glob(f"{run}/snapshots/snapshot_*.h5")):
        with h5py.File(path) as f:
            on_gate = f["kind"][:] == STRUCTURE
            snapshot[round(float(f.attrs["time"]), 9)] = mass * f["structure_interaction"][:, 0][on_gate].sum()
    d = read_probes(run)
    times = np.array(sorted(snapshot))
    worst, rows = 0.0, 0
    for k in range(1, len(d["time"])):
        t0, t1 = round(float(d["time"][k - 1]), 9), round(float(d["time"][k]), 9)
        between = times[(times > t0 + 1e-9) & (times < t1 - 1e-9)]
        if t0 in snapshot and t1 in snapshot and len(between) == 0:   # a row of one step
            worst = max(worst, abs(d["gate_force.fx"][k] - snapshot[t1]))
            rows += 1
    return d, times, np.array([snapshot[t] for t in times]), rows, worst


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs")
    parser.add_argument("--figure", default="docs/figures/force_probes.png")
    a = parser.parse_args()
    rows = tank_rows(a.runs)
    print("| run | D | h/dx | H/dx | floor / rho g H A | side wall / (rho g H^2 W / 2) | lattice sum |")
    print("|---|---|---|---|---|---|---|")
    for name, dim, hf, n, floor, side, lattice in rows:
        print(f"| {name} | {dim} | {hf:g} | {n} | {floor:.5f} | {side:.5f} | {'' if lattice is None else f'{lattice:.5f}'} |")
    d, times, forces, single, worst = gate_check(f"{a.runs}/gate")
    print(f"gate: {single} probe rows of one step; largest |row - the step's force in the snapshot| = {worst:.2g} N/m")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    h = np.linspace(0.9, 2.1, 121)
    for dim, colour in ((2, "C0"), (3, "C1")):
        axes[0].plot(h, [lattice_factor(x, dim) for x in h], color=colour, label=f"lattice sum, {dim}D")
        measured = [(r[2], r[4]) for r in rows if r[1] == dim and r[6] is not None]
        axes[0].plot(*zip(*measured), "o", color=colour, mfc="none", ms=9, label=f"floor force / rho g H A, {dim}D tank")
    axes[0].axhline(1, color="k", lw=0.5)
    axes[0].set_xlabel("h / dx (cubic spline)")
    axes[0].set_ylabel("force / continuum force")
    axes[0].set_title("Pairwise pressure force on a flat wall")
    axes[0].legend(fontsize=8)
    axes[1].plot(times, forces, lw=0.6, color="0.6", label="force of the step (snapshots every 0.5 ms)")
    axes[1].step(d["time"], d["gate_force.fx"], where="pre", color="C3", lw=1.2, label="force probe: mean over each 1 ms row")
    axes[1].set_xlim(0, 0.4)
    axes[1].set_xlabel("t [s]")
    axes[1].set_ylabel("horizontal force on the gate [N/m]")
    axes[1].set_title("Elastic gate (cases/elastic_gate.toml)")
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.figure, dpi=120)
    print(f"wrote {a.figure}")


if __name__ == "__main__":
    main()
