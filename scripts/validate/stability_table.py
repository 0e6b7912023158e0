#!/usr/bin/python3
"""The stability table: every shipped case at its shipped Courant number and at larger multiples of it.

  /usr/bin/python3 scripts/validate/stability_table.py [--cases NAME,...] [--factors 1,1.5,2] [--budget 150]
        [--budgets NAME=SECONDS,...] [--threads 1] [--out runs/stability_table] [--isph build/isph]
        [--report-only]

The Courant number scaled is the fluid's (fluid.courant for ISPH, fluid.wcsph.acoustic_courant for
WCSPH) where the case has a fluid, else the structure's (structure.courant); the shipped value is read
from the factor-1 run's case.resolved.toml. Each point runs `isph run CASE --quiet --threads N` into
<out>/<case>/x<factor>/segment_1/, and is stopped by SIGINT once it has run for its wall budget (BUDGETS
below, else --budget): the solver then ends the step, writes its last snapshot and summary.json with
status "interrupted", and the table gives how far it got. A point whose summary.json and
stability_run.json (the command) match is not run again, so the table can be resumed and extended; one
the budget stopped continues, given a larger budget, from its last snapshot into segment_2/, and so on
(`--restart`), so that a point longer than a session runs in parts. Its summary.json is the last
segment's, with the wall time and steps of all.

Columns: status (completed, diverged, interrupted by the budget), the steps taken (fluid steps, or
structure steps without a fluid: the limit that binds may be another than the Courant number scaled,
e.g. viscosity's), the simulated time reached out of end_time, the largest fraction of the case's energy scale created (the energy books of
docs/RELIABILITY.md, summary.json energy_books.peak_created_fraction), the wall time and, for a run
that stopped, the solver's message. Writes <out>/table.csv, <out>/table.md and the chart
<out>/table.png (docs/STUDIES.md, "Stability table").
"""
import argparse
import csv
import glob
import json
import os
import shutil
import signal
import subprocess
import sys
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Wall budgets [s] of the cases whose run to end_time takes longer than the default's (2-core VM, one
# thread); each still reaches past its first violent event (impact, peak, first period) in its budget.
BUDGETS = {"dam_break": 420, "elastic_gate": 300, "hydrostatic_plate": 300}


def courant_key(resolved):
    """The Courant number the table scales, and its shipped value, from a case.resolved.toml."""
    if resolved["stages"]["fluid"]:
        fluid = resolved["fluid"]
        if fluid["model"] == "wcsph":
            return "fluid.wcsph.acoustic_courant", fluid["wcsph"]["acoustic_courant"]
        return "fluid.courant", fluid["courant"]
    return "structure.courant", resolved["structure"]["courant"]


def factor_label(f):
    return f"x{f:g}"


def run_segment(command, out, budget):
    """Runs `command` into `out` for at most `budget` s, then stops it with SIGINT (the solver ends the
    step and writes its last snapshot and summary.json); returns the exit status."""
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "stderr.txt"), "w") as err:
        proc = subprocess.Popen(command + ["--out", out], cwd=ROOT, stderr=err, stdout=subprocess.DEVNULL)
        try:
            proc.wait(timeout=budget)
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGINT)
            proc.wait()
    return proc.returncode


