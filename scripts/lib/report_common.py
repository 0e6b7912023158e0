"""What the validation reports share: reading run folders written by `isph run` (probes.csv,
summary.json, snapshots) and writing markdown tables and PNG figures."""
import glob
import json
import math
import os
import re
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def fmt(x, digits=4):
    """x to `digits` significant digits, '-' when missing."""
    return "-" if x is None or not np.isfinite(x) else f"{x:.{digits}g}"


def pct(x, ref):
    return 100.0 * (x - ref) / abs(ref)


def table(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in rows:
        print("| " + " | ".join(str(c) for c in row) + " |")


def run_state(run):
    probes, summary_path = os.path.join(run, "probes.csv"), os.path.join(run, "summary.json")
    if not os.path.exists(probes):
        return "missing"
    # isph writes summary.json last; one older than probes.csv was left by an earlier run.
    if not os.path.exists(summary_path) or os.path.getmtime(summary_path) + 1.0 < os.path.getmtime(probes):
        return "in progress"
    return "finished"


def finished_run(runs, name):
    """The folder of a finished run, else None (with a note on stderr)."""
    run = os.path.join(runs, name)
    state = run_state(run)
    if state == "finished":
        return run
    print(f"note: {run}: {state}, skipped", file=sys.stderr)
    return None


def summary(run):
    with open(os.path.join(run, "summary.json")) as f:
        return json.load(f)


def read_probes(run, name="probes.csv"):
    """probes.csv (or another CSV of the run, e.g. energy.csv) as {column name: array}; the names keep
    their dots (bottom.p)."""
    with open(os.path.join(run, name)) as f:
        lines = [line for line in f.read().splitlines() if line.strip()]
    names = [n.strip() for n in lines[0].split(",")]
    data = np.loadtxt(lines[1:], delimiter=",", ndmin=2)
    return {n: data[:, k] for k, n in enumerate(names)}


def snapshot_times(folder, end=math.inf):
    """[(time, path)] of one folder's snapshots up to `end`."""
    out = []
    for path in sorted(glob.glob(os.path.join(folder, "snapshots", "snapshot_*.h5"))):
        with h5py.File(path, "r") as h:
            t = float(h.attrs["time"])
        if t <= end * (1 + 1e-9):
            out.append((t, path))
    return out


def snapshot_list(run):
    """[(time, path)] of the snapshots up to the end of the run (later files are stale). A run continued
    with --restart whose earlier parts were moved to RUN.part1, RUN.part2, ... (scripts/validate/validate_coupled.sh)
    also lists their snapshots before its own first."""
    end = summary(run).get("simulated_time", math.inf) if os.path.exists(os.path.join(run, "summary.json")) else math.inf
    parts = {int(m.group(1)): p for p in glob.glob(run + ".part*")
             if os.path.isdir(p) and (m := re.fullmatch(r".*\.part(\d+)", p))}
    out = snapshot_times(run, end)
    for part in (parts[k] for k in sorted(parts, reverse=True)):
        first = out[0][0] if out else math.inf
        out = [s for s in snapshot_times(part) if s[0] < first * (1 - 1e-9)] + out
    return out


def read_snapshot(path):
    with h5py.File(path, "r") as h:
        return {k: h[k][:] for k in h}


def closest(snaps, t):
    return min(range(len(snaps)), key=lambda i: abs(snaps[i][0] - t))


def save(fig, args, name):
    os.makedirs(args.figures, exist_ok=True)
    path = os.path.join(args.figures, name)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print(f"\n<!-- figure {os.path.relpath(path, ROOT) if path.startswith(ROOT) else path} -->")
