#!/usr/bin/python3
"""SPHERIC Test 2, the 3D dam break against a box (cases/dam_break_obstacle_3d.toml), against the
experiment of Kleefsman et al. (2005) in ../shared/reference/spheric_test2_3d_dam_break_obstacle: per
run, the RMSE of each water level H1-H4 and pressure P1-P8 over the run's time up to 6 s, and the first
pressure peak at P1 (its value and time in the first second, raw and as a 10 ms mean) and P1's impulse over
0.1 s from the water's arrival. Optionally a figure of every gauge, and a
Pareto figure of the errors against the cost (core-seconds).

  /usr/bin/python3 scripts/validate/dam_break_3d_report.py LABEL=RUN [LABEL=RUN ...] [--figure PNG] [--pareto PNG]

The pressures are compared as sampled: the experiment's every 1 ms, the runs' every fluid step (2-3 ms).
"""
import argparse
import os
import sys

import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from report_common import ROOT, plt, read_probes, summary, table

REFERENCE = os.path.join(os.path.dirname(ROOT), "shared", "reference", "spheric_test2_3d_dam_break_obstacle")
LEVELS = [f"H{k}" for k in range(1, 5)]
PRESSURES = [f"P{k}" for k in range(1, 9)]
END = 6.0  # [s]: the span the issue compares
FIRST_IMPACT = 1.0  # [s]: P1's first peak is the largest pressure before this
PEAK_WINDOW = 0.01  # [s]: the centred moving average whose first peak is given beside the raw one
IMPULSE_SPAN = 0.1  # [s]: P1's impulse is its integral over this span from its arrival (above 1 kPa)


def experiment():
    """{gauge: (t, value)} of the experiment; levels in m, pressures in Pa."""
    out = {}
    for name, gauges in (("water_level.dat", LEVELS), ("pressure.dat", PRESSURES)):
        data = np.loadtxt(os.path.join(REFERENCE, name))
        out.update({g: (data[:, 0], data[:, k + 1]) for k, g in enumerate(gauges)})
    return out


def rmse(t, u, ref_t, ref_u):
    """RMSE of u(t) against the experiment's samples inside the run's time range and the first END s."""
    inside = (ref_t >= t[0]) & (ref_t <= min(t[-1], END))
    return float(np.sqrt(np.mean((np.interp(ref_t[inside], t, u) - ref_u[inside]) ** 2)))


def spacing(run):
    """The run's dx, from its case.resolved.toml."""
    with open(os.path.join(run, "case.resolved.toml")) as f:
        return next(float(line.split("=")[1]) for line in f if line.startswith("dx ="))


def first_peak(t, p):
    """(value, time) of the largest p before FIRST_IMPACT."""
    before = t < FIRST_IMPACT
    k = int(np.argmax(p[before]))
    return float(p[before][k]), float(t[before][k])


def impulse(t, p):
    """The integral of p over IMPULSE_SPAN from the first time p exceeds 1 kPa (the water's arrival)."""
    start = t[np.argmax(p > 1e3)]
    grid = np.linspace(start, start + IMPULSE_SPAN, 2001)
    return float(np.trapz(np.interp(grid, t, p), grid))


