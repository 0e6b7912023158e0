#!/usr/bin/python3
"""Tables and figures of the coupled ISPH-TLSPH validation (docs/VALIDATION.md): hydrostatic plate,
elastic gate and its stability variants, the Walhorn obstacle, the Liao plate and the sloshing baffle.

Reads the run folders written by `isph run` under --runs and the gate references under --reference;
writes PNG figures into --figures and prints markdown tables to stdout. Unfinished runs are skipped
with a note on stderr.

  /usr/bin/python3 scripts/validate/coupled_report.py [--runs DIR] [--figures DIR] [--reference DIR] [--partial]
"""
import argparse
import math
import os
import sys
import tomllib

import h5py
import matplotlib.pyplot as plt
import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from report_common import (ROOT, closest, finished_run, fmt, pct, read_probes, read_snapshot, save,
                           snapshot_list, summary, table)

G = 9.81
# Hydrostatic plate (seed 001 §3.2.1): static mid-span deflection, plane strain, with the plate's weight.
PLATE = dict(L=1.0, T=0.05, H=2.0, rho_w=1000.0, rho_s=2700.0, E=67.5e9, nu=0.34)
PLATE_STATIC = (12 * G * (1 - PLATE["nu"] ** 2) * (PLATE["rho_w"] * PLATE["H"] + PLATE["rho_s"] * PLATE["T"]) *
                PLATE["L"] ** 4 / (384 * PLATE["E"] * PLATE["T"] ** 3))
# The same plate as a 2D plane-strain continuum clamped over its end faces (scripts/reference/fe_beam.py plate,
# Q9 elements, 40 x 2 to 160 x 8, extrapolated): thin-plate theory plus the plate's shear, +3.0 %.
PLATE_CONTINUUM = 7.066e-5
PLATE_RUNS = (("plate_T4", 4), ("plate_T8", 8), ("plate_T10", 10), ("plate_T12", 12))  # (folder, T/dx)
PLATE_MEAN_FROM = 0.1  # [s] the seed's averaging window starts here
# Elastic gate (Antoci et al. 2007): reference tip displacement histories.
# Rows (file key, label, marker[, time shift in s]). The PySPH run's time column is shifted by 0.05 s, as
# the plot script it was digitised for does (../shared/reference/README.md); it has no y curve.
GATE_REFS = (("khayyer_2018_isph_sph", "Khayyer et al. 2018, ISPH-SPH", "o"),
             ("yang_2012_sph_fem", "Yang et al. 2012, SPH-FEM", "s"),
             ("ng_2020_sph_vcpm_alpha_1", "Ng et al. 2020, SPH-VCPM", "^"),
             ("wcsph_pysph", "PySPH, WCSPH", "d", 0.05))
GATE_SNAPSHOT_TIMES = (0.04, 0.08, 0.12, 0.16, 0.20, 0.24)  # seed Fig. 17
COUPLED_PHASES = ("neighbours", "predictor", "free_surface", "ppe_assembly", "ppe_solve", "interaction",
                  "structure", "projection", "shifting", "wall_motion", "output", "setup")


def coupling(s):
    return s.get("performance", {}).get("coupling", {})


def run_line(s):
    c = coupling(s)
    return (f"Run: {s['status']} ({s['message']}), t = {fmt(s['simulated_time'])} s, wall time "
            f"{fmt(s['wall_time_s'], 3)} s; {s['particles']['fluid']} fluid, {s['particles']['structure']} "
            f"structure particles; {fmt(c.get('mean_substeps'), 3)} substeps and "
            f"{fmt(c.get('mean_interface_iterations'), 3)} interface iterations per fluid step; fluid "
            f"inside the structure: {c.get('fluid_inside_structure_max')}; closest fluid-structure distance "
            f"{fmt(c.get('min_fluid_structure_distance'), 3)} m.")


def phase_table(runs):
    rows = []
    for name, s in runs:
        ph = s["phases"]
        total = sum(ph.values())
        rows.append([name, fmt(s["wall_time_s"], 3)] + [f"{100 * ph.get(p, 0) / total:.1f}" for p in COUPLED_PHASES])
    table(["run", "wall [s]"] + [f"{p} %" for p in COUPLED_PHASES], rows)


def save_history(fig, ax, args, ylabel, name):
    """Labels a time-history axis, adds its legend and saves the figure."""
    ax.set_xlabel("t [s]")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save(fig, args, name)


