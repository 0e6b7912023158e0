#!/usr/bin/python3
"""Plots of isph run output. Run with Debian's /usr/bin/python3 (matplotlib, numpy, h5py).

  plot.py probes RUN_DIR [--fields tip.uy,tip.ux] [--reference FILE[:LABEL[:SCALE[:SHIFT[:TIME_SCALE]]]] ...]
  plot.py energy RUN_DIR
  plot.py snapshot RUN_DIR [--field NAME] [--index K | --time T] [--structure-field NAME] [--deformed | --reference]
  plot.py compare --runs DIR1,DIR2,... --field tip.uy [--labels a,b] [--reference SPEC] [--level VALUE:LABEL]

Axes carry SI units, taken from the field names (a probe's ux/uy/uz and x in m, p in Pa, u in m/s;
snapshot fields by name).

Every command takes --out PNG, writes PNG files and prints their paths.
"""

import argparse
import re
import sys
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

TIME_COLUMN = "time"
REFERENCE_STYLES = ("--", ":", "-.")


class PlotError(Exception):
    """A problem with the input files or arguments, reported without a traceback."""


# ----------------------------------------------------------------------------------------------
# Input


def require_file(path):
    path = Path(path)
    if not path.is_file():
        raise PlotError(f"{path}: file not found")
    return path


def read_table(path):
    """Reads a CSV file written by CsvTable: a header line, then rows of numbers.

    Returns (column names, 2D array with one row per line).
    """
    path = require_file(path)
    lines = path.read_text().splitlines()
    if not lines:
        raise PlotError(f"{path}: empty file (no header line)")
    names = [name.strip() for name in lines[0].split(",")]
    rows = [line for line in lines[1:] if line.strip()]
    if not rows:
        return names, np.empty((0, len(names)))
    try:
        data = np.loadtxt(rows, delimiter=",", ndmin=2)
    except ValueError as error:
        raise PlotError(f"{path}: {error}") from None
    if data.shape[1] != len(names):
        raise PlotError(f"{path}: {data.shape[1]} values per row for {len(names)} columns")
    return names, data


def time_index(path, names):
    """Index of the time column: the one named 'time', else the first."""
    if not names:
        raise PlotError(f"{path}: no columns")
    return names.index(TIME_COLUMN) if TIME_COLUMN in names else 0


def read_reference(path):
    """Reads a two-column (time, value) reference file.

    Columns are separated by commas and/or whitespace, lines starting with '#' are skipped and
    a first line that is not numeric is taken as a header. Extra columns are ignored.
    """
    path = require_file(path)
    rows = []
    header_possible = True
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        parts = [part for part in re.split(r"[,\s]+", text) if part]
        try:
            values = [float(part) for part in parts[:2]]
        except ValueError:
            if header_possible:
                header_possible = False
                continue
            raise PlotError(f"{path}:{number}: not numeric: {text!r}") from None
        header_possible = False
        if len(values) < 2:
            raise PlotError(f"{path}:{number}: expected two columns (time, value): {text!r}")
        rows.append(values)
    if not rows:
        raise PlotError(f"{path}: no data rows")
    return np.array(rows)


class Reference:
    """A reference curve from FILE[:LABEL[:COLUMN_SCALE[:TIME_SHIFT[:TIME_SCALE]]]].

    The value column is multiplied by COLUMN_SCALE (default 1); the time column by TIME_SCALE
    (default 1), then TIME_SHIFT (default 0) is added: a non-dimensional curve (the dam break's
    t sqrt(2g/a), x/a) is drawn in seconds and metres.
    """

    def __init__(self, spec):
        parts = spec.split(":")
        if len(parts) > 5:
            raise PlotError(f"reference {spec!r}: expected FILE[:LABEL[:SCALE[:SHIFT[:TIME_SCALE]]]]")
        parts += [""] * (5 - len(parts))
        path, label, scale, shift, time_scale = parts
        try:
            self.scale = float(scale) if scale else 1.0
            self.shift = float(shift) if shift else 0.0
            self.time_scale = float(time_scale) if time_scale else 1.0
        except ValueError:
            raise PlotError(f"reference {spec!r}: SCALE, SHIFT and TIME_SCALE must be numbers") from None
        data = read_reference(path)
        self.time = data[:, 0] * self.time_scale + self.shift
        self.value = data[:, 1] * self.scale
        self.label = label or Path(path).stem

    def plot(self, ax, number):
        style = REFERENCE_STYLES[number % len(REFERENCE_STYLES)]
        ax.plot(self.time, self.value, style, color="black", linewidth=1.2, label=self.label)


