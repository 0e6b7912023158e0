#!/usr/bin/python3
"""Tables and figures of the structural validation (docs/VALIDATION.md) from the runs written by
scripts/validate/validate_structure.sh. Prints markdown tables, writes docs/figures/*.png and
<runs>/structure_metrics.json.

  /usr/bin/python3 scripts/validate/structure_report.py runs/validation                # every section
  /usr/bin/python3 scripts/validate/structure_report.py runs/validation cantilever     # sections named
"""
import glob
import json
import math
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FIG = os.path.join(ROOT, "docs", "figures")

# Analytical references (../shared/reference/README.md).
CANTILEVER_L = 0.1
ELASTICA_V, ELASTICA_H = 0.30172 * CANTILEVER_L, 0.05643 * CANTILEVER_L
LINEAR_V = 0.3359e-3
# The same cantilever as a 2D plane-stress St. Venant-Kirchhoff continuum, clamped over its end face
# (scripts/reference/fe_beam.py cantilever, Q9 elements, 80 x 8): what the particle solution should converge to.
FE_V, FE_H = 30.386e-3, 5.7145e-3
FE_LINEAR_V = 0.33529e-3
PLATE_OMEGA = 24.72
PLATE_PERIOD = 2 * math.pi / PLATE_OMEGA        # 0.2541 s
PLATE_AMPLITUDE = 0.02306
# Turek & Hron (2006), CSM3 at the finest level: mean +/- amplitude [m], frequency [Hz].
CSM3 = {"ux": (-14.305e-3, 14.305e-3), "uy": (-63.607e-3, 65.160e-3), "frequency": 1.0995}
SEED_PLATE = {10: (5.68, 6.96), 20: (3.33, 4.35), 40: (2.36, 3.48)}  # period, amplitude errors [%]


def load(run, name):
    path = os.path.join(run, name)
    return np.genfromtxt(path, delimiter=",", names=True) if os.path.exists(path) else None


def summary(run):
    with open(os.path.join(run, "summary.json")) as f:
        return json.load(f)


def final_value(d, field, fraction=0.05):
    """Mean over the last `fraction` of the run (the damped static state)."""
    t = d["time"]
    return float(np.mean(d[field][t >= t[-1] * (1 - fraction)]))


def upward_crossings(t, y, mean=0.0):
    y = y - mean
    i = np.where((y[:-1] < 0) & (y[1:] >= 0))[0]
    return np.array([t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k]) for k in i])


def odd_even_indicator(run):
    """RMS second difference of u_x along particle rows over the RMS first difference: about 1
    when the odd-even (hourglass) mode dominates, a few per cent for a smooth field."""
    files = sorted(glob.glob(os.path.join(run, "snapshots", "*.h5")))
    if not files:
        return float("nan")
    with h5py.File(files[-1], "r") as h:
        X, u = h["reference_position"][:], h["displacement"][:]
    values = []
    for y in np.unique(np.round(X[:, 1], 9)):
        row = np.abs(X[:, 1] - y) < 1e-9
        order = np.argsort(X[row, 0])
        xs, ux = X[row][order, 0], u[row][order, 0]
        ux = ux[xs > 0.01]
        if len(ux) > 4:
            values.append(np.sqrt(np.mean(np.diff(ux, 2) ** 2)) / np.sqrt(np.mean(np.diff(ux) ** 2)))
    return float(np.mean(values))


def pct(x, ref):
    return 100.0 * (x - ref) / abs(ref)


# What each discretisation of the cantilever is called in runs/validation (scripts/validate/validate_structure.sh).
CANTILEVER_VARIANTS = (
    ("", "columns on the end faces, cell quadrature (the case as shipped)"),
    ("node_point_", "columns on the end faces, one-point rule"),
    ("cc_cell_", "cell centres, cell quadrature"),
    ("cc_point_", "cell centres, one-point rule (the earlier default)"),
)


