#!/usr/bin/python3
"""What the water does to the elastic gate, from a run's snapshots (docs/VALIDATION.md section 25, issue 37):
per snapshot, the water's horizontal force on the free gate (the sum of its particles' mass times the
interaction acceleration of seed Eq. 48, per metre of depth) and the part of it on the gate's downstream
half (from any water within a kernel's reach of those particles, upstream water included where the kernel
reaches through the gate), the reservoir's level half-way between the left wall and the gate, and the water
that has passed under the gate (the area of the water beyond the bent gate's farthest particle).

    /usr/bin/python3 scripts/validate/gate_load.py RUN [RUN ...] [--times 0.1 0.15 0.2 0.25] [--window 0.02] [--csv FILE]
        [--figure FILE]
"""
import argparse
import glob
import tomllib

import h5py
import numpy as np

FLUID, STRUCTURE = 0, 2


class GateRun:
    """A run of cases/elastic_gate.toml with snapshots: its case, and what each snapshot says of the gate's
    free part (below the clamp) and of the water."""

    def __init__(self, run):
        self.run = run
        self.case = tomllib.load(open(f"{run}/case.resolved.toml", "rb"))
        self.gate = next(b for b in self.case["bodies"] if b["kind"] == "structure")
        self.water = next(b for b in self.case["bodies"] if b["kind"] == "fluid")
        self.material = next(m for m in self.case["materials"] if m["name"] == self.gate["material"])
        self.dx = self.case["dx"]
        self.gate_dx = self.dx / self.gate.get("refinement", 1)
        self.x0, self.x1 = self.gate["shape"]["min"][0], self.gate["shape"]["max"][0]
        self.clamp_y = self.gate["clamps"][0]["min"][1]

    def snapshots(self):
        """Per snapshot: its time, the free gate particles' reference and current positions (x, y) and the
        water's force on each (m times the interaction acceleration, per metre of depth), all in the order of
        their ids, and the water particles' positions."""
        mass = self.material["density"] * self.gate_dx**2
        reference = None
        for path in sorted(glob.glob(f"{self.run}/snapshots/snapshot_*.h5")):
            with h5py.File(path) as f:
                kind, x = f["kind"][:], f["position"][:, :2]
                structure = np.flatnonzero(kind == STRUCTURE)
                structure = structure[np.argsort(f["id"][:][structure])]
                if reference is None:   # the first snapshot is the initial state
                    reference = x[structure]
                    free = reference[:, 1] < self.clamp_y
                force = mass * f["structure_interaction"][:, :2][structure]
                yield f.attrs["time"], reference[free], x[structure][free], force[free], x[kind == FLUID]


def history(run):
    """{quantity: array over the snapshots} of one run of cases/elastic_gate.toml."""
    g = GateRun(run)
    level_x = 0.5 * (g.water["shape"]["min"][0] + g.x0)
    out = {k: [] for k in ("time", "force", "force_downstream_half", "level", "passed")}
    for time, X, x, force, fluid in g.snapshots():
        column = fluid[np.abs(fluid[:, 0] - level_x) < g.dx]
        out["time"].append(time)
        out["force"].append(force[:, 0].sum())
        out["force_downstream_half"].append(force[X[:, 0] > 0.5 * (g.x0 + g.x1), 0].sum())
        out["level"].append(column[:, 1].max() + g.dx / 2 if len(column) else 0.0)
        out["passed"].append(g.dx**2 * np.count_nonzero(fluid[:, 0] > x[:, 0].max()))
    return {k: np.array(v) for k, v in out.items()}


def windowed(h, key, window, at):
    """The means of h[key] over the snapshots within window/2 of each time in `at`."""
    return np.array([h[key][np.abs(h["time"] - t) <= window / 2].mean() for t in at])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--labels", help="comma-separated, one per run")
    parser.add_argument("--times", type=float, nargs="+", default=[0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    parser.add_argument("--window", type=float, default=0.02,
                        help="the table's force, level and passed water: means over the snapshots this long about each time [s]")
    parser.add_argument("--csv", help="write every run's history here")
    parser.add_argument("--figure", help="plot force, level and passed water here (PNG)")
    a = parser.parse_args()
    labels = a.labels.split(",") if a.labels else a.runs
    histories = [history(run) for run in a.runs]
    print("| run | t [s] | force on the gate [N/m] | on its downstream half [N/m] | reservoir level [mm] | "
          "water passed [cm^2] |")
    print("|---|---|---|---|---|---|")
    for label, h in zip(labels, histories):
        mean = {k: windowed(h, k, a.window, a.times) for k in h}
        for i, t in enumerate(a.times):
            print(f"| {label} | {t:.3f} | {mean['force'][i]:.1f} | {mean['force_downstream_half'][i]:.1f} | "
                  f"{1e3 * mean['level'][i]:.1f} | {1e4 * mean['passed'][i]:.1f} |")
    if a.csv:
        with open(a.csv, "w") as out:
            keys = list(histories[0])
            out.write("run," + ",".join(keys) + "\n")
            for label, h in zip(labels, histories):
                for row in zip(*(h[k] for k in keys)):
                    out.write(label + "," + ",".join(f"{v:.6g}" for v in row) + "\n")
    if a.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
        for label, h in zip(labels, histories):
            axes[0].plot(h["time"], windowed(h, "force", a.window, h["time"]), label=label)
            axes[1].plot(h["time"], 1e3 * windowed(h, "level", a.window, h["time"]), label=label)
            axes[2].plot(h["time"], 1e4 * h["passed"], label=label)
        for ax, name in zip(axes, (f"water's force on the gate [N/m], {1e3 * a.window:g} ms means",
                                   f"reservoir level at mid-column [mm], {1e3 * a.window:g} ms means",
                                   "water passed under the gate [cm²]")):
            ax.set_xlabel("t [s]")
            ax.set_title(name, fontsize=10)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.figure, dpi=110)


if __name__ == "__main__":
    main()