def moving_average(t, p):
    """p averaged over PEAK_WINDOW centred on each sample (sampled evenly, as the runs' steps are not)."""
    grid = np.arange(t[0], t[-1], 5e-4)
    on_grid = np.interp(grid, t, p)
    half = int(round(0.5 * PEAK_WINDOW / 5e-4))
    kernel = np.ones(2 * half + 1)
    return grid, np.convolve(on_grid, kernel, mode="same") / np.convolve(np.ones_like(grid), kernel, mode="same")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=RUN_FOLDER")
    ap.add_argument("--figure", help="write the gauges' histories here")
    ap.add_argument("--pareto", help="write the errors against wall time here")
    args = ap.parse_args()
    exp = experiment()
    peak_exp, at_exp = first_peak(*exp["P1"])
    mean_peak_exp, mean_at_exp = first_peak(*moving_average(*exp["P1"]))
    impulse_exp = impulse(*exp["P1"])

    series = []
    for label, run in (r.split("=", 1) for r in args.runs):
        d, s = read_probes(run), summary(run) | {"dx": spacing(run)}
        t = d["time"]
        gauges = {g: d[f"{g}.h"] for g in LEVELS} | {g: d[f"{g}.p"] for g in PRESSURES}
        errors = {g: rmse(t, gauges[g], *exp[g]) for g in LEVELS + PRESSURES}
        series.append((label, t, gauges, errors, s, first_peak(t, gauges["P1"]),
                       first_peak(*moving_average(t, gauges["P1"])) + (impulse(t, gauges["P1"]),)))

    print(f"Experiment: P1's first peak {peak_exp / 1e3:.2f} kPa at {at_exp:.3f} s; its {1e3 * PEAK_WINDOW:.0f} ms mean "
          f"peaks at {mean_peak_exp / 1e3:.2f} kPa at {mean_at_exp:.3f} s; its impulse over {IMPULSE_SPAN} s from its "
          f"arrival is {impulse_exp:.0f} Pa s.\n")
    header = ["run", "dx [m]", "particles (water / wall)", "simulated [s]", "wall [s]"] + [
        f"{g} [mm]" for g in LEVELS] + ["P1 first peak [kPa] (at s)", "vs experiment",
                                    f"its {1e3 * PEAK_WINDOW:.0f} ms mean [kPa] (at s)", "vs experiment's",
                                    f"P1 impulse over {IMPULSE_SPAN} s [Pa s]", "vs experiment's"]
    table(header, [[label, f"{s['dx']:.4g}",
                    f"{s['particles']['fluid']:,} / {s['particles']['wall']:,}", f"{s['simulated_time']:.2f}",
                    f"{s['wall_time_s']:.0f}"] + [f"{1e3 * e[g]:.1f}" for g in LEVELS] +
                   [f"{p[0] / 1e3:.2f} ({p[1]:.3f})", f"{100 * (p[0] - peak_exp) / peak_exp:+.1f} %",
                    f"{m[0] / 1e3:.2f} ({m[1]:.3f})", f"{100 * (m[0] - mean_peak_exp) / mean_peak_exp:+.1f} %",
                    f"{m[2]:.0f}", f"{100 * (m[2] - impulse_exp) / impulse_exp:+.1f} %"]
                   for label, t, _, e, s, p, m in series])
    print()
    table(["run"] + [f"{g} [kPa]" for g in PRESSURES],
          [[label] + [f"{e[g] / 1e3:.2f}" for g in PRESSURES] for label, _, _, e, _, _, _ in series])

    if args.figure:
        fig, axes = plt.subplots(3, 4, figsize=(16, 9), sharex=True)
        for ax, g in zip(axes.flat, LEVELS + PRESSURES):
            scale = 1.0 if g in LEVELS else 1e-3
            ax.plot(exp[g][0], exp[g][1] * scale, "k-", lw=0.7, label="experiment (Kleefsman 2005)")
            for label, t, gauges, *_ in series:
                ax.plot(t, gauges[g] * scale, lw=1.0, label=label)
            ax.set_title(g, fontsize=9)
            ax.set_ylabel("water level [m]" if g in LEVELS else "pressure [kPa]", fontsize=8)
            ax.set_xlim(0, END)
            ax.grid(alpha=0.3)
        for ax in axes[-1]:
            ax.set_xlabel("t [s]")
        axes[0, 0].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=110)
        plt.close(fig)
        print(f"\nfigure: {os.path.relpath(args.figure, ROOT)}")
    if args.pareto:
        # Cost as core-seconds (wall time x threads): the runs may use different thread counts. Runs
        # over the whole 6 s only (a shorter run's early steps are longer than the average).
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        for label, _, _, e, s, p, _ in series:
            if s["simulated_time"] < END * (1 - 1e-6):
                continue
            cost = s["wall_time_s"] * s["performance"]["threads"]
            for ax, error in ((axes[0], 1e3 * np.mean([e[g] for g in LEVELS])),
                              (axes[1], 100 * abs(p[0] - peak_exp) / peak_exp)):
                ax.plot(cost, error, "o")
                ax.annotate(label, (cost, error), fontsize=8)
        axes[0].set_ylabel("mean RMSE of H1-H4 over 6 s [mm]")
        axes[1].set_ylabel("|P1 first peak - experiment| [%]")
        for ax in axes:
            ax.set_xscale("log")
            ax.set_xlabel("core-seconds for 6 s (wall x threads)")
            ax.grid(alpha=0.3, which="both")
        fig.tight_layout()
        fig.savefig(args.pareto, dpi=110)
        plt.close(fig)
        print(f"pareto: {os.path.relpath(args.pareto, ROOT)}")


if __name__ == "__main__":
    main()