# ----------------------------------------------------------------------------------------------


def plate(args):
    print("\n### Hydrostatic plate\n")
    found = [(name, n, run) for name, n in PLATE_RUNS if (run := finished_run(args.runs, name)) is not None]
    if not found:
        print("_no finished run_")
        return
    fig, ax = plt.subplots(figsize=(8, 4))
    rows, perf = [], []
    for name, n, run in found:
        d, s = read_probes(run), summary(run)
        t, uy = d["time"], d["midspan.uy"]
        window = t >= PLATE_MEAN_FROM
        mean = float(np.mean(uy[window])) if window.any() else math.nan
        # A restarted run (isph run --restart) carries the earlier rows but times only its own part.
        start = s.get("restart", {}).get("time", 0.0)
        wall = fmt(s["wall_time_s"], 3) + (f" (from t = {fmt(start, 3)} s)" if start > 0 else "")
        rows.append([f"T/dx = {n}", f"{fmt(t[-1], 3)} s", fmt(-mean), pct(-mean, PLATE_STATIC), pct(-mean, PLATE_CONTINUUM),
                     fmt(-uy.min()), wall, fmt(s["wall_time_s"] / (s["simulated_time"] - start), 3)])
        perf.append((name, s))
        ax.plot(t, uy * 1e6, lw=1, label=f"ISPH-TLSPH, T/dx = {n}")
    ax.axhline(-PLATE_STATIC * 1e6, color="k", ls="--", lw=1, label="static, thin-plate theory (Eq. 53)")
    ax.axhline(-PLATE_CONTINUUM * 1e6, color="tab:red", ls=":", lw=1.2, label="static, 2D continuum (finite elements)")
    save_history(fig, ax, args, "mid-span deflection u_y [µm]", "coupled_plate.png")
    print(f"\nStatic deflection (reference README, seed Eq. 53): {PLATE_STATIC:.4g} m.")
    dry = finished_run(args.runs, "plate_dry")
    if dry is not None:
        u = -read_probes(dry)["midspan.uy"][-1]
        print(f"The plate alone under the water's weight (cases/hydrostatic_plate_dry.toml, T/dx = 4, at rest): "
              f"{u:.4g} m ({pct(u, PLATE_STATIC):+.1f} %).")
    print()
    table(["resolution", "simulated", f"mean -u_y, t ≥ {PLATE_MEAN_FROM} s [m]", "error %", "against the 2D continuum %",
           "peak -u_y [m]", "wall [s]", "wall per simulated s"],
          [[r[0], r[1], r[2], f"{r[3]:+.2f}", f"{r[4]:+.2f}", r[5], r[6], r[7]] for r in rows])
    print()
    for name, s in perf:
        print(f"- {name}: " + run_line(s))
    print()
    phase_table(perf)


# ----------------------------------------------------------------------------------------------


def read_reference(path):
    data = np.loadtxt(path, delimiter=",", ndmin=2)
    return data[np.argsort(data[:, 0])]


def rmse_against(t, u, ref):
    """RMSE of u(t) against the reference points inside the run's time range."""
    inside = (ref[:, 0] >= t[0]) & (ref[:, 0] <= t[-1])
    if not inside.any():
        return math.nan
    return float(np.sqrt(np.mean((np.interp(ref[inside, 0], t, u) - ref[inside, 1]) ** 2)))


def gate(args):
    run = open_section(args, "Elastic gate", "gate_T4")
    if run is None:
        return
    folder = os.path.join(args.reference, "antoci_2007_elastic_gate")
    refs = {comp: reference_curves(folder, f"ng_2020_elastic_dam_break_{comp}_displacement_{{}}.csv", GATE_REFS)
            for comp in ("x", "y")}
    d, rows = tip_history(args, run, refs, "ISPH-TLSPH (this code), T/dx = 4", "coupled_gate_tip.png", ("x", "y"))
    t, ux, uy = d["time"], d["tip.ux"], d["tip.uy"]
    print(f"\nPeak tip u_x: {fmt(ux.max() * 1e3, 3)} mm at t = {fmt(t[np.argmax(ux)], 3)} s; peak u_y: "
          f"{fmt(uy.max() * 1e3, 3)} mm at t = {fmt(t[np.argmax(uy)], 3)} s.\n")
    table(["component", "reference", "RMSE [mm]", "reference peak [mm]", "at t [s]"], rows)
    describe_end(run)
    if os.path.exists(os.path.join(run, "summary.json")):
        phase_table([("gate_T4", summary(run))])
    gate_energy(args, run)
    gate_snapshots(args, run)
    gate_stress(args)


