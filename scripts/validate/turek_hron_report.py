#!/usr/bin/python3
"""Turek & Hron's channel (cases/turek_hron.toml, docs/VALIDATION.md section 36) against the benchmark's
finite-element values (Turek & Hron 2006, their finest grids). Per run: the displacement of point A (the
bar's free end, probe `A`) and the drag and lift on cylinder and bar together (the `cylinder` and `bar`
force probes, all terms; drag and lift through a running mean, --smooth), each as mean ± amplitude [frequency]
over a window: for the steady variants
(CFD2, FSI1) the mean and the window's standard deviation; for the periodic ones the mean of the
window's extremes, half their difference, and the frequency from the mean-crossings. Also the bar's
share of the drag, the fluid lost through the open boundaries and the wall time (these two once the run has
ended: a run still going is read as far as its probes.csv). Optionally a figure of
the histories against the reference bands.

  /usr/bin/python3 scripts/validate/turek_hron_report.py VARIANT:LABEL=RUN [...] [--window LO HI] [--figure PNG]
        [--pareto PNG]

--pareto: the speed-accuracy chart of the runs that have ended: each quantity's error (of the mean for a
steady one, of the amplitude for a periodic one) against the wall time per simulated second of the whole
run (summary.json's wall time over its simulated time: a run continued from a snapshot counts only its
own part, so such runs are left out). A LABEL "SERIES/POINT" joins the runs of one SERIES by a line, each
point named POINT (cfd2:rings/D10=RUN cfd2:rings/D20=RUN); other labels join the runs of their variant.

VARIANT is one of cfd2, cfd3, fsi1, fsi2, fsi3; the --set lines of each are in the case's header.
"""
import argparse
import os
import sys

import numpy as np

sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "lib")]
from report_common import plt, read_probes, summary, table

# (mean, amplitude, frequency [Hz]) per quantity; amplitude None for steady values. Displacements in mm,
# forces in N per metre of depth at rho_f = 1000 kg/m^3. Turek & Hron (2006), Tables 7, 9, 12 and 13.
REFERENCE = {
    "cfd2": {"drag": (136.7, None, None), "lift": (10.53, None, None)},
    "cfd3": {"drag": (439.45, 5.6183, 4.3956), "lift": (-11.893, 437.81, 4.3956)},
    "fsi1": {"ux": (0.0227, None, None), "uy": (0.8209, None, None), "drag": (14.295, None, None),
             "lift": (0.7638, None, None)},
    "fsi2": {"ux": (-14.58, 12.44, 3.8), "uy": (1.23, 80.6, 2.0), "drag": (208.83, 73.75, 3.8),
             "lift": (0.88, 234.2, 2.0)},
    "fsi3": {"ux": (-2.69, 2.53, 10.9), "uy": (1.48, 34.38, 5.3), "drag": (457.3, 22.66, 10.9),
             "lift": (2.22, 149.78, 5.3)},
}


def histories(run):
    p = read_probes(run)
    h = {"time": np.asarray(p["time"])}
    h["drag"] = np.asarray(p["cylinder.fx"]) + np.asarray(p["bar.fx"])
    h["lift"] = np.asarray(p["cylinder.fy"]) + np.asarray(p["bar.fy"])
    h["bar_drag"] = np.asarray(p["bar.fx"])
    h["ux"] = 1e3 * np.asarray(p["A.ux"])
    h["uy"] = 1e3 * np.asarray(p["A.uy"])
    return h


def smoothed(t, y, width):
    """The centred running mean of y over `width` seconds (the rows' spacing taken as uniform); near the ends
    the mean of the rows there are, not of rows padded with zeros."""
    n = max(1, int(round(width / np.median(np.diff(t)))))
    if n < 2:
        return y
    kernel = np.ones(n)
    return np.convolve(y, kernel, mode="same") / np.convolve(np.ones_like(y), kernel, mode="same")


def oscillation(t, y):
    """Mean of the extremes, half their difference, and the frequency from the crossings of that mean."""
    mid, amplitude = 0.5 * (y.max() + y.min()), 0.5 * (y.max() - y.min())
    s = np.sign(y - mid)
    up = np.nonzero((s[:-1] < 0) & (s[1:] >= 0))[0]
    crossings = t[up] + (mid - y[up]) * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    frequency = (len(crossings) - 1) / (crossings[-1] - crossings[0]) if len(crossings) > 1 else float("nan")
    return mid, amplitude, frequency


