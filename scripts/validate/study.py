#!/usr/bin/python3
"""Method studies: error against wall time for every method and resolution, and stability maps.

  /usr/bin/python3 scripts/validate/study.py cases/studies/NAME.toml [--out runs/studies/NAME] [--isph build/isph]
        [--threads 1] [--jobs 1] [--set key=value ...] [--only VARIANT[,VARIANT]] [--force] [--dry-run]

A study file (TOML, docs/STUDIES.md) names a case, the key swept for resolution, the variants (each a
list of `isph --set` overrides) and, for a stability map, a second axis: a time-step factor per
variant. Every point is one `isph run CASE --out DIR --quiet --threads N --set ...` into
<out>/<variant>/<resolution label>[/<step value>]/, which keeps the solver's summary.json, probes.csv,
energy.csv and case.resolved.toml, plus study_run.json (the command and its exit status). A point whose
study_run.json names the same case and overrides and whose summary.json exists is not run again
(--force re-runs it), so a study can be stopped and resumed. Exit status 0 is a completed run, 3 a
diverged one (a data point); any other is an error: its stderr is shown, the point is marked "error"
and run again the next time. --only limits which variants are run; the report covers every point found done.

--set KEY=VALUE edits the study when KEY starts with one of the study file's own keys (title, case,
kind, metric, set, resolution, step, stability, variants; an element of `variants` by its name, e.g.
variants.isph.set=[...]); any other KEY is a solver override added to every run (end_time=0.7).

Writes <out>/study.csv and <out>/study.md (one row per point) and the charts: pareto.png (error
against wall time) and convergence.png (error against the swept resolution, with the observed order
of a least-squares fit of log error on log dx) for a study; map_<variant>.png and map.png for a
stability map.

Stability classes (kind = "stability_map"), thresholds below:
  failed    the run diverged (its summary's message says why: non-finite values, PPE failure, time-step
            collapse, a particle escaping the tank, structure runaway) or ended with an error;
  degraded  it completed, but fluid particles entered the structure (summary
            performance.coupling.fluid_inside_structure_max above FLUID_INSIDE_MAX), or the total energy grew by more
            than ENERGY_GROWTH_MAX of the energy scale E0 (max over t of total(t) - total(0); E0 = |total(0)|,
            gravitational energies measured from y = 0, the tank floor of the mapped cases: the water's
            initial potential energy for a dam break, the initial kinetic energy for a free structure;
            a fixed scale per case and resolution, so every step factor is judged alike, and growth
            rather than change because a stable run may dissipate but not create energy), or the
            pressure noise exceeded PRESSURE_NOISE_MAX (RMS of the study's pressure probe minus its
            centred moving average over `highpass_window`, from `noise_from` on, over the study's
            `pressure_scale` = rho g H);
  stable    otherwise.
"""
import argparse
import sys
import concurrent.futures
import contextlib
import csv
import io
import json
import math
import os
import re
import shlex
import subprocess
import tomllib
from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
import coupled_report as cr
import fluid_report as fr
import structure_report as sr
from report_common import ROOT, fmt, pct, read_probes, summary, table

# Stability thresholds (docs/STUDIES.md).
ENERGY_GROWTH_MAX = 0.02     # energy created, as a fraction of E0 = |total(0)|
PRESSURE_NOISE_MAX = 0.05    # high-pass RMS of the pressure probe over rho g H
# Fluid particles inside the structure (performance.coupling.fluid_inside_structure_max): none allowed
# (the coupled issue's requirement; structure/interaction.hpp says how they are found).
FLUID_INSIDE_MAX = 0
# Dam break: reference points before the front reaches the right wall (Z = 4), as in fluid_report.py.
SURGE_Z_MAX = 3.8
SURGE_EXPERIMENTS = ("mm_data_1", "mm_data_2", "ko_data")  # keys of fr.DB_REFERENCES measured in a tank

STUDY_KEYS = ("title", "case", "kind", "metric", "set", "resolution", "step", "stability", "variants")
VARIANT_KEYS = ("name", "set", "step")
AXIS_KEYS = ("key", "values", "labels", "also")
STABILITY_KEYS = ("pressure_probe", "pressure_scale", "highpass_window", "noise_from")
CLASS_COLOURS = {"stable": "#43a047", "degraded": "#fb8c00", "failed": "#e53935", "error": "#757575"}