def probe_columns(run_dir, fields):
    """Reads RUN_DIR/probes.csv; returns (time name, time, {field: values}) for `fields`
    (all columns but time when `fields` is empty)."""
    path = Path(run_dir) / "probes.csv"
    names, data = read_table(path)
    t = time_index(path, names)
    if not fields:
        fields = [name for i, name in enumerate(names) if i != t]
    missing = [field for field in fields if field not in names]
    if missing:
        available = ", ".join(name for i, name in enumerate(names) if i != t)
        raise PlotError(f"{path}: no column {', '.join(missing)} (available: {available})")
    if data.shape[0] == 0:
        raise PlotError(f"{path}: no rows yet")
    return names[t], data[:, t], {field: data[:, names.index(field)] for field in fields}


# SI units of the output files' columns and fields (docs/CASES.md, README: outputs).
PROBE_UNITS = {"ux": "m", "uy": "m", "uz": "m", "x": "m", "p": "Pa", "u": "m/s", "fx": "N/m", "fy": "N/m"}
FIELD_UNITS = {"pressure": "Pa", "velocity": "m/s", "displacement": "m", "position": "m", "sigma_xx": "Pa",
               "sigma_yy": "Pa", "sigma_xy": "Pa", "sigma_zz": "Pa", "sigma_xz": "Pa", "sigma_yz": "Pa", "density": "kg/m^3", "shift": "m", "structure_velocity": "m/s",
               "structure_acceleration": "m/s^2", "structure_interaction": "m/s^2", "acceleration": "m/s^2",
               "pressure_acceleration": "m/s^2", "boundary_force": "N/m^3"}


def with_unit(name, units):
    """'name [unit]' where the unit is known: a probe column by its part after the dot, a field by name."""
    unit = units.get(name.split(".")[-1]) or units.get(name)
    return f"{name} [{unit}]" if unit else name


def split_list(text):
    return [item.strip() for item in text.split(",") if item.strip()] if text else []


# ----------------------------------------------------------------------------------------------
# Output


def new_figure(width, height):
    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save(fig, out):
    out = Path(out)
    try:
        fig.savefig(out, dpi=150)
    except OSError as error:
        raise PlotError(f"cannot write {out}: {error.strerror or error}") from None
    print(out)


# ----------------------------------------------------------------------------------------------
# Commands


def cmd_probes(args):
    time_name, time, columns = probe_columns(args.run_dir, split_list(args.fields))
    references = [Reference(spec) for spec in args.reference]
    fig = new_figure(9, 0.6 + 2.6 * len(columns))
    axes = fig.subplots(len(columns), 1, sharex=True, squeeze=False)[:, 0]
    for k, (ax, (field, values)) in enumerate(zip(axes, columns.items())):
        ax.plot(time, values, linewidth=1.5, label=field)
        if k == 0:
            for number, reference in enumerate(references):
                reference.plot(ax, number)
        ax.set_ylabel(with_unit(field, PROBE_UNITS))
        ax.grid(True, alpha=0.3)
        if k == 0 and references:
            ax.legend(fontsize=8)
    axes[-1].set_xlabel(f"{time_name} [s]")
    fig.suptitle(Path(args.run_dir).resolve().name)
    save(fig, args.out or Path(args.run_dir) / "probes.png")