def describe(value, reference):
    mean, amplitude, frequency = value
    ref_mean, ref_amplitude, ref_frequency = reference

    def rel(a, b):
        return f" ({100 * (a / b - 1):+.1f} %)" if b else ""

    if ref_amplitude is None:
        return f"{mean:.4g} ± {amplitude:.2g}{rel(mean, ref_mean)}"
    return (f"{mean:.4g} ± {amplitude:.4g}{rel(amplitude, ref_amplitude)} [{frequency:.3g} Hz"
            f"{rel(frequency, ref_frequency)}]")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", help="VARIANT:LABEL=RUN")
    parser.add_argument("--window", nargs=2, type=float, help="time window [s] (default: the run's last third)")
    parser.add_argument("--figure", help="write the histories here (PNG)")
    parser.add_argument("--pareto", help="write the error against the wall time per simulated second here (PNG)")
    parser.add_argument("--smooth", type=float, default=0.05,
                        help="running mean [s] of drag and lift before their extremes and crossings (the rows' "
                             "means over 0.01 s still swing from step to step)")
    args = parser.parse_args()
    rows, curves, errors = [], [], []
    for spec in args.runs:
        head, run = spec.split("=", 1)
        variant, label = head.split(":", 1)
        reference = REFERENCE[variant]
        h = histories(run)
        t = h["time"]
        lo, hi = args.window if args.window else (t[-1] * 2 / 3, t[-1])
        finite = np.isfinite(h["drag"])  # the row at t = 0 holds no force
        m = (t > lo) & (t <= hi) & finite
        row = [f"{variant.upper()} {label} ({lo:g}-{hi:g} s)"]
        run_errors = []
        for q in ("ux", "uy", "drag", "lift"):
            if q not in reference:
                row.append("")
                continue
            # smoothed over the whole run, then windowed, so that the window's ends see their neighbours
            y = smoothed(t[finite], h[q][finite], args.smooth)[m[finite]] if q in ("drag", "lift") else h[q][m]
            value = (y.mean(), y.std(), None) if reference[q][1] is None else oscillation(t[m], y)
            row.append(describe(value, reference[q]))
            k = 0 if reference[q][1] is None else 1  # the mean of a steady value, the amplitude of a periodic one
            run_errors.append((q, 100 * abs(value[k] / reference[q][k] - 1)))
        row.append(f"{h['bar_drag'][m].mean() / h['drag'][m].mean():.2f}")
        cost = None
        if os.path.exists(os.path.join(run, "summary.json")):
            s = summary(run)
            if s["simulated_time"] >= t[-1] - 1e-9:  # the whole run in one piece
                cost = s["wall_time_s"] / s["simulated_time"]
            b = s["particles"]["open_boundaries"]
            row += [f"{-b['fluid_mass_change'] / b['mass_in'] * 100:.2f} %", f"{s['wall_time_s']:.0f}"]
        else:  # still running
            row += ["-", "-"]
        rows.append(row)
        curves.append((variant, label, h))
        if cost is not None:
            series, _, point = label.rpartition("/")
            errors += [(f"{variant.upper()} {q} {series}".rstrip(), point, error, cost) for q, error in run_errors]
    table(["run", "u_x(A) [mm]", "u_y(A) [mm]", "drag [N/m]", "lift [N/m]", "bar's drag share",
           "fluid lost / inflow", "wall [s]"], rows)
    if args.figure:
        fig, axes = plt.subplots(2, 2, figsize=(10, 6), sharex=True)
        for ax, q, unit in zip(axes.flat, ("ux", "uy", "drag", "lift"), ("mm", "mm", "N/m", "N/m")):
            for variant, label, h in curves:
                if q not in REFERENCE[variant]:
                    continue
                line, = ax.plot(h["time"], h[q], lw=1, label=f"{variant.upper()} {label}")
                mean, amplitude, _ = REFERENCE[variant][q]
                ax.axhline(mean, color=line.get_color(), lw=0.8, ls="--")
                if amplitude:
                    ax.axhspan(mean - amplitude, mean + amplitude, color=line.get_color(), alpha=0.08)
            ax.set_ylabel(f"{q} [{unit}]")
            ax.legend(fontsize=7)
        for ax in axes[1]:
            ax.set_xlabel("t [s]")
        fig.suptitle("Turek & Hron's channel: ours (lines) against the benchmark (dashed: mean; band: amplitude)")
        fig.tight_layout()
        fig.savefig(args.figure, dpi=120)
        print(f"wrote {args.figure}")
    if args.pareto:
        pareto(errors, args.pareto)


def pareto(errors, path):
    """Error [%] against wall seconds per simulated second, one line per variant and quantity."""
    fig, ax = plt.subplots(figsize=(8.5, 4.2))
    lines = {}
    for name, label, error, cost in errors:
        lines.setdefault(name, []).append((cost, error, label))
    for name, points in lines.items():
        points.sort()
        line, = ax.loglog([p[0] for p in points], [p[1] for p in points], "o-", label=name)
        for cost, error, label in points:
            ax.annotate(label, (cost, error), textcoords="offset points", xytext=(4, 4), fontsize=8,
                        color=line.get_color())
    ax.set_xlabel("wall time per simulated second [s] (1 thread)")
    ax.set_ylabel("error against Turek & Hron [%]")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1))  # beside the axes: it hid points inside
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