# ----------------------------------------------------------------------------------------------
# Metrics: metric(run folder, reference folder) -> {name: number}, with the primary one as "error".


def oscillating_plate(run, reference):
    """Tip of the free oscillating plate (cases/oscillating_plate.toml) against thin-plate theory
    (../shared/reference/README.md, structure_report.py): amplitude = largest tip u_y, period = twice the
    mean spacing of the zero crossings of u_y, counting t = 0 (the plate starts undeformed, so an end
    time past half a period suffices). error = |amplitude - 0.02306 m| / 0.02306 m."""
    d = read_probes(run)
    t, y = d["time"], d["tip.uy"]
    crossings = np.sort(np.concatenate([[t[0]], sr.upward_crossings(t, y), sr.upward_crossings(t, -y)]))
    period = 2 * float(np.mean(np.diff(crossings))) if len(crossings) > 1 else math.nan
    amplitude = float(np.max(y))
    return {"error": abs(amplitude - sr.PLATE_AMPLITUDE) / sr.PLATE_AMPLITUDE,
            "amplitude_m": amplitude, "amplitude_error_pct": pct(amplitude, sr.PLATE_AMPLITUDE),
            "period_s": period, "period_error_pct": pct(period, sr.PLATE_PERIOD)}


def surge_front_rmse(run, reference):
    """Dam-break surge front Z = (front.x + dx/2)/a against T = t sqrt(2g/a) (fluid_report.py), RMSE over
    the reference points with Z <= 3.8 that the run reached, for each table of dam_break_2d/pysph.
    error = the RMSE against Koshizuka & Oka's MPS simulation of the same set-up: a converged
    incompressible solution, which both fluid models approach as dx shrinks. The experiments (Martin &
    Moyce a = 1.125 in and 2.25 in, Koshizuka & Oka) are reported beside it with their mean: their front
    is slower (the gate's opening and the floor's friction), so a coarse run that lags can sit closer to
    them than a converged one."""
    d = read_probes(run)
    dx = resolved_case(run)["dx"]
    T = d["time"] * math.sqrt(2 * fr.G / fr.DB_A)
    Z = (d["front.x"] + dx / 2) / fr.DB_A
    keys = {label: key for key, label, _ in fr.DB_REFERENCES}
    out = {f"rmse_{keys[label]}": cr.rmse_against(T, Z, ref[ref[:, 1] <= SURGE_Z_MAX])
           for label, _, ref in fr.dam_break_references(SimpleNamespace(reference=reference))}
    return {"error": out["rmse_ko_mps_data"],
            "rmse_experiments": mean_of(out, (f"rmse_{k}" for k in SURGE_EXPERIMENTS)), **out}


def gate_tip_rmse(run, reference):
    """Elastic gate (Antoci et al. 2007): RMSE [m] of the tip's x displacement against each reference
    curve of antoci_2007_elastic_gate (coupled_report.py) over the simulated window. No experiment is
    machine-readable: error = the mean of the RMSEs against the three numerical curves (Khayyer et al.
    2018, Yang et al. 2012, Ng et al. 2020)."""
    d = read_probes(run)
    refs = tuple(row for row in cr.GATE_REFS if row[0] != "wcsph_pysph")  # the three curves docs/STUDIES.md averages
    keys = {row[1]: row[0] for row in refs}
    curves = cr.reference_curves(os.path.join(reference, "antoci_2007_elastic_gate"),
                                 "ng_2020_elastic_dam_break_x_displacement_{}.csv", refs)
    out = {f"rmse_{keys[label]}": cr.rmse_against(d["time"], d["tip.ux"], cr.read_reference(path))
           for path, label, _, _ in curves}
    return {"error": mean_of(out, out.keys()), **out, "peak_ux_m": float(np.max(d["tip.ux"]))}


def plate_deflection(run, reference):
    """Hydrostatic plate: mean mid-span deflection over t >= 0.1 s against the static 6.86e-5 m (seed
    Eq. 53, coupled_report.py); error = |mean - static| / static. Pressure noise: standard deviation
    over its mean of the probe bottom_p (0.01 m above the plate's mid-span) over the same window."""
    d = read_probes(run)
    window = d["time"] >= cr.PLATE_MEAN_FROM
    deflection = -float(np.mean(d["midspan.uy"][window])) if window.any() else math.nan
    p = d["bottom_p.p"][window]
    return {"error": abs(deflection - cr.PLATE_STATIC) / cr.PLATE_STATIC, "deflection_m": deflection,
            "deflection_error_pct": pct(deflection, cr.PLATE_STATIC),
            "pressure_noise": float(np.std(p) / np.mean(p)) if p.size else math.nan}


