#!/usr/bin/python3
"""Tables and figures of the ISPH fluid validation (docs/VALIDATION.md): hydrostatic tank, dam
break, Couette flow and a performance summary.

Reads the run folders written by `isph run` under --runs (probes.csv, summary.json,
snapshots/snapshot_NNNNN.h5) and the dam-break data under --reference; writes PNG figures into
--figures and prints markdown tables to stdout. Folders without a finished run (no summary.json,
or one older than probes.csv, left by an earlier run) are skipped with a note on stderr.

  /usr/bin/python3 scripts/validate/fluid_report.py [--runs DIR] [--figures DIR] [--reference DIR]
                                            [--only hydrostatic,dam_break,couette,performance]
"""
import argparse
import math
import os
import sys

import matplotlib.pyplot as plt
import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from report_common import (ROOT, closest, finished_run, fmt, pct, read_probes, read_snapshot, run_state, save,
                           snapshot_list, summary, table)

RHO, G = 1000.0, 9.81
TANK_H = 1.0  # hydrostatic tank depth [m]
# Dam break: a column a wide and 2a high, dx = a/40, in a tank 4a wide.
DB_A = 0.146
DB_DX = DB_A / 40
DB_VARIANTS = ("ops", "xu", "none")
DB_P = RHO * G * 2 * DB_A  # hydrostatic pressure at the foot of the initial column
DB_REFERENCES = (("mm_data_1", "Martin & Moyce, a = 1.125 in", "s"),
                 ("mm_data_2", "Martin & Moyce, a = 2.25 in", "D"),
                 ("ko_data", "Koshizuka & Oka, experiment", "o"),
                 ("ko_mps_data", "Koshizuka & Oka, MPS", "x"))
DB_SNAPSHOT_TAUS = (1, 2.5, 4, 6, 8)  # t sqrt(g/a) of the snapshot columns
# Couette flow: plates at y = 0 and y = H, the upper one moving at U from t = 0.
CO_H, CO_U, CO_NU = 1e-3, 1.25e-5, 1e-6
CO_N = (10, 20, 40)  # H/dx
CO_TIMES = (0.05, 0.1, 0.2, 0.5, 1.0)
PHASES = ("neighbours", "predictor", "free_surface", "ppe_assembly", "ppe_solve", "projection",
          "shifting", "output", "setup")


# ----------------------------------------------------------------------------------------------
# Hydrostatic tank


def hydrostatic(args):
    print("\n### Hydrostatic tank\n")
    run = finished_run(args.runs, "hydrostatic_tank")
    if run is None:
        print("_no finished run_")
        return
    d, s = read_probes(run), summary(run)
    t = d["time"]
    rgh, c = RHO * G * TANK_H, math.sqrt(G * TANK_H)
    late = t >= 3.0
    rows = []
    for probe, y in (("bottom", 0.001), ("mid", 0.5)):
        p, ref = d[f"{probe}.p"][late], RHO * G * (TANK_H - y)  # hydrostatic p = rho g (H - y)
        rows.append([f"mean {probe}.p, t ≥ 3 s [Pa]", fmt(p.mean()), fmt(ref), f"{pct(p.mean(), ref):+.3g} %"])
        rows.append([f"std {probe}.p, t ≥ 3 s / ρgH", f"{100 * p.std() / rgh:.3g} %", "-", "-"])
    umax = d["fastest.u"][t >= 1.0].max()
    rows.append(["max fastest.u, t ≥ 1 s / √(gH)", f"{100 * umax / c:.3g} %", "-", "-"])
    table(["quantity", "ISPH", "reference", "error"], rows)
    print(f"\nRun: {s['status']} ({s['message']}), t = {t[-1]:.3g} s, wall time {s['wall_time_s']:.3g} s.")

    fig, axs = plt.subplots(1, 3, figsize=(14, 4), layout="constrained", gridspec_kw={"width_ratios": [1.2, 1.2, 1]})
    for probe, y in (("bottom", 0.001), ("mid", 0.5)):
        line, = axs[0].plot(t, d[f"{probe}.p"] / rgh, lw=1, label=f"{probe}.p (y = {y} m)")
        axs[0].axhline((TANK_H - y) / TANK_H, color=line.get_color(), ls="--", lw=0.8)
    axs[0].set_xlabel("t [s]")
    axs[0].set_ylabel("p / ρgH")
    axs[0].legend(fontsize=8, title="dashed: ρg(H - y)", title_fontsize=8)
    axs[1].semilogy(t[t > 0], d["fastest.u"][t > 0] / c, lw=1, label="fastest fluid particle")
    axs[1].axhline(0.01, color="k", ls="--", lw=0.8, label="1 %")
    axs[1].set_xlabel("t [s]")
    axs[1].set_ylabel("max |u| / √(gH)")
    axs[1].legend(fontsize=8)
    snaps = snapshot_list(run)
    if snaps:
        h = read_snapshot(snaps[-1][1])
        x, p, wall = h["position"], h["pressure"], h["kind"] == 1
        norm = plt.Normalize(0, rgh)
        axs[2].scatter(x[wall, 0], x[wall, 1], s=14, c=p[wall], norm=norm, edgecolors="0.5", linewidths=0.5)
        sc = axs[2].scatter(x[h["kind"] == 0, 0], x[h["kind"] == 0, 1], s=14, c=p[h["kind"] == 0], norm=norm, lw=0)
        fig.colorbar(sc, ax=axs[2], label="p [Pa]")
        axs[2].set_aspect("equal")
        axs[2].set_title(f"t = {snaps[-1][0]:.3g} s (walls grey-edged)", fontsize=9)
    else:
        axs[2].axis("off")
    fig.suptitle("Hydrostatic tank: pressure and spurious velocity")
    save(fig, args, "fluid_hydrostatic.png")