def run_point(args, case, folder, overrides, budget):
    """Runs one point unless it is done with the same command, or continues it from its last snapshot
    when the budget stopped it and this one is larger; returns its summary (None on error). The point's
    summary.json is its last segment's, with the wall time and steps of all of them."""
    command = [args.isph, "run", case, "--quiet", "--threads", str(args.threads)] + [
        a for o in overrides for a in ("--set", o)]
    record_path, summary_path = os.path.join(folder, "stability_run.json"), os.path.join(folder, "summary.json")
    segments = []
    if os.path.exists(record_path) and os.path.exists(summary_path):
        with open(record_path) as f:
            record = json.load(f)
        with open(summary_path) as g:
            summary = json.load(g)
        if record.get("command") == command[1:] and "segments" in record:
            if not (summary["status"] == "interrupted" and budget > record.get("budget", 0)):
                return summary
            segments = record["segments"]
    spent = sum(seg["wall_time_s"] for seg in segments)
    for stale in (record_path, summary_path):  # a stopped run must not look finished
        if os.path.exists(stale):
            os.remove(stale)
    out = os.path.join(folder, f"segment_{len(segments) + 1}")
    restart = ["--restart", os.path.join(folder, segments[-1]["folder"])] if segments else []
    print(f"run  {os.path.relpath(out, args.out)}  (budget {budget - spent:.0f} of {budget} s)", flush=True)
    code = run_segment(command + restart, out, budget - spent)
    if code not in (0, 3, 4) and not os.path.exists(os.path.join(out, "summary.json")):
        print(f"  error: exit {code}; see {out}/stderr.txt", file=sys.stderr)
        return None
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    segments.append({"folder": os.path.basename(out), "returncode": code, "wall_time_s": summary["wall_time_s"],
                     "steps": summary["steps"]})
    summary["wall_time_s"] = sum(seg["wall_time_s"] for seg in segments)
    summary["steps"] = {k: sum(seg["steps"][k] for seg in segments) for k in summary["steps"]}
    shutil.copy(os.path.join(out, "case.resolved.toml"), os.path.join(folder, "case.resolved.toml"))
    with open(summary_path, "w") as f:
        json.dump(summary, f, indent=2)
    with open(record_path, "w") as f:
        json.dump({"command": command[1:], "budget": budget, "segments": segments}, f)
    return summary


def row_of(name, factor, key, value, end_time, s):
    books = s.get("energy_books", {})
    return {"case": name, "factor": factor, "key": key, "courant": value * factor, "status": s["status"],
            "simulated_time": s["simulated_time"], "end_time": end_time,
            "created": books.get("peak_created_fraction", float("nan")), "wall_time_s": s["wall_time_s"],
            "steps": s["steps"]["fluid" if key.startswith("fluid") else "structure"],
            "message": "" if s["status"] == "completed" else s["message"]}


def markdown(rows, factors):
    """One line per case: for each factor, the outcome and the energy created."""
    by_case = {}
    for r in rows:
        by_case.setdefault(r["case"], {})[r["factor"]] = r
    head = ["case", "Courant key", "shipped"] + [factor_label(f) for f in factors]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    notes = []
    for name, points in sorted(by_case.items()):
        first = next(iter(points.values()))
        cells = []
        for f in factors:
            r = points.get(f)
            if r is None:
                cells.append("-")
                continue
            created = f"{r['created']:.2g}" if r["created"] == r["created"] else "-"
            reached = f"{r['simulated_time']:.3g} of {r['end_time']:.3g} s"
            if r["status"] == "completed":
                cells.append(f"completed, {created} created, {r['steps']} steps ({r['wall_time_s']:.0f} s)")
            elif r["status"] == "interrupted":
                cells.append(f"running at budget: {reached}, {created} created")
            else:
                cells.append(f"**{r['status']}** at {reached}, {created} created [{len(notes) + 1}]")
                notes.append(f"[{len(notes) + 1}] {name} {factor_label(f)}: {r['message']}")
        lines.append("| " + " | ".join([name, f"`{first['key']}`", f"{first['courant'] / first['factor']:g}"] + cells)
                     + " |")
    return "\n".join(lines + [""] + notes) + "\n"