METRICS = {f.__name__: f for f in (oscillating_plate, surge_front_rmse, gate_tip_rmse, plate_deflection)}
# What each metric's error is measured in, for the charts' axes.
METRIC_UNITS = {"oscillating_plate": "relative", "surge_front_rmse": "in x/a", "gate_tip_rmse": "m",
                "plate_deflection": "relative"}


def mean_of(values, keys):
    """Mean of values[k] over the keys present (NaN if none)."""
    found = [values[k] for k in keys if k in values]
    return float(np.mean(found)) if found else math.nan


def resolved_case(run):
    with open(os.path.join(run, "case.resolved.toml"), "rb") as f:
        return tomllib.load(f)


# ----------------------------------------------------------------------------------------------
# Stability classification


def energy_growth(run):
    """max over t of (total(t) - total(0)) / |total(0)| (energy.csv)."""
    total = read_probes(run, "energy.csv")["total"]
    return float(np.max(total - total[0]) / abs(total[0]))


def pressure_noise(run, stability):
    """RMS of the pressure probe minus its moving average (fluid_report.highpass) from noise_from on,
    over pressure_scale."""
    d = read_probes(run)
    t, p = d["time"], d[stability["pressure_probe"]]
    late = t >= stability.get("noise_from", 0.0)
    noise = fr.highpass(t, p, stability["highpass_window"])[late]
    return float(np.sqrt(np.mean(noise ** 2)) / stability["pressure_scale"]) if noise.size else math.nan


def classify(row, run, stability):
    """(class, reason, measures) of a stability-map point; see the module docstring."""
    if row["status"] != "completed":
        return "failed", row["message"], {}
    measures = {"energy_growth": energy_growth(run)}
    reasons = []
    if row["fluid_inside_structure"] > FLUID_INSIDE_MAX:
        reasons.append(f"{row['fluid_inside_structure']} fluid particles inside the structure")
    if measures["energy_growth"] > ENERGY_GROWTH_MAX:
        reasons.append(f"energy grew by {100 * measures['energy_growth']:.3g} % of E(0)")
    if "pressure_probe" in stability:
        measures["pressure_noise"] = pressure_noise(run, stability)
        if measures["pressure_noise"] > PRESSURE_NOISE_MAX:
            reasons.append(f"pressure noise {100 * measures['pressure_noise']:.3g} % of rho g H")
    return ("degraded" if reasons else "stable"), "; ".join(reasons), measures


# ----------------------------------------------------------------------------------------------
# The study file


def parse_value(text):
    """A TOML value, or the text itself as a string (as `isph --set` reads values)."""
    try:
        return tomllib.loads("v = " + text)["v"]
    except tomllib.TOMLDecodeError:
        return text


def toml_value(v):
    """v written as a TOML value for `isph --set`."""
    if isinstance(v, bool):
        return "true" if v else "false"
    return json.dumps(v) if isinstance(v, str) else repr(v)


def set_study_key(study, key, text):
    """Sets the dotted `key` of the study (an element of an array by index or by its name). New values of
    an axis drop its labels, unless they are set too (after the values)."""
    *path, last = key.split(".")
    node = study
    for segment in path:
        if isinstance(node, list):
            node = next((v for i, v in enumerate(node) if segment in (str(i), v.get("name"))), None)
            if node is None:
                raise SystemExit(f"--set {key}: no element {segment!r}")
        else:
            node = node.setdefault(segment, {})
    if isinstance(node, list):
        raise SystemExit(f"--set {key}: name an element of the array, not a key of it")
    node[last] = parse_value(text)
    if last == "values":
        node.pop("labels", None)


def check_keys(table_, allowed, where, problems):
    problems += [f"{where}{k}: unknown key" for k in table_ if k not in allowed]