# ----------------------------------------------------------------------------------------------
# Dam break


def clumped_fraction(x, r):
    """Fraction of the points whose nearest other point is closer than r: cell hashing with cells
    of size r, so every such pair lies in the same or adjacent cells (3 x 3 block in 2D)."""
    cell = np.floor(x / r).astype(np.int64)
    cell -= cell.min(axis=0) - 1  # indices >= 1, so neighbour cells stay >= 0
    ny = cell[:, 1].max() + 2
    key = cell[:, 0] * ny + cell[:, 1]
    order = np.argsort(key)
    sorted_key = key[order]
    close = np.zeros(len(x), dtype=bool)
    for ox in (-1, 0, 1):
        for oy in (-1, 0, 1):
            target = key + ox * ny + oy
            lo = np.searchsorted(sorted_key, target, "left")
            count = np.searchsorted(sorted_key, target, "right") - lo
            # pairs (i, j): i repeated count[i] times, j running over the points of the cell
            i = np.repeat(np.arange(len(x)), count)
            j = order[np.repeat(lo - np.cumsum(count) + count, count) + np.arange(count.sum())]
            hit = (i != j) & (np.sum((x[i] - x[j]) ** 2, axis=1) < r * r)
            close[i[hit]] = True
    return float(close.mean())


def highpass(t, p, window):
    """p minus its centred moving average over `window` seconds."""
    n = max(1, int(round(window / np.median(np.diff(t)))))
    kernel = np.ones(n)
    return p - np.convolve(p, kernel, "same") / np.convolve(np.ones_like(p), kernel, "same")


def dam_break_references(args):
    refs = []
    for key, label, marker in DB_REFERENCES:
        path = os.path.join(args.reference, "dam_break_2d", "pysph", f"pysph_db_exp_data_{key}.txt")
        if os.path.exists(path):
            refs.append((label, marker, np.loadtxt(path, comments="#", ndmin=2)))
        else:
            print(f"note: {path}: missing, skipped", file=sys.stderr)
    return refs