def figure(rows, factors, path):
    """The table as a chart: one row per case, one column per factor, coloured by the outcome (green
    completed, amber stopped by the budget, shaded by how far it got, red failed) and labelled with the
    energy created."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    cases = sorted({r["case"] for r in rows})
    by_point = {(r["case"], r["factor"]): r for r in rows}
    fig, ax = plt.subplots(figsize=(2.2 + 1.6 * len(factors), 0.36 * len(cases) + 1.2))
    colour = {"completed": (0.30, 0.69, 0.31), "interrupted": (1.0, 0.70, 0.20)}
    for y, case in enumerate(cases):
        for x, f in enumerate(factors):
            r = by_point.get((case, f))
            if r is None:
                continue
            c = colour.get(r["status"], (0.84, 0.19, 0.15))
            reached = min(1.0, r["simulated_time"] / r["end_time"])
            alpha = 1.0 if r["status"] != "interrupted" else 0.25 + 0.75 * reached
            ax.add_patch(plt.Rectangle((x, y), 0.95, 0.9, color=c, alpha=alpha))
            label = f"{r['created']:.2g}" if r["status"] == "completed" else (
                f"{100 * reached:.0f} %" if r["status"] == "interrupted" else r["status"])
            ax.text(x + 0.47, y + 0.45, label, ha="center", va="center", fontsize=7)
    ax.set_xlim(0, len(factors))
    ax.set_ylim(0, len(cases))
    ax.set_xticks([x + 0.47 for x in range(len(factors))], [f"{f:g} x shipped" for f in factors])
    ax.set_yticks([y + 0.45 for y in range(len(cases))], cases, fontsize=8)
    ax.invert_yaxis()
    ax.set_title("Each shipped case at multiples of its Courant number\n(label: energy created / scale; "
                 "or share of the run done in the budget)", fontsize=9)
    ax.legend(handles=[Patch(color=colour["completed"], label="completed"),
                       Patch(color=colour["interrupted"], label="stopped by the wall budget"),
                       Patch(color=(0.84, 0.19, 0.15), label="diverged")],
              loc="upper center", bbox_to_anchor=(0.5, -0.04), ncol=3, fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", help="comma-separated case names (default: every cases/*.toml)")
    ap.add_argument("--factors", default="1,1.5,2")
    ap.add_argument("--budget", type=float, default=150, help="wall seconds per run where BUDGETS names none")
    ap.add_argument("--budgets", default="", help="NAME=SECONDS,... : these cases' budgets instead (a point the "
                    "budget stopped continues from its last snapshot, to its end or the new budget, when the new one is larger)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(ROOT, "runs", "stability_table"))
    ap.add_argument("--isph", default=os.path.join(ROOT, "build", "isph"))
    ap.add_argument("--report-only", action="store_true", help="tabulate the runs found, run nothing")
    args = ap.parse_args()
    factors = [float(f) for f in args.factors.split(",")]
    budgets = dict(BUDGETS)
    budgets.update({k: float(v) for k, v in (item.split("=") for item in args.budgets.split(",") if item)})
    cases = sorted(glob.glob(os.path.join(ROOT, "cases", "*.toml")))
    if args.cases:
        wanted = set(args.cases.split(","))
        cases = [c for c in cases if os.path.basename(c)[:-5] in wanted]
    shown = sorted(set(factors) | {1.0, 1.5, 2.0})  # the table shows every point run so far
    rows = []
    for case in cases:
        name = os.path.basename(case)[:-5]
        budget = budgets.get(name, args.budget)
        base = os.path.join(args.out, name)
        first = os.path.join(base, factor_label(1.0))
        # the shipped point gives the Courant number the others scale; it runs when asked for or missing
        run_first = 1.0 in factors or not os.path.exists(os.path.join(first, "case.resolved.toml"))
        if not args.report_only and run_first and run_point(args, case, first, [], budget) is None:
            continue
        if not os.path.exists(os.path.join(first, "case.resolved.toml")):
            continue
        with open(os.path.join(first, "case.resolved.toml"), "rb") as f:
            resolved = tomllib.load(f)
        key, value = courant_key(resolved)
        if not args.report_only:
            for factor in factors:
                if factor != 1.0:
                    run_point(args, case, os.path.join(base, factor_label(factor)),
                              [f"{key}={value * factor:.6g}"], budget)
        for factor in shown:
            summary_path = os.path.join(base, factor_label(factor), "summary.json")
            if os.path.exists(summary_path):
                with open(summary_path) as f:
                    rows.append(row_of(name, factor, key, value, resolved["end_time"], json.load(f)))
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "table.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["case"])
        w.writeheader()
        w.writerows(rows)
    text = markdown(rows, shown)
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write(text)
    if rows:
        figure(rows, shown, os.path.join(args.out, "table.png"))
    print(text)


if __name__ == "__main__":
    main()