def load_study(path, sets):
    """The study file with the study keys of `sets` applied, checked; and the solver overrides of `sets`."""
    with open(path, "rb") as f:
        study = tomllib.load(f)
    solver_sets = []
    for text in sets:
        key, sep, value = text.partition("=")
        if not sep:
            raise SystemExit(f"--set {text}: expected key=value")
        if key.strip().split(".")[0] in STUDY_KEYS:
            set_study_key(study, key.strip(), value.strip())
        else:
            solver_sets.append(text)
    problems = []
    check_keys(study, STUDY_KEYS, "", problems)
    check_sets(study, "set", problems)
    study.setdefault("kind", "study")
    if study["kind"] not in ("study", "stability_map"):
        problems.append(f"kind: must be \"study\" or \"stability_map\" (got {study['kind']!r})")
    if "case" not in study:
        problems.append("case: required")
    else:
        study["case"] = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), study["case"]))
        if not os.path.exists(study["case"]):
            problems.append(f"case: {study['case']} not found")
    if study.get("metric", "") not in METRICS and (study["kind"] == "study" or "metric" in study):
        problems.append(f"metric: one of {', '.join(METRICS)} (got {study.get('metric')!r})")
    res = study.get("resolution", {})
    check_axis(res, "resolution", problems)
    if any(res.get("key") == s.split("=")[0] for s in solver_sets):
        problems.append(f"--set {res['key']}: the swept key; set resolution.values instead")
    variants = study.get("variants", [])
    if not variants:
        problems.append("variants: at least one [[variants]] table")
    names = [v.get("name") for v in variants]
    for i, v in enumerate(variants):
        check_keys(v, VARIANT_KEYS, f"variants[{i}].", problems)
        check_sets(v, f"variants[{i}].set", problems)
        if not isinstance(v.get("name"), str) or not re.fullmatch(r"[A-Za-z0-9_.-]+", v["name"]):
            problems.append(f"variants[{i}].name: required, letters, digits, _ . - only")
        elif names.count(v["name"]) > 1:
            problems.append(f"variants[{i}].name: duplicate {v['name']!r}")
        if study["kind"] == "stability_map":
            v["step"] = v.get("step") or dict(study.get("step", {}))  # its own axis, else the study's
            check_axis(v["step"], f"variants[{i}].step (or [step])", problems)
        elif "step" in v:
            problems.append(f"variants[{i}].step: only in a stability_map")
    stability = study.setdefault("stability", {})
    check_keys(stability, STABILITY_KEYS, "stability.", problems)
    if "pressure_probe" in stability:
        problems += [f"stability.{k}: required with pressure_probe" for k in ("pressure_scale", "highpass_window")
                     if k not in stability]
    if problems:
        raise SystemExit(f"{path}:\n  " + "\n  ".join(problems))
    return study, solver_sets


def check_sets(table_, where, problems):
    sets = table_.get("set", [])
    if not isinstance(sets, list) or not all(isinstance(s, str) and "=" in s for s in sets):
        problems.append(f"{where}: an array of \"key=value\" strings (isph --set overrides)")


def check_axis(axis, where, problems):
    check_keys(axis, AXIS_KEYS, where + ".", problems)
    if not isinstance(axis.get("key"), str) or not axis.get("values"):
        problems.append(f"{where}: needs key and a non-empty values array")
    elif len(axis.setdefault("labels", [format_label(v) for v in axis["values"]])) != len(axis["values"]):
        problems.append(f"{where}.labels: {len(axis['labels'])} labels for {len(axis['values'])} values")
    for i, also in enumerate(axis.get("also", [])):  # keys swept in step with `key`
        if not isinstance(also, dict) or not isinstance(also.get("key"), str) or \
                len(also.get("values", [])) != len(axis.get("values", [])):
            problems.append(f"{where}.also[{i}]: a {{key, values}} table with one value per value of {where}.key")


def format_label(v):
    return f"{v:g}" if isinstance(v, float) else str(v)


def folder_name(label):
    return re.sub(r"[^A-Za-z0-9._=+-]", "_", label)


# ----------------------------------------------------------------------------------------------
# Running