def gate_energy(args, run):
    e = read_probes(run, "energy.csv")
    t = e["time"]
    fig, ax = plt.subplots(figsize=(8, 4))
    base = e["total"][0]
    for key, label in (("fluid_kinetic", "fluid kinetic"), ("fluid_potential", "fluid potential"),
                       ("structure_kinetic", "structure kinetic"), ("structure_strain", "structure strain"),
                       ("structure_potential", "structure potential"), ("total", "total")):
        v = e[key] - (e[key][0] if key in ("fluid_potential", "total") else 0.0)
        ax.plot(t, v, lw=1.5 if key == "total" else 1, label=label + (" (change)" if key in ("fluid_potential", "total") else ""))
    save_history(fig, ax, args, "energy per unit depth [J/m]", "coupled_gate_energy.png")
    released = e["fluid_potential"][0] - e["fluid_potential"].min()
    print(f"\nEnergy: the total changes by {fmt(e['total'][-1] - base, 3)} J/m over the run "
          f"({fmt(100 * (e['total'][-1] - base) / released, 3)} % of the potential energy released, "
          f"{fmt(released, 3)} J/m); largest excursion {fmt(np.max(np.abs(e['total'] - base)), 3)} J/m.")


def snapshots(args, run, times, xlim, ylim, p_max, name, walls=False, size=0.5):
    """Six snapshots nearest to `times`: fluid coloured by pressure, structure red (walls grey)."""
    snaps = snapshot_list(run)
    if not snaps:
        return
    fig, axes = plt.subplots(2, 3, figsize=(12, 6), sharex=True, sharey=True)
    sc = None
    for ax, want in zip(axes.ravel(), times):
        t, path = snaps[closest(snaps, want)]
        if abs(t - want) > 0.01:  # the run did not reach it
            ax.set_axis_off()
            continue
        sn = read_snapshot(path)
        x, kind, p = sn["position"], sn["kind"].ravel(), sn["pressure"].ravel()
        fluid, structure = kind == 0, kind == 2
        if walls:
            ax.scatter(x[kind == 1, 0], x[kind == 1, 1], c="0.6", s=size)
        sc = ax.scatter(x[fluid, 0], x[fluid, 1], c=p[fluid], s=size, cmap="viridis", vmin=0, vmax=p_max)
        ax.scatter(x[structure, 0], x[structure, 1], c="r", s=size)
        ax.set_title(f"t = {t:.2f} s", fontsize=9)
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal")
    if sc is not None:
        fig.colorbar(sc, ax=axes, label="pressure [Pa]", shrink=0.8)
    save(fig, args, name)


def gate_stress(args):
    """The gate's sigma_yy at its largest opening (seed Fig. 18), from a run that writes the stresses."""
    run = finished_run(args.runs, "gate_stress")
    if run is None:
        return
    d = read_probes(run)
    t_peak = d["time"][np.argmax(d["tip.ux"])]
    snaps = snapshot_list(run)
    t, path = snaps[closest(snaps, t_peak)]
    sn = read_snapshot(path)
    if "sigma_yy" not in sn:
        print("\n_the gate_stress run has no stresses in its snapshots_")
        return
    x, kind = sn["position"], sn["kind"].ravel()
    fluid, structure = kind == 0, kind == 2
    fig, axes = plt.subplots(1, 2, figsize=(11, 5), gridspec_kw={"width_ratios": [2, 1]})
    axes[0].scatter(x[fluid, 0], x[fluid, 1], c=sn["pressure"].ravel()[fluid], s=0.5, cmap="Blues", vmin=0, vmax=1400)
    for ax in axes:
        sc = ax.scatter(x[structure, 0], x[structure, 1], c=sn["sigma_yy"].ravel()[structure] / 1e3, s=3 if ax is axes[0] else 12,
                        cmap="coolwarm", vmin=-500, vmax=500)
        ax.set_aspect("equal")
    axes[0].set_xlim(-0.01, 0.25)
    axes[0].set_ylim(-0.01, 0.16)
    axes[1].set_xlim(0.09, 0.15)
    axes[1].set_ylim(-0.005, 0.085)
    axes[0].set_title(f"t = {t:.3f} s (largest tip u_x): fluid pressure (blue), gate sigma_yy", fontsize=9)
    fig.colorbar(sc, ax=axes, label="sigma_yy [kPa]", shrink=0.8)
    save(fig, args, "coupled_gate_stress.png")
    sy = sn["sigma_yy"].ravel()[structure]
    print(f"\nGate stress at t = {fmt(t, 3)} s (tip u_x {fmt(d['tip.ux'].max() * 1e3, 3)} mm): sigma_yy from "
          f"{fmt(sy.min() / 1e3, 3)} to {fmt(sy.max() / 1e3, 3)} kPa.")