def dam_break(args):
    print("\n### Dam break\n")
    runs = {v: r for v in DB_VARIANTS if (r := finished_run(args.runs, f"dam_break_{v}"))}
    if not runs:
        print("_no finished run_")
        return
    refs = dam_break_references(args)
    front_rows, run_rows = [], []
    fig_front, ax_front = plt.subplots(figsize=(7, 4.5), layout="constrained")
    fig_p, ax_p = plt.subplots(figsize=(8, 4), layout="constrained")
    for v, run in runs.items():
        d, s = read_probes(run), summary(run)
        t = d["time"]
        T, tau = t * math.sqrt(2 * G / DB_A), t * math.sqrt(G / DB_A)
        Z = (d["front.x"] + DB_DX / 2) / DB_A  # front.x is a particle centre: add half a spacing
        cells = []
        for _, _, ref in refs:
            # reference points before the front reaches the right wall (Z = 4) and within the run
            m = (ref[:, 1] <= 3.8) & (ref[:, 0] <= T[-1])
            err = np.interp(ref[m, 0], T, Z) - ref[m, 1]
            cells.append(f"{fmt(np.sqrt(np.mean(err ** 2)), 3)} ({m.sum()})" if m.any() else "-")
        hit = np.nonzero(Z >= 3.95)[0]
        impact = T[hit[0]] if len(hit) else math.nan
        front_rows.append([v] + cells + [fmt(impact, 3), fmt(impact / math.sqrt(2), 3)])
        # pressure noise: the part of wall_p faster than 0.02 s, for 2.5 <= t sqrt(g/a) <= 8
        noise = highpass(t, d["wall_p.p"], 0.02)[(tau >= 2.5) & (tau <= 8)]
        snaps = snapshot_list(run)
        clumped = "-"
        if snaps:
            h = read_snapshot(snaps[-1][1])
            x = h["position"][h["kind"] == 0, :2]
            tau_last = snaps[-1][0] * math.sqrt(G / DB_A)
            clumped = f"{100 * clumped_fraction(x, 0.5 * DB_DX):.3g} % (at {tau_last:.3g})"
        run_rows.append([v, s["status"], s["message"], fmt(tau[-1], 3), fmt(d["fastest.u"].max(), 3),
                         fmt(s["wall_time_s"], 3), fmt(noise.std() / DB_P if noise.size else math.nan, 3), clumped])
        ax_front.plot(T, Z, lw=1.2, label=f"ISPH, shifting {v}")
        ax_p.plot(tau, d["wall_p.p"] / DB_P, lw=0.8, label=f"shifting {v}")
    ref_names = [label for label, _, _ in refs]
    table(["shifting"] + [f"RMSE Z: {n}" for n in ref_names] + ["impact T", "impact t√(g/a)"], front_rows)
    print("\nZ = (front.x + dx/2)/a against T = t√(2g/a); RMSE over the reference points with Z ≤ 3.8"
          " that the run reached (their number in brackets). Impact: first Z ≥ 3.95.\n")
    table(["shifting", "status", "message", "end t√(g/a)", "max fastest.u [m/s]", "wall time [s]",
           "wall_p noise / ρg2a", "clumped (< dx/2)"], run_rows)
    print("\nwall_p noise: standard deviation of wall_p minus its 0.02 s moving average for"
          " 2.5 ≤ t√(g/a) ≤ 8 (or the end). No pressure reference: Buchner's data are for another"
          " geometry. Clumped: share of fluid particles with a fluid neighbour closer than dx/2,"
          " last snapshot (its t√(g/a) in brackets).")

    for label, marker, ref in refs:
        ax_front.plot(ref[:, 0], ref[:, 1], marker, ls="none", mfc="none", color="k", ms=5, label=label)
    TT = np.linspace(0, 3.5, 50)
    ax_front.plot(TT, 1 + 2 * TT, "k:", lw=0.8, label="Ritter, dry bed: Z = 1 + 2T")
    ax_front.axhline(4.0, color="0.6", lw=0.8)
    ax_front.set(xlim=(0, 3.5), ylim=(1, 4.2), xlabel="T = t√(2g/a)", ylabel="Z = x_front / a",
                 title="Dam break: surge front")
    ax_front.legend(fontsize=8)
    save(fig_front, args, "fluid_dam_break_front.png")
    ax_p.set(xlabel="t√(g/a)", ylabel="p / ρg2a", title="Dam break: pressure on the right wall at y = 0.1a")
    ax_p.legend(fontsize=8)
    save(fig_p, args, "fluid_dam_break_pressure.png")
    dam_break_snapshots(args, runs)