def plan(study, solver_sets, out):
    """Every point of the study: {variant, resolution (label), resolution_value, step (label), overrides,
    run}."""
    res = study["resolution"]
    points = []
    for v in study["variants"]:
        steps = v.get("step") or {"key": None, "values": [None], "labels": [None]}
        for index, (value, label) in enumerate(zip(res["values"], res["labels"])):
            for step, step_label in zip(steps["values"], steps["labels"]):
                overrides = (["output.snapshots=false"] + study.get("set", []) + v.get("set", []) + solver_sets
                             + [f"{res['key']}={toml_value(value)}"]
                             + [f"{also['key']}={toml_value(also['values'][index])}" for also in res.get("also", [])]
                             + ([f"{steps['key']}={toml_value(step)}"] if step is not None else []))
                run = os.path.join(out, v["name"], folder_name(label),
                                   *([folder_name(step_label)] if step is not None else []))
                points.append({"variant": v["name"], "resolution": label, "resolution_value": value, "step": step_label,
                               "overrides": overrides, "run": run})
    return points


def record(point, case):
    """The study_run.json of the point if it was run with the same case and overrides, else None."""
    path = os.path.join(point["run"], "study_run.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        rec = json.load(f)
    return rec if rec["case"] == case and rec["overrides"] == point["overrides"] else None


def is_done(point, case):
    """Run to its end (completed or diverged) with the same case and overrides; an error is not."""
    rec = record(point, case)
    finished = os.path.exists(os.path.join(point["run"], "summary.json"))
    return rec is not None and rec["returncode"] in (0, 3) and finished


def command(point, case, args):
    cmd = [args.isph, "run", case, "--out", point["run"], "--quiet", "--threads", str(args.threads)]
    for s in point["overrides"]:
        cmd += ["--set", s]
    return cmd


def run_point(point, case, args):
    """Runs the point; writes study_run.json; returns a one-line outcome."""
    os.makedirs(point["run"], exist_ok=True)
    for stale in ("study_run.json", "summary.json"):  # an interrupted run must not look finished
        with contextlib.suppress(FileNotFoundError):
            os.remove(os.path.join(point["run"], stale))
    cmd = command(point, case, args)
    proc = subprocess.run(cmd, capture_output=True, text=True)
    rec = {"case": case, "overrides": point["overrides"], "command": cmd, "returncode": proc.returncode,
           "stderr": proc.stderr[-4000:]}
    with open(os.path.join(point["run"], "study_run.json"), "w") as f:
        json.dump(rec, f, indent=1)
    if proc.returncode not in (0, 3):
        return f"error (exit {proc.returncode}):\n{proc.stderr.strip()}"
    s = summary(point["run"])
    return f"{s['status']} ({s['message']}), {s['wall_time_s']:.3g} s"


def run_all(points, case, args):
    todo = [p for p in points if p["variant"] in args.only and (args.force or not is_done(p, case))]
    print(f"{len(points)} points, {len(todo)} to run", flush=True)
    if args.dry_run:
        for p in points:
            state = "run " if p in todo else ("done" if is_done(p, case) else "skip")
            print(f"{state}  {shlex.join(command(p, case, args))}")
        return
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(run_point, p, case, args): p for p in todo}
        for k, done in enumerate(concurrent.futures.as_completed(futures), 1):
            p = futures[done]
            print(f"[{k}/{len(todo)}] {os.path.relpath(p['run'], args.out)}: {done.result()}", flush=True)


# ----------------------------------------------------------------------------------------------
# Evaluating


def evaluate(point, case, study, reference):
    """The row of a point that has been run, to its end or to an error (None if it has not)."""
    rec = record(point, case)
    if rec is None or (rec["returncode"] in (0, 3) and not is_done(point, case)):
        return None
    row = {k: point[k] for k in ("variant", "resolution", "resolution_value")}
    if study["kind"] == "stability_map":
        row["step"] = point["step"]
    row["run_dir"] = point["run"]
    if rec["returncode"] not in (0, 3):
        lines = rec["stderr"].strip().splitlines()
        row.update(status="error", message=lines[0] if lines else f"exit {rec['returncode']}")
    else:
        s = summary(point["run"])
        steps, particles = s["steps"], s["particles"]
        coupling = s["performance"].get("coupling", {})
        row.update(status=s["status"], message=s["message"], wall_time_s=s["wall_time_s"],
                   simulated_time=s["simulated_time"], steps_fluid=steps["fluid"],
                   steps_structure=steps["structure"],
                   particles=sum(particles.get(kind, 0) for kind in ("fluid", "wall", "structure")),
                   mean_dt=s["simulated_time"] / (steps["fluid"] or steps["structure"] or math.nan),
                   fluid_inside_structure=coupling.get("fluid_inside_structure_max", 0))
        if "metric" in study and has_rows(point["run"]):
            row.update(METRICS[study["metric"]](point["run"], reference))
    if study["kind"] == "stability_map":
        row["class"], row["reason"], measures = classify(row, point["run"], study["stability"])
        row.update(measures)
    return row