def cantilever_tip(runs, name):
    """(delta_v, delta_h, wall time) of a finished cantilever run, or None."""
    run = os.path.join(runs, name)
    d = load_probe(run)
    if d is None:
        return None
    return -final_value(d, "tipuy"), -final_value(d, "tipux"), summary(run)["wall_time_s"]


def cantilever(runs, metrics):
    print("\n### Cantilever (the case as shipped)\n")
    print("| particles through T | load | tip δ_v [mm] | reference [mm] | error | 2D continuum [mm] | error | "
          "tip δ_h [mm] | reference [mm] | error | 2D continuum [mm] | error | wall time [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for load, prefix in (("elastica", "cantilever_N"), ("linear", "cantilever_linear_N")):
        for n in (5, 10, 17):
            tip = cantilever_tip(runs, f"{prefix}{n}")
            if tip is None:
                continue
            v, h, wall = tip
            if load == "elastica":
                print(f"| {n} | 1750 N | {v*1e3:.3f} | {ELASTICA_V*1e3:.3f} | {pct(v, ELASTICA_V):+.2f} % | {FE_V*1e3:.3f} | "
                      f"{pct(v, FE_V):+.2f} % | {h*1e3:.3f} | {ELASTICA_H*1e3:.3f} | {pct(h, ELASTICA_H):+.2f} % | "
                      f"{FE_H*1e3:.3f} | {pct(h, FE_H):+.2f} % | {wall:.1f} |")
            else:
                print(f"| {n} | 17.5 N | {v*1e3:.4f} | {LINEAR_V*1e3:.4f} | {pct(v, LINEAR_V):+.2f} % | {FE_LINEAR_V*1e3:.4f} | "
                      f"{pct(v, FE_LINEAR_V):+.2f} % | {h*1e3:.5f} | - | - | - | - | {wall:.1f} |")
            metrics[f"cantilever_{load}_N{n}"] = {"tip_v": v, "tip_h": h, "error_v_pct": pct(v, ELASTICA_V if load == "elastica" else LINEAR_V),
                                                 "wall_s": wall}
    print("\n### Cantilever: what each discretisation choice does (tip δ_v error against the reference)\n")
    print("| discretisation | load | 5 particles | 10 | 17 |")
    print("|---|---|---|---|---|")
    fig, axs = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, (load, prefix, ref, continuum) in zip(axs, (("elastica", "cantilever_N", ELASTICA_V, FE_V),
                                                        ("linear", "cantilever_linear_N", LINEAR_V, FE_LINEAR_V))):
        for (variant, label), style in zip(CANTILEVER_VARIANTS, ("s-", "o-", "s--", "o--")):
            points = [(n, cantilever_tip(runs, f"{variant}{prefix}{n}")) for n in (5, 10, 17)]
            points = [(n, pct(tip[0], ref)) for n, tip in points if tip is not None]
            if not points:
                continue
            cells = {n: f"{e:+.2f} %" for n, e in points}
            print(f"| {label} | {load} | " + " | ".join(cells.get(n, "-") for n in (5, 10, 17)) + " |")
            ax.plot(*zip(*points), style, label=label)
        ax.axhline(pct(continuum, ref), color="tab:red", ls=":", lw=1.2, label="2D continuum (Q9 finite elements)")
        ax.axhspan(-1.5, 1.5, color="0.92", label="±1.5 % (acceptance)")
        ax.axhline(0, color="k", lw=0.8)
        ax.set_xlabel("particles through the thickness")
        ax.set_title(f"{load} load: reference {ref*1e3:.4g} mm")
    axs[0].set_ylabel("tip δ_v error against the reference [%]")
    axs[1].legend(fontsize=7)
    save(fig, "cantilever_convergence.png")
    # deflection history at N = 10
    d = load_probe(os.path.join(runs, "cantilever_N10"))
    if d is not None:
        fig, ax = plt.subplots(figsize=(5.5, 4))
        ax.plot(d["time"] * 1e3, -d["tipuy"] * 1e3, label="TLSPH δ_v, 10 particles")
        ax.plot(d["time"] * 1e3, -d["tipux"] * 1e3, label="TLSPH δ_h")
        ax.axhline(ELASTICA_V * 1e3, color="k", ls="--", lw=0.8, label="elastica")
        ax.axhline(ELASTICA_H * 1e3, color="k", ls="--", lw=0.8)
        ax.axhline(33.59, color="r", ls=":", lw=0.8, label="linear theory (33.59 mm)")
        ax.set_xlabel("t [ms]")
        ax.set_ylabel("tip displacement [mm]")
        ax.legend(fontsize=8)
        ax.set_title("Cantilever under a ramped end load (damped)")
        save(fig, "cantilever_history.png")


def load_probe(run):
    """The probes of a finished run (one with summary.json), else None."""
    return load(run, "probes.csv") if os.path.exists(os.path.join(run, "summary.json")) else None


def plate_metrics(run):
    """Period, amplitude, RMSE against the thin-plate solution and energy drift of a plate run, or None."""
    d, e = load_probe(run), load(run, "energy.csv")
    if d is None:
        return None
    t, y = d["time"], d["tipuy"]
    down = upward_crossings(t, -y)  # downward crossings of y
    period = float(np.mean(np.diff(down))) if len(down) > 1 else float("nan")
    amp = float(np.max(y))
    rmse = float(np.sqrt(np.mean((y - PLATE_AMPLITUDE * np.sin(PLATE_OMEGA * t)) ** 2)))
    drift = float((e["total"][-1] - e["total"][0]) / e["total"][0])
    return {"period": period, "period_error_pct": pct(period, PLATE_PERIOD), "amplitude": amp,
            "amplitude_error_pct": pct(amp, PLATE_AMPLITUDE), "rmse": rmse, "nrmse": rmse / (2 * PLATE_AMPLITUDE),
            "energy_drift": drift, "wall_s": summary(run)["wall_time_s"], "t": t, "y": y}


def plate(runs, metrics):
    print("\n### Oscillating plate\n")
    print("| T/dx | period [s] | t·c0/L | period error | seed | A/L | amplitude error | seed | RMSE [m] | NRMSE | energy drift | simulated | wall time [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    c0_over_L = math.sqrt(3.25e6 / 1000.0) / 0.2
    fig, ax = plt.subplots(figsize=(7, 4))
    for n in (10, 20, 40):
        m = plate_metrics(os.path.join(runs, f"op_N{n}"))
        if m is None:
            continue
        t, y = m.pop("t"), m.pop("y")
        sp, sa = SEED_PLATE[n]
        print(f"| {n} | {m['period']:.4f} | {m['period']*c0_over_L:.2f} | {m['period_error_pct']:+.2f} % | {sp} % | "
              f"{m['amplitude']/0.2:.4f} | {m['amplitude_error_pct']:+.2f} % | {sa} % | {m['rmse']:.5f} | {m['nrmse']:.4f} | "
              f"{m['energy_drift']:+.1e} | {t[-1]:.2f} s | {m['wall_s']:.0f} |")
        metrics[f"plate_N{n}"] = m
        ax.plot(t, y, lw=1, label=f"TLSPH T/dx = {n}")
    tt = np.linspace(0, 0.7, 800)
    ax.plot(tt, PLATE_AMPLITUDE * np.sin(PLATE_OMEGA * tt), "k--", lw=1, label="analytical (thin plate)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("tip u_y [m]")
    ax.legend(fontsize=8, ncol=2)
    ax.set_title("Free oscillating plate: tip displacement")
    save(fig, "plate_tip.png")
    for n in (40, 20, 10):
        e = load(os.path.join(runs, f"op_N{n}"), "energy.csv")
        if e is None:
            continue
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot(e["time"], e["structure_kinetic"], label="kinetic")
        ax.plot(e["time"], e["structure_strain"], label="strain (incl. hourglass)")
        ax.plot(e["time"], e["total"], "k", label="total")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("energy [J per m depth]")
        ax.set_title(f"Free oscillating plate, T/dx = {n}: energies (seed Fig. 11)")
        ax.legend(fontsize=8)
        save(fig, "plate_energy.png")
        break


def csm3(runs, metrics):
    print("\n### Turek-Hron CSM3\n")
    print("| T/dx | u_x(A) mean ± amplitude [mm] | reference | u_y(A) mean ± amplitude [mm] | reference | frequency [Hz] | reference | wall time [s] |")
    print("|---|---|---|---|---|---|---|---|")
    fig, axs = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    for n in (4, 8):
        run = os.path.join(runs, f"csm3_N{n}")
        d = load_probe(run)
        if d is None:
            continue
        t = d["time"]
        late = t >= t[-1] / 2
        stats = {}
        for f in ("ux", "uy"):
            y = d["A" + f][late]
            stats[f] = (0.5 * (y.max() + y.min()), 0.5 * (y.max() - y.min()))
        mean_uy = stats["uy"][0]
        cross = upward_crossings(t[late], d["Auy"][late], mean_uy)
        freq = 1.0 / float(np.mean(np.diff(cross))) if len(cross) > 1 else float("nan")
        wall = summary(run)["wall_time_s"]
        fmt = lambda m, a: f"{m*1e3:.2f} ± {a*1e3:.2f}"
        print(f"| {n} | {fmt(*stats['ux'])} | {fmt(*CSM3['ux'])} | {fmt(*stats['uy'])} | {fmt(*CSM3['uy'])} | {freq:.4f} | {CSM3['frequency']} | {wall:.0f} |")
        metrics[f"csm3_N{n}"] = {"ux": stats["ux"], "uy": stats["uy"], "frequency": freq, "wall_s": wall}
        axs[0].plot(t, d["Aux"] * 1e3, lw=1, label=f"T/dx = {n}")
        axs[1].plot(t, d["Auy"] * 1e3, lw=1, label=f"T/dx = {n}")
    for ax, f in zip(axs, ("ux", "uy")):
        m, a = CSM3[f]
        ax.axhspan((m - a) * 1e3, (m + a) * 1e3, color="0.9", label="Turek & Hron range")
        ax.set_ylabel(f"{f}(A) [mm]")
        ax.legend(fontsize=8)
    axs[1].set_xlabel("t [s]")
    axs[0].set_title("CSM3: displacement of point A")
    save(fig, "csm3.png")


def hourglass(runs, metrics):
    print("\n### Hourglass control coefficient α\n")
    print("| α | cantilever (linear) T/dx=5: error | odd-even indicator | T/dx=10: error | odd-even indicator | plate T/dx=10: period error | amplitude error | energy drift |")
    print("|---|---|---|---|---|---|---|---|")
    for a in (0, 1, 2, 5, 10):
        cells = []
        for n in (5, 10):
            run = os.path.join(runs, f"hg{a}_cantilever_linear_N{n}")
            d = load_probe(run)
            cells += ["-", "-"] if d is None else [f"{pct(-final_value(d, 'tipuy'), LINEAR_V):+.2f} %", f"{odd_even_indicator(run):.3f}"]
        m = plate_metrics(os.path.join(runs, f"hg{a}_op_N10"))
        cells += ["-", "-", "-"] if m is None else [f"{m['period_error_pct']:+.2f} %", f"{m['amplitude_error_pct']:+.2f} %",
                                                    f"{m['energy_drift']:+.1e}"]
        print(f"| {a} | " + " | ".join(cells) + " |")


def quadrature(runs, metrics):
    """Point (one-point rule) against cell quadrature of the strain energy (VALIDATION section 22)."""
    print("\n### Strain-energy quadrature: point against cell\n")
    print("| case | point | cell | cell, wall time [s] |")
    print("|---|---|---|---|")
    fig, ax = plt.subplots(figsize=(6, 4))
    for load, prefix, ref in (("elastica", "cantilever_N", ELASTICA_V), ("linear", "cantilever_linear_N", LINEAR_V)):
        for q, style in (("point", "o--"), ("cell", "s-")):
            points = []
            for n in (5, 10, 17):
                run = os.path.join(runs, f"cc_{q}_{prefix}{n}")
                d = load_probe(run)
                if d is not None:
                    points.append((n, pct(-final_value(d, "tipuy"), ref), summary(run)["wall_time_s"]))
                    metrics[f"{q}_{prefix}{n}"] = {"error_v_pct": points[-1][1], "wall_s": points[-1][2]}
            if points:
                n, err, _ = zip(*points)
                ax.plot(n, err, style, label=f"{load} load, {q}")
        for n in (5, 10, 17):
            p, c = metrics.get(f"point_{prefix}{n}"), metrics.get(f"cell_{prefix}{n}")
            if p and c:
                print(f"| cantilever, {load} load, T/dx = {n}: tip δ_v error | {p['error_v_pct']:+.2f} % | "
                      f"{c['error_v_pct']:+.2f} % | {c['wall_s']:.0f} |")
    for a in (0, 10):
        d = load_probe(os.path.join(runs, f"cell_hg{a}_cantilever_linear_N10"))
        p = load_probe(os.path.join(runs, f"hg{a}_cantilever_linear_N10"))
        if d is not None and p is not None:
            print(f"| cantilever, linear load, T/dx = 10, α = {a} | {pct(-final_value(p, 'tipuy'), LINEAR_V):+.2f} % | "
                  f"{pct(-final_value(d, 'tipuy'), LINEAR_V):+.2f} % | - |")
    p, c = plate_metrics(os.path.join(runs, "op_N10")), plate_metrics(os.path.join(runs, "cell_op_N10"))
    if p and c:
        for key, label, fmt in (("period_error_pct", "period error", "{:+.2f} %"), ("amplitude_error_pct", "amplitude error", "{:+.2f} %"),
                                ("rmse", "RMSE [m]", "{:.5f}"), ("energy_drift", "energy drift", "{:+.1e}")):
            wall = f"{c['wall_s']:.0f}" if key == "period_error_pct" else "-"
            print(f"| oscillating plate, T/dx = 10: {label} | {fmt.format(p[key])} | {fmt.format(c[key])} | {wall} |")
    ax.axhline(pct(FE_V, ELASTICA_V), color="tab:red", ls=":", lw=1, label="elastica load: 2D continuum")
    ax.axhline(pct(FE_LINEAR_V, LINEAR_V), color="tab:purple", ls=":", lw=1, label="linear load: 2D continuum")
    ax.axhspan(-1.5, 1.5, color="0.92", label="±1.5 %")
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xlabel("particles through the thickness")
    ax.set_ylabel("tip δ_v error against the reference [%]")
    ax.set_title("Cantilever on cell centres: point against cell quadrature (α = 5)")
    ax.legend(fontsize=7)
    save(fig, "cantilever_quadrature.png")


def save(fig, name):
    os.makedirs(FIG, exist_ok=True)
    fig.tight_layout()
    fig.savefig(os.path.join(FIG, name), dpi=120)
    plt.close(fig)
    print(f"<!-- figure docs/figures/{name} -->")


SECTIONS = {"cantilever": cantilever, "plate": plate, "csm3": csm3, "hourglass": hourglass, "quadrature": quadrature}


def main(argv):
    runs = argv[1] if len(argv) > 1 else "runs/validation"
    names = argv[2:] or list(SECTIONS)
    unknown = [n for n in names if n not in SECTIONS]
    if unknown:
        sys.exit(f"unknown section(s) {unknown}; sections: {list(SECTIONS)}")
    metrics = {}
    for name in names:
        SECTIONS[name](runs, metrics)
    with open(os.path.join(runs, "structure_metrics.json"), "w") as f:
        json.dump(metrics, f, indent=1)


if __name__ == "__main__":
    main(sys.argv)