def dam_break_snapshots(args, runs):
    """Grid of snapshots: rows = variants, columns = the snapshots closest to DB_SNAPSHOT_TAUS."""
    fig, axs = plt.subplots(len(runs), len(DB_SNAPSHOT_TAUS), figsize=(14, 2.9 * len(runs) + 0.3),
                            squeeze=False, layout="constrained")
    norm = plt.Normalize(0, DB_P)
    for row, (v, run) in zip(axs, runs.items()):
        snaps, shown = snapshot_list(run), set()
        for ax, target in zip(row, DB_SNAPSHOT_TAUS):
            ax.set(xlim=(0, 0.6), ylim=(0, 0.6), aspect="equal")
            ax.tick_params(labelsize=7)
            i = closest(snaps, target / math.sqrt(G / DB_A)) if snaps else None
            if i is None or i in shown:  # the run ended before this time
                ax.axis("off")
                continue
            shown.add(i)
            h = read_snapshot(snaps[i][1])
            x, fluid, wall = h["position"], h["kind"] == 0, h["kind"] == 1
            ax.scatter(x[wall, 0], x[wall, 1], s=0.8, c="0.75", lw=0)
            ax.scatter(x[fluid, 0], x[fluid, 1], s=0.8, c=h["pressure"][fluid], norm=norm, lw=0)
            ax.set_title(f"{v}: t√(g/a) = {snaps[i][0] * math.sqrt(G / DB_A):.2f}", fontsize=9)
    fig.colorbar(plt.cm.ScalarMappable(norm=norm), ax=axs, label="p [Pa]", shrink=0.8)
    save(fig, args, "fluid_dam_break_snapshots.png")


# ----------------------------------------------------------------------------------------------
# Couette flow


def couette_exact(y, t):
    """Startup Couette flow, u/U = y/H + sum_n 2 (-1)^n / (n pi) sin(n pi y/H) exp(-nu n^2 pi^2 t / H^2)."""
    n = np.arange(1, 401)[:, None]
    eta = np.asarray(y)[None, :] / CO_H
    terms = 2 * (-1.0) ** n / (n * np.pi) * np.sin(n * np.pi * eta) * np.exp(-CO_NU * (n * np.pi) ** 2 * t / CO_H ** 2)
    return eta[0] + terms.sum(axis=0)


def couette(args):
    print("\n### Couette flow\n")
    errors, profiles = {}, {}  # errors[N][t] = (L_inf, L2); profiles[N][t] = (time, y, u/U)
    for n in CO_N:
        run = finished_run(args.runs, f"couette_{n}")
        snaps = snapshot_list(run) if run else []
        if not snaps:
            continue
        errors[n], profiles[n] = {}, {}
        for target in CO_TIMES:
            time, path = snaps[closest(snaps, target)]
            h = read_snapshot(path)
            fluid = h["kind"] == 0
            y, u = h["position"][fluid, 1], h["velocity"][fluid, 0] / CO_U
            e = u - couette_exact(y, time)
            errors[n][target] = (np.abs(e).max(), np.sqrt(np.mean(e ** 2)))  # L_inf, L2 (RMS) of u_x/U
            profiles[n][target] = (time, y, u)
    if not errors:
        print("_no finished run_")
        return
    table(["H/dx", "dx [m]"] + [f"t = {t} s: L∞ / L2" for t in CO_TIMES],
          [[n, fmt(CO_H / n, 3)] + ["{:.2e} / {:.2e}".format(*errors[n][t]) for t in CO_TIMES] for n in errors])
    print("\nErrors of u_x/U over the fluid particles against the series solution (400 terms), at the"
          " snapshot closest to each time.\n")
    for target in CO_TIMES[:2]:
        if len(errors) < 2:
            print(f"- t = {target} s: only H/dx = {', '.join(map(str, errors))}, no convergence order")
            continue
        dx = np.array([CO_H / n for n in errors])
        l2 = np.array([errors[n][target][1] for n in errors])
        order = np.polyfit(np.log(dx), np.log(l2), 1)[0]  # least-squares slope of log L2 against log dx
        print(f"- t = {target} s: order of L2 {order:.2f} (H/dx = {', '.join(map(str, errors))})")

    n = 20 if 20 in profiles else next(iter(profiles))
    fig, ax = plt.subplots(figsize=(6, 4.5), layout="constrained")
    eta = np.linspace(0, 1, 200)
    for target, (time, y, u) in profiles[n].items():
        dots, = ax.plot(u, y / CO_H, ".", ms=3)
        ax.plot(couette_exact(eta * CO_H, time), eta, color=dots.get_color(), lw=1, label=f"t = {time:.3g} s")
    ax.set(xlabel="u_x / U", ylabel="y / H", title=f"Couette flow, H/dx = {n}: particles (dots), series (lines)")
    ax.legend(fontsize=8)
    save(fig, args, "fluid_couette_profiles.png")

    fig, ax = plt.subplots(figsize=(6, 4.5), layout="constrained")
    dx = np.array([CO_H / n for n in errors])
    for target in CO_TIMES:
        ax.loglog(dx, [errors[n][target][1] for n in errors], "o-", label=f"t = {target} s")
    e0 = 0.4 * errors[next(iter(errors))][CO_TIMES[0]][1]  # guides below the t = 0.05 s curve
    ax.loglog(dx, e0 * (dx / dx[0]) ** 2, "k--", lw=0.8, label="slope 2")
    ax.loglog(dx, e0 * (dx / dx[0]), "k:", lw=0.8, label="slope 1")
    ax.set(xlabel="dx [m]", ylabel="L2 error of u_x / U", title="Couette flow: convergence")
    ax.legend(fontsize=8)
    save(fig, args, "fluid_couette_convergence.png")