def has_rows(run):
    """probes.csv has a data row past t = 0 (a run that diverged at once has none)."""
    with open(os.path.join(run, "probes.csv")) as f:
        return sum(1 for line in f if line.strip()) > 2


# ----------------------------------------------------------------------------------------------
# Writing


def columns(rows, kind):
    axes = ["step", "class", "reason"] if kind == "stability_map" else []
    first = ["variant", "resolution", "resolution_value"] + axes + ["status", "error"]
    last = ["fluid_inside_structure", "wall_time_s", "simulated_time", "steps_fluid", "steps_structure", "particles",
            "mean_dt", "message", "run_dir"]
    middle = []
    for row in rows:
        middle += [k for k in row if k not in first + last + middle]
    return first + middle + last


def write_tables(rows, study, out):
    cols = columns(rows, study["kind"])
    with open(os.path.join(out, "study.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=cols, restval="")
        writer.writeheader()
        writer.writerows(rows)
    # a map's reason column says why a point failed; a study's note says why a run did not complete
    shown = ([c for c in cols if c not in ("resolution_value", "message", "run_dir")]
             + (["note"] if study["kind"] == "study" else []))
    text = io.StringIO()
    with contextlib.redirect_stdout(text):
        print(f"### {study.get('title', study['case'])}\n")
        table(shown, [[cell(r, c) for c in shown] for r in rows])
        print(f"\nerror: `{study.get('metric', '-')}` (scripts/validate/study.py). Runs under {out}; "
              "the command of each is in its study_run.json.")
    with open(os.path.join(out, "study.md"), "w") as f:
        f.write(text.getvalue())


def cell(row, col):
    if col == "note":
        return "" if row["status"] == "completed" else row["message"].replace("|", "/")
    v = row.get(col, "")
    return fmt(v, 3) if isinstance(v, float) else str(v).replace("|", "/")


def finite(rows, variant):
    """The completed rows of a variant with a positive finite error, in the order of the study."""
    return [r for r in rows if r["variant"] == variant and r["status"] == "completed"
            and np.isfinite(r.get("error", math.nan)) and r["error"] > 0]


def observed_order(rows):
    """Slope of the least-squares line of log error against log dx (NaN with fewer than two points)."""
    if len(rows) < 2:
        return math.nan
    x, y = np.log([r["resolution_value"] for r in rows]), np.log([r["error"] for r in rows])
    return float(np.polyfit(x, y, 1)[0])


def study_charts(rows, study, out):
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    res_key, metric = study["resolution"]["key"], study["metric"]
    fig_p, ax_p = plt.subplots(figsize=(7, 5), layout="constrained")
    fig_c, ax_c = plt.subplots(figsize=(7, 5), layout="constrained")
    for v in variants:
        good = finite(rows, v)
        line, = ax_p.loglog([r["wall_time_s"] for r in good], [r["error"] for r in good], "o-", label=v)
        for r in good:
            ax_p.annotate(r["resolution"], (r["wall_time_s"], r["error"]), fontsize=7,
                          xytext=(4, 3), textcoords="offset points")
        diverged = [r for r in rows if r["variant"] == v and r["status"] == "diverged" and r.get("error", 0) > 0]
        if diverged:
            ax_p.loglog([r["wall_time_s"] for r in diverged], [r["error"] for r in diverged], "x",
                        color=line.get_color(), ms=8, label=f"{v}: diverged (error until it stopped)")
        ax_c.loglog([r["resolution_value"] for r in good], [r["error"] for r in good], "o-", color=line.get_color(),
                    label=f"{v} (order {fmt(observed_order(good), 3)})")
    title = study.get("title", "")
    error_label = f"error ({metric}) [{METRIC_UNITS[metric]}]"
    ax_p.set(xlabel="wall time [s]", ylabel=error_label, title=f"{title}: error against cost")
    ax_c.set(xlabel=res_key, ylabel=error_label, title=f"{title}: convergence")
    for ax, fig, name in ((ax_p, fig_p, "pareto.png"), (ax_c, fig_c, "convergence.png")):
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
        fig.savefig(os.path.join(out, name), dpi=120)
        plt.close(fig)


def draw_map(ax, rows, study, variant):
    """Cells resolution x step of one variant, coloured by class and annotated."""
    res_labels = study["resolution"]["labels"]
    step = next(v["step"] for v in study["variants"] if v["name"] == variant)
    for r in (r for r in rows if r["variant"] == variant):
        x, y = step["labels"].index(r["step"]), res_labels.index(r["resolution"])
        cls = r["class"] if r["status"] != "error" else "error"
        ax.add_patch(plt.Rectangle((x - 0.5, y - 0.5), 1, 1, facecolor=CLASS_COLOURS[cls], edgecolor="white"))
        if r["status"] == "diverged":
            detail = f"t = {fmt(r['simulated_time'], 3)} s"
        elif r["status"] == "completed":
            detail = f"ΔE {100 * r['energy_growth']:+.2g} %"
            detail += f"\np' {100 * r['pressure_noise']:.2g} %" if "pressure_noise" in r else ""
        else:
            detail = ""
        ax.text(x, y, f"{cls}\n{detail}", ha="center", va="center", fontsize=7)
    ax.set(xlim=(-0.5, len(step["labels"]) - 0.5), ylim=(-0.5, len(res_labels) - 0.5),
           xticks=range(len(step["labels"])), yticks=range(len(res_labels)), xlabel=step["key"],
           ylabel=study["resolution"]["key"], title=variant)
    ax.set_xticklabels(step["labels"])
    ax.set_yticklabels(res_labels)


def map_charts(rows, study, out):
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    for v in variants:
        fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
        draw_map(ax, rows, study, v)
        fig.savefig(os.path.join(out, f"map_{v}.png"), dpi=120)
        plt.close(fig)
    ncol = min(3, len(variants))
    nrow = math.ceil(len(variants) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.5 * ncol, 3.8 * nrow), squeeze=False, layout="constrained")
    for ax, v in zip(axes.ravel(), variants):
        draw_map(ax, rows, study, v)
    for ax in axes.ravel()[len(variants):]:
        ax.set_axis_off()
    fig.suptitle(study.get("title", ""))
    fig.savefig(os.path.join(out, "map.png"), dpi=120)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study")
    ap.add_argument("--out", help="default: runs/studies/<study file name>")
    ap.add_argument("--isph", default=os.path.join(ROOT, "build", "isph"))
    ap.add_argument("--threads", type=int, default=1, help="threads per run")
    ap.add_argument("--jobs", type=int, default=1, help="runs side by side")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a study key (resolution.values=[...]) or a solver override for every run")
    ap.add_argument("--only", help="comma-separated variants to run (the report covers every point done)")
    ap.add_argument("--force", action="store_true", help="re-run points already done")
    ap.add_argument("--dry-run", action="store_true", help="print the commands, run nothing")
    ap.add_argument("--reference", default=os.path.join(os.path.dirname(ROOT), "shared", "reference"))
    args = ap.parse_args(argv)
    if not os.path.isdir(args.reference) and os.path.isdir("/work/shared/reference"):
        args.reference = "/work/shared/reference"
    study, solver_sets = load_study(args.study, args.set)
    names = [v["name"] for v in study["variants"]]
    args.only = names if args.only is None else [s.strip() for s in args.only.split(",")]
    if unknown := [s for s in args.only if s not in names]:
        ap.error(f"--only: unknown variant(s) {', '.join(unknown)}; the study has {', '.join(names)}")
    args.out = os.path.abspath(args.out or os.path.join(ROOT, "runs", "studies",
                                                        os.path.splitext(os.path.basename(args.study))[0]))
    args.isph = os.path.abspath(args.isph)
    points = plan(study, solver_sets, args.out)
    run_all(points, study["case"], args)
    if args.dry_run:
        return
    rows = [r for p in points if (r := evaluate(p, study["case"], study, args.reference)) is not None]
    if not rows:
        raise SystemExit("no point has been run")
    write_tables(rows, study, args.out)
    (map_charts if study["kind"] == "stability_map" else study_charts)(rows, study, args.out)
    print(f"wrote {os.path.join(args.out, 'study.csv')}, study.md and the charts")


if __name__ == "__main__":
    main()