def gate_snapshots(args, run):
    snapshots(args, run, GATE_SNAPSHOT_TIMES, (-0.01, 0.3), (-0.01, 0.16), 1400, "coupled_gate_snapshots.png")


def open_section(args, title, name):
    """Prints the section's title; returns the run (finished, or with --partial as far as it got), or None."""
    print(f"\n### {title}\n")
    run = run_or_partial(args, name)
    if run is None:
        print("_no run_")
    return run


def reference_curves(folder, pattern, table):
    """[(path, label, marker, time shift)] for the rows (key, label, marker[, time shift]) of `table` whose file
    pattern.format(key) exists."""
    return [(path, row[1], row[2], row[3] if len(row) > 3 else 0.0) for row in table
            if os.path.exists(path := os.path.join(folder, pattern.format(row[0])))]


def run_or_partial(args, name):
    """A finished run, or with --partial one still running or stopped (what it has written so far)."""
    run = finished_run(args.runs, name)
    if run is None and args.partial and os.path.exists(os.path.join(args.runs, name, "probes.csv")):
        run = os.path.join(args.runs, name)
    return run


def tip_history(args, run, refs, label, name, components=("x",), windows=(math.inf,), others=()):
    """The probe `tip` against reference curves {component: [(path, label, marker, time shift)]} and beside
    the tips of other runs [(run, label)]; returns the probes and the rows (component, reference, the RMSE
    up to each time in `windows` (default: over the run), reference peak and its time)."""
    d = read_probes(run)
    t = d["time"]
    fig, axes = plt.subplots(1, len(components), figsize=(5.5 * len(components), 4), squeeze=False)
    rows = []
    for comp, ax in zip(components, axes[0]):
        u = d[f"tip.u{comp}"]
        ax.plot(t, u * 1e3, "k-", lw=1.5, label=label)
        for other, other_label in others:
            o = read_probes(other)
            ax.plot(o["time"], o[f"tip.u{comp}"] * 1e3, lw=1.2, label=other_label)
        for path, ref_label, marker, shift in refs.get(comp, ()):
            ref = read_reference(path)
            ref[:, 0] += shift
            ax.plot(ref[:, 0], ref[:, 1] * 1e3, marker, ms=3, mfc="none", label=ref_label)
            rows.append([comp, ref_label] + [fmt(rmse_against(t[t <= end], u[t <= end], ref) * 1e3, 3) for end in windows]
                        + [fmt(ref[:, 1].max() * 1e3, 3), fmt(ref[np.argmax(ref[:, 1]), 0], 3)])
        ax.set_xlabel("t [s]")
        ax.set_ylabel(f"tip u_{comp} [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, args, name)
    return d, rows


def describe_end(run):
    if os.path.exists(os.path.join(run, "summary.json")):
        print("\n- " + run_line(summary(run)) + "\n")
    else:
        print(f"\n- Unfinished run (no summary.json): its output reaches t = {fmt(read_probes(run)['time'][-1], 3)} s.\n")


WALHORN_REFS = (("bogaers_2016_qn_ls", "Bogaers et al. 2016, QN-LS", "o"),
                ("idelsohn_2008_pfrem", "Idelsohn et al. 2008, PFEM", "s"),
                ("liu_2013_sph", "Liu et al. 2013, SPH", "^"),
                ("sun_2019_mps_dem", "Sun et al. 2019, MPS-DEM", "v"))


def walhorn(args):
    run = open_section(args, "Dam break on an elastic obstacle (Walhorn et al. 2005 set-up)", "walhorn")
    if run is None:
        return
    folder = os.path.join(args.reference, "walhorn_2005_dam_break_elastic_obstacle")
    refs = reference_curves(folder, "sun_2019_dam_breaking_flow_impacting_an_elastic_plate_x_displacement_{}.csv",
                            WALHORN_REFS)
    # RMSE over the first swing (to 0.283 s), up to the returning wave (0.55 s) and over the whole run.
    windows = (0.283, 0.55, math.inf)
    d, rows = tip_history(args, run, {"x": refs},
                          "ISPH-TLSPH (this code), dx = 2.4 mm", "coupled_walhorn_tip.png", windows=windows)
    t, ux = d["time"], d["tip.ux"]
    print(f"Peak tip u_x: {fmt(ux.max() * 1e3, 3)} mm at t = {fmt(t[np.argmax(ux)], 3)} s (references: 45-48 mm at "
          f"0.22-0.26 s).\n")
    table(["reference"] + [f"RMSE of u_x to {fmt(min(end, t[-1]), 3)} s [mm]" for end in windows]
          + ["reference peak [mm]", "at t [s]"], [row[1:] for row in rows])
    describe_end(run)
    snapshots(args, run, (0.05, 0.1, 0.15, 0.2, 0.25, 0.3), (-0.01, 0.6), (-0.01, 0.35), 3000,
              "coupled_walhorn_snapshots.png")
    walhorn_energy(args, run)


def walhorn_energy(args, run):
    """Total energy of the case as shipped against the same case with OPS shifting (`walhorn_ops`, finished
    or not), each relative to its initial value and labelled with the shifting it ran."""
    fig, ax = plt.subplots(figsize=(8, 4))
    for folder in (run, os.path.join(args.runs, "walhorn_ops")):
        if not os.path.exists(os.path.join(folder, "energy.csv")):
            continue
        with open(os.path.join(folder, "case.resolved.toml"), "rb") as f:
            label = "shifting " + tomllib.load(f)["fluid"]["shifting"]["type"]
        e = read_probes(folder, "energy.csv")
        change = e["total"] - e["total"][0]
        ax.plot(e["time"], change, lw=1.2, label=label)
        print(f"- Total energy, {label}: initial {fmt(e['total'][0], 4)} J/m; largest gain {fmt(change.max(), 3)} J/m; "
              f"{fmt(e['total'][-1], 4)} J/m at t = {fmt(e['time'][-1], 3)} s.")
    save_history(fig, ax, args, "total energy − initial [J/m]", "coupled_walhorn_energy.png")


def case_without_reference(args, title, name, snap_times, xlim, ylim, p_max, size):
    """A case with no reference curve: its tip history (x and y) and snapshots; returns the run or None."""
    run = open_section(args, title, name)
    if run is None:
        return None
    d, _ = tip_history(args, run, {}, "ISPH-TLSPH (this code)", f"coupled_{name}_tip.png", ("x", "y"))
    t, ux = d["time"], d["tip.ux"]
    print(f"Tip u_x from {fmt(ux.min() * 1e3, 3)} to {fmt(ux.max() * 1e3, 3)} mm; largest at t = {fmt(t[np.argmax(ux)], 3)} s.")
    describe_end(run)
    snapshots(args, run, snap_times, xlim, ylim, p_max, f"coupled_{name}_snapshots.png", walls=True, size=size)
    return run


LIAO_COLUMNS = (("liao", "water column 0.4 m high (the case)"),
                ("liao_H02", "water column 0.2 m high (SPHinXsys, Zhang et al. 2021)"))


def liao(args):
    case_without_reference(args, "Dam break on an elastic plate (Liao et al. 2015 set-up)", "liao",
                           (0.1, 0.2, 0.25, 0.3, 0.4, 0.5), (-0.01, 0.81), (-0.01, 0.55), 4000, 0.2)
    case_without_reference(args, "Dam break on an elastic plate, water column 0.2 m high", "liao_H02",
                           (0.2, 0.25, 0.3, 0.35, 0.4, 0.45), (-0.01, 0.81), (-0.01, 0.3), 2000, 0.2)
    liao_columns(args)
    liao_contact(args)


def liao_contact(args):
    """The 0.4 m column continued from 0.27 s with the structure-wall contact, beside the run without it."""
    run = case_without_reference(args, "Dam break on an elastic plate, 0.4 m column, structure-wall contact from 0.27 s",
                                 "liao_contact", (0.28, 0.29, 0.30, 0.31, 0.32, 0.34), (0.55, 0.75), (-0.02, 0.12), 4000, 0.5)
    without = run_or_partial(args, "liao")
    if run is None or without is None:
        return
    c = coupling(summary(run)) if os.path.exists(os.path.join(run, "summary.json")) else {}
    if c:
        print(f"- Structure-wall contact in {c.get('steps_with_wall_contact')} fluid steps; deepest overlap "
              f"{fmt(c.get('max_wall_overlap', math.nan) * 1e3, 3)} mm.\n")
    tip_history(args, run, {}, "with structure-wall contact", "coupled_liao_contact_tip.png", ("x", "y"),
                others=[(without, "without it (the plate passes through the floor)")])


def liao_columns(args):
    """The plate's tip under the two column heights that public set-ups of the case use."""
    runs = [(run_or_partial(args, name), label) for name, label in LIAO_COLUMNS]
    if all(run is not None for run, _ in runs):
        (run, label), others = runs[0], runs[1:]
        tip_history(args, run, {}, label, "coupled_liao_columns.png", ("x", "y"), others=others)


def sloshing(args):
    run = case_without_reference(args, "Rolling tank with an elastic baffle (Idelsohn et al. 2008 set-up), T/dx = 2",
                                 "sloshing_T2", (0.1, 0.2, 0.3, 0.4, 0.5, 0.6), (-0.03, 0.65), (-0.04, 0.2), 1200, 0.3)
    if run is None:
        return
    e = read_probes(run, "energy.csv")
    print(f"- Work of the rolling walls on the oil: {fmt(e['boundary_work'][-1], 3)} J/m at the end; the total "
          f"(energies minus that work) changes by {fmt(e['total'][-1] - e['total'][0], 3)} J/m.\n")
    sloshing_energy(args, [(run, "T/dx = 2"), (run_or_partial(args, "sloshing_T4"), "T/dx = 4")],
                    [(run_or_partial(args, f"sloshing_no_baffle_T2_{shifting}"), shifting) for shifting in ("ops", "none", "xu")])
    # the whole measured roll history at T/dx = 2, and the case as shipped (T/dx = 4) beside it
    full = case_without_reference(args, "Rolling tank, T/dx = 2, the whole measured roll history", "sloshing_T2_full",
                                  (0.8, 1.6, 2.4, 3.2, 4.0, 4.9), (-0.03, 0.65), (-0.04, 0.2), 1200, 0.3)
    fine = run_or_partial(args, "sloshing_T4_full") or run_or_partial(args, "sloshing_T4")  # the former carries the latter's rows
    if fine is not None:
        tip_history(args, fine, {}, "T/dx = 4 (dx = 1 mm)", "coupled_sloshing_T2_T4_tip.png", ("x", "y"),
                    others=[(full or run, "T/dx = 2 (dx = 2 mm)")])


def sloshing_energy(args, runs, no_baffle):
    """The rolling tank's energy books: the total (energies less the walls' and the clamp's work) with the
    baffle, and without it under each shifting [(run, shifting)]; the baffle's strain energy; and per
    finished run the split of the exchange between oil and baffle (summary.json's interaction_work is the
    oil's work on the baffle)."""
    fig, ax = plt.subplots(figsize=(8, 4))
    runs = [(run, label) for run, label in runs if run is not None]
    for run, label in runs:
        e = read_probes(run, "energy.csv")
        line, = ax.plot(e["time"], e["total"] - e["total"][0], lw=1.5, label=f"total − initial, {label}")
        ax.plot(e["time"], e["structure_strain"], "--", color=line.get_color(), lw=1, label=f"baffle's strain energy, {label}")
        if os.path.exists(os.path.join(run, "summary.json")):
            end, w_fs = -1, coupling(summary(run)).get("interaction_work", math.nan)
        else:  # a run still going or stopped: the works its last snapshot carries
            snaps = snapshot_list(run)
            if not snaps:
                continue
            with h5py.File(snaps[-1][1], "r") as h:
                end, w_fs = int(np.argmin(np.abs(e["time"] - h.attrs["time"]))), float(h.attrs["interaction_work"])
        structure = sum(e[k][end] - e[k][0] for k in ("structure_kinetic", "structure_potential", "structure_strain"))
        fluid = sum(e[k][end] - e[k][0] for k in ("fluid_kinetic", "fluid_potential"))
        clamp = structure - w_fs  # the structure's own books close (MovingWalls.ClampWorkClosesTheStructuresEnergyBalance)
        walls = e["boundary_work"][end] - clamp
        print(f"- {label}, to t = {fmt(e['time'][end], 3)} s: the oil's work on the baffle {fmt(w_fs, 3)} J/m, the clamp's "
              f"{fmt(clamp, 3)} J/m, the baffle's gain {fmt(structure, 3)} J/m; the walls' work on the oil {fmt(walls, 3)} J/m, "
              f"the oil's gain {fmt(fluid, 3)} J/m, so the oil's books are out by {fmt(fluid - walls + w_fs, 3)} J/m; "
              f"the total changes by {fmt(e['total'][end] - e['total'][0], 3)} J/m.")
    rows = []
    for (run, shifting), style in zip(no_baffle, ("k:", "k-.", "k--")):
        if run is None:
            continue
        e = read_probes(run, "energy.csv")
        ax.plot(e["time"], e["total"] - e["total"][0], style, lw=1.2, label=f"total − initial, no baffle, {shifting}, T/dx = 2")
        rows.append([shifting, fmt(e["time"][-1], 3), fmt(e["boundary_work"][-1], 3),
                     fmt(e["fluid_kinetic"][-1] - e["fluid_kinetic"][0], 3),
                     fmt(e["fluid_potential"][-1] - e["fluid_potential"][0], 3), fmt(e["total"][-1] - e["total"][0], 3)])
    if rows:
        print("\nWithout the baffle (oil alone in the rolling tank, T/dx = 2):\n")
        table(["shifting", "to t [s]", "walls' work [J/m]", "kinetic change [J/m]", "potential change [J/m]",
               "total change [J/m]"], rows)
    print()
    save_history(fig, ax, args, "energy per unit depth [J/m]", "coupled_sloshing_energy.png")


STABILITY_VARIANTS = (("reference", "the case's defaults (no FSI layer, substeps from the stability limit, "
                                    "velocity-Verlet, two interface iterations)"),
                      ("fsi_on", "FSI shifting layer on"),
                      ("seed_ratio", "100 substeps per fluid step (the seed's ratio)"),
                      ("large_step", "1 substep per fluid step (beyond the structure's limit)"),
                      ("rk4", "RK4 structure integrator at Courant 0.5"),
                      ("staggered", "one interface iteration (staggered)"))


def gate_stability(args):
    print("\n### Elastic gate: stability of the variants (T/dx = 4, to 0.06 s)\n")
    folder = os.path.join(args.runs, "gate_stability")
    rows = []
    for name, label in STABILITY_VARIANTS:
        run = finished_run(folder, name)
        if run is None:
            continue
        s, e, d = summary(run), read_probes(run, "energy.csv"), read_probes(run)
        c = coupling(s)
        released = e["fluid_potential"][0] - e["fluid_potential"].min()
        drift = (e["total"][-1] - e["total"][0]) / released if released > 0 else math.nan
        rows.append([label, s["status"] + ("" if s["status"] == "completed" else f" at {fmt(s['simulated_time'], 3)} s"),
                     c.get("fluid_inside_structure_max", "-"), fmt(c.get("min_fluid_structure_distance", math.nan) * 1e3, 3),
                     "> 1000" if abs(drift) > 10 else fmt(100 * drift, 3), fmt(d["tip.ux"].max() * 1e3, 3), fmt(c.get("mean_substeps", math.nan), 3),
                     fmt(c.get("mean_interface_iterations", math.nan), 3), fmt(s["wall_time_s"], 3)])
    if not rows:
        print("_no finished run_")
        return
    table(["variant", "outcome", "fluid inside gate (max)", "min distance [mm]", "energy change [% of released]",
           "peak tip u_x [mm]", "substeps", "iterations", "wall [s]"], rows)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", default=os.path.join(ROOT, "runs"))
    ap.add_argument("--figures", default=os.path.join(ROOT, "docs", "figures"))
    ap.add_argument("--reference", default=os.path.join(ROOT, "..", "shared", "reference"))
    ap.add_argument("--partial", action="store_true", help="report an unfinished gate run up to where it got")
    args = ap.parse_args(argv)
    if not os.path.isdir(args.reference) and os.path.isdir("/work/shared/reference"):
        args.reference = "/work/shared/reference"
    plate(args)
    gate(args)
    gate_stability(args)
    walhorn(args)
    liao(args)
    sloshing(args)


if __name__ == "__main__":
    main(sys.argv[1:])