def cmd_energy(args):
    path = Path(args.run_dir) / "energy.csv"
    names, data = read_table(path)
    t = time_index(path, names)
    if data.shape[0] == 0:
        raise PlotError(f"{path}: no rows yet")
    others = [i for i in range(len(names)) if i != t]
    if not others:
        raise PlotError(f"{path}: no energy columns besides {names[t]}")
    if "total" in names:
        total = data[:, names.index("total")]
    else:
        total = data[:, others].sum(axis=1)
    fig = new_figure(9, 5)
    ax = fig.subplots()
    for i in others:
        if names[i] != "total" and np.any(data[:, i] != 0):
            ax.plot(data[:, t], data[:, i], linewidth=1.3, label=names[i])
    ax.plot(data[:, t], total, "k-", linewidth=2.0, label="total")
    ax.set_xlabel(f"{names[t]} [s]")
    ax.set_ylabel("energy [J per m of depth in 2D, J in 3D]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    ax.set_title(Path(args.run_dir).resolve().name)
    save(fig, args.out or Path(args.run_dir) / "energy.png")


def pick_snapshot(run_dir, index, time=None):
    """The snapshot at `index` among the sorted files, or the one nearest `time` [s] when given."""
    directory = Path(run_dir) / "snapshots"
    files = sorted(directory.glob("snapshot_*.h5"))
    if not files:
        raise PlotError(f"{directory}: no snapshot_*.h5 files")
    if time is not None:
        import h5py

        def snapshot_time(path):
            with h5py.File(path, "r") as f:
                return float(f.attrs.get("time", np.nan))

        return min(files, key=lambda path: abs(snapshot_time(path) - time))
    if not -len(files) <= index < len(files):
        raise PlotError(f"{directory}: no snapshot at index {index} ({len(files)} files)")
    return files[index]


def read_field(snapshot, datasets, path, field):
    if field not in datasets:
        raise PlotError(f"{path}: no field {field} (available: {', '.join(datasets)})")
    values = np.asarray(snapshot[field], dtype=float)
    if values.ndim > 1:
        return np.linalg.norm(values.reshape(len(values), -1), axis=1), f"|{field}|"
    return values, field


def cmd_snapshot(args):
    import h5py  # only this command needs it

    path = pick_snapshot(args.run_dir, args.index, args.time)
    try:
        snapshot = h5py.File(path, "r")
    except OSError as error:
        raise PlotError(f"{path}: cannot open as HDF5: {error}") from None
    with snapshot:
        datasets = [name for name in snapshot if isinstance(snapshot[name], h5py.Dataset)]
        geometry = "position"
        if args.reference:
            if "reference_position" in datasets:
                geometry = "reference_position"
            else:
                print(f"{path}: no reference_position, plotting positions", file=sys.stderr)
        if geometry not in datasets:
            raise PlotError(f"{path}: no dataset {geometry}")
        positions = np.asarray(snapshot[geometry], dtype=float)
        field = args.field
        if field is None:
            fields = [name for name in datasets if name not in ("position", "reference_position")]
            field = "pressure" if "pressure" in fields else (fields[0] if fields else None)
        values, label = read_field(snapshot, datasets, path, field) if field else (None, None)
        kind = np.asarray(snapshot["kind"], dtype=int) if "kind" in datasets else None
        structure_values = structure_label = None
        if args.structure_field:
            if kind is None:
                raise PlotError(f"{path}: no particle kinds (a structure-only run: use --field)")
            structure_values, structure_label = read_field(snapshot, datasets, path, args.structure_field)
        time = snapshot.attrs.get("time")

    if positions.ndim != 2 or positions.shape[1] < 2:
        raise PlotError(f"{path}: {geometry} is not an N x 2 or N x 3 array")
    x, y = positions[:, 0], positions[:, 1]
    if values is not None and len(values) != len(x):
        raise PlotError(f"{path}: {field} has {len(values)} values for {len(x)} particles")

    width = max(np.ptp(x) if len(x) else 0.0, 1e-12)
    height = max(np.ptp(y) if len(y) else 0.0, 1e-12)
    aspect = height / width
    fig = new_figure(10, min(10.0, max(2.5, 9 * aspect)) + 1.2 + (1.0 if structure_values is not None else 0.0))
    ax = fig.subplots()
    orientation = "horizontal" if aspect < 0.5 else "vertical"
    if structure_values is None:
        scatter = ax.scatter(x, y, c=values, s=1.0, cmap="viridis", linewidths=0)
        scatters = [scatter]
        if values is not None:
            fig.colorbar(scatter, ax=ax, label=with_unit(label, FIELD_UNITS), orientation=orientation, shrink=0.8)
    else:  # fluid by --field, walls grey, the structure by --structure-field
        fluid, wall, structure = kind == 0, kind == 1, kind == 2
        scatters = [ax.scatter(x[wall], y[wall], c="0.7", s=1.0, linewidths=0)]
        fluid_scatter = ax.scatter(x[fluid], y[fluid], c=values[fluid] if values is not None else None, s=1.0,
                                   cmap="viridis", linewidths=0)
        limit = max(float(np.max(np.abs(structure_values[structure]))) if structure.any() else 0.0, 1e-30)
        structure_scatter = ax.scatter(x[structure], y[structure], c=structure_values[structure], s=1.0,
                                       cmap="coolwarm", vmin=-limit, vmax=limit, linewidths=0)
        scatters += [fluid_scatter, structure_scatter]
        fig.colorbar(fluid_scatter, ax=ax, label=f"fluid {with_unit(label, FIELD_UNITS)}", orientation=orientation,
                     shrink=0.8)
        fig.colorbar(structure_scatter, ax=ax, label=f"structure {with_unit(structure_label, FIELD_UNITS)}",
                     orientation=orientation, shrink=0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    title = path.name + (f", t = {float(time):.6g} s" if time is not None else "")
    ax.set_title(title + (" (reference configuration)" if geometry != "position" else ""))
    if args.xlim:
        ax.set_xlim(*args.xlim)
    if args.ylim:
        ax.set_ylim(*args.ylim)
    for scatter in scatters:
        set_particle_size(fig, ax, scatter, width, height, len(x))
    out = args.out or Path(args.run_dir) / f"snapshot_{field or geometry}.png"
    save(fig, out)


def set_particle_size(fig, ax, scatter, width, height, count):
    """Sizes markers so that a particle covers about its share of the bounding box."""
    if count == 0:
        return
    fig.canvas.draw()  # lays out the axes, so that their size on the page is known
    box = ax.get_window_extent()
    x0, x1 = ax.get_xlim()
    points_per_unit = box.width / (x1 - x0) * 72.0 / fig.dpi
    spacing = np.sqrt(width * height / count) if height > 1e-12 else width / count
    diameter = 0.9 * spacing * points_per_unit
    scatter.set_sizes([float(np.clip(diameter ** 2, 0.05, 400.0))])


def cmd_compare(args):
    runs = split_list(args.runs)
    if not runs:
        raise PlotError("--runs: give at least one run directory")
    labels = split_list(args.labels)
    if labels and len(labels) != len(runs):
        raise PlotError(f"--labels: {len(labels)} labels for {len(runs)} runs")
    if not labels:
        names = [Path(run).resolve().name for run in runs]
        labels = names if len(set(names)) == len(names) else runs
    fig = new_figure(9, 5)
    ax = fig.subplots()
    time_name = TIME_COLUMN
    for run, label in zip(runs, labels):
        time_name, time, columns = probe_columns(run, [args.field])
        ax.plot(time, columns[args.field], linewidth=1.3, label=label)
    for number, spec in enumerate(args.reference):
        Reference(spec).plot(ax, number)
    for number, spec in enumerate(args.level):
        value, _, label = spec.partition(":")
        ax.axhline(float(value), color="0.3", linestyle=("--", ":", "-.")[number % 3], linewidth=1.0,
                   label=label or value)
    ax.set_xlabel(f"{time_name} [s]")
    ax.set_ylabel(with_unit(args.field, PROBE_UNITS))
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, args.out or f"compare_{args.field}.png")


# ----------------------------------------------------------------------------------------------


def parser():
    top = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    commands = top.add_subparsers(dest="command", required=True)
    reference_help = ("reference curve FILE[:LABEL[:COLUMN_SCALE[:TIME_SHIFT[:TIME_SCALE]]]] with "
                      "columns time,value (comma or whitespace separated, '#' comments, optional "
                      "header); repeatable")

    probes = commands.add_parser("probes", help="probe values from RUN_DIR/probes.csv")
    probes.add_argument("run_dir", metavar="RUN_DIR")
    probes.add_argument("--fields", help="comma-separated columns (default: all)")
    probes.add_argument("--reference", action="append", default=[],
                        help=reference_help + "; drawn on the first field's subplot")
    probes.add_argument("--out", help="PNG file (default: RUN_DIR/probes.png)")
    probes.set_defaults(run=cmd_probes)

    energy = commands.add_parser("energy", help="energies from RUN_DIR/energy.csv")
    energy.add_argument("run_dir", metavar="RUN_DIR")
    energy.add_argument("--out", help="PNG file (default: RUN_DIR/energy.png)")
    energy.set_defaults(run=cmd_energy)

    snapshot = commands.add_parser("snapshot", help="particles of one HDF5 snapshot")
    snapshot.add_argument("run_dir", metavar="RUN_DIR")
    snapshot.add_argument("--field", help="colouring field (default: pressure, else the first); "
                                          "vector fields are shown as magnitude")
    snapshot.add_argument("--index", type=int, default=-1,
                          help="snapshot index among the sorted files (default: -1, the last)")
    snapshot.add_argument("--time", type=float, help="the snapshot nearest this time [s] (instead of --index)")
    snapshot.add_argument("--structure-field", help="with a fluid: colour the structure particles by this field "
                                                    "(e.g. sigma_yy), the fluid by --field, walls grey")
    snapshot.add_argument("--xlim", type=float, nargs=2, metavar=("LO", "HI"), help="x range [m]")
    snapshot.add_argument("--ylim", type=float, nargs=2, metavar=("LO", "HI"), help="y range [m]")
    geometry = snapshot.add_mutually_exclusive_group()
    geometry.add_argument("--deformed", dest="reference", action="store_false",
                          help="plot current positions (default)")
    geometry.add_argument("--reference", dest="reference", action="store_true",
                          help="plot reference_position where the snapshot has it")
    snapshot.add_argument("--out", help="PNG file (default: RUN_DIR/snapshot_<field>.png)")
    snapshot.set_defaults(run=cmd_snapshot, reference=False)

    compare = commands.add_parser("compare", help="one probe field from several runs")
    compare.add_argument("--runs", required=True, help="comma-separated run directories")
    compare.add_argument("--field", required=True, help="probe column, e.g. tip.uy")
    compare.add_argument("--labels", help="comma-separated legend labels (default: run names)")
    compare.add_argument("--reference", action="append", default=[], help=reference_help)
    compare.add_argument("--level", action="append", default=[],
                         help="a constant reference VALUE[:LABEL] (an analytical static value); repeatable")
    compare.add_argument("--out", help="PNG file (default: compare_<field>.png)")
    compare.set_defaults(run=cmd_compare)
    return top


def main(argv=None):
    args = parser().parse_args(argv)
    try:
        args.run(args)
    except PlotError as error:
        print(f"plot.py: error: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