# ----------------------------------------------------------------------------------------------
# Performance


def performance(args):
    print("\n### Performance\n")
    rows = []
    for name in sorted(os.listdir(args.runs)):
        run = os.path.join(args.runs, name)
        if not os.path.exists(os.path.join(run, "summary.json")):
            continue
        if run_state(run) != "finished":
            print(f"note: {run}: in progress, skipped", file=sys.stderr)
            continue
        s = summary(run)
        if s.get("particles", {}).get("fluid", 0) <= 0:
            continue
        phases = [s["phases"].get(p, 0.0) for p in PHASES]
        total = sum(phases) or math.nan
        rows.append([name, s["status"], s["particles"]["fluid"], s["particles"]["wall"], s["steps"]["fluid"],
                     fmt(s["wall_time_s"], 3), f'{s["performance"]["fluid_particle_steps_per_s"]:.0f}',
                     s["ppe"]["solver"], fmt(s["ppe"]["mean_iterations"], 3)]
                    + [f"{100 * p / total:.1f}" for p in phases])
    if not rows:
        print("_no finished fluid run_")
        return
    table(["run", "status", "fluid", "wall", "steps", "wall time [s]", "particle-steps/s", "PPE solver",
           "mean its"] + [f"{p} [%]" for p in PHASES], rows)


SECTIONS = {"hydrostatic": hydrostatic, "dam_break": dam_break, "couette": couette, "performance": performance}


def main():
    parser = argparse.ArgumentParser(description="Tables and figures of the ISPH fluid validation.")
    parser.add_argument("--runs", default=os.path.join(ROOT, "runs"), help="folder of the run folders")
    parser.add_argument("--figures", default=os.path.join(ROOT, "docs", "figures"), help="where the PNGs go")
    parser.add_argument("--reference", default=os.path.join(os.path.dirname(ROOT), "shared", "reference"),
                        help="reference data (dam_break_2d/pysph/...)")
    parser.add_argument("--only", default=",".join(SECTIONS), help="comma-separated sections: " + ",".join(SECTIONS))
    args = parser.parse_args()
    only = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = [s for s in only if s not in SECTIONS]
    if unknown:
        parser.error(f"unknown section(s) {', '.join(unknown)}; choose from {', '.join(SECTIONS)}")
    if not os.path.isdir(args.runs):
        parser.error(f"{args.runs}: not a folder")
    for name in only:
        SECTIONS[name](args)


if __name__ == "__main__":
    main()
