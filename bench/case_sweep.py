#!/usr/bin/python3
"""Whole-case benchmark driver: the dam break and the elastic gate scaled from 1e4 to millions of
fluid particles (2D), and the 3D dam break of cases/dam_break_obstacle_3d.toml, a few steps from rest each, on
the CPU or the GPU.

    /usr/bin/python3 bench/case_sweep.py [--cases dam_break,elastic_gate,dam_break_3d] [--sizes 1e4,1e5,1e6,4e6]
        [--device cpu|cuda] [--threads 1,2] [--backend eigen] [--preconditioner P] [--out DIR]
        [--kernels] [--timeout SECONDS]

For each case, size and thread count it runs `build/isph run` with dx = (fluid area or volume / size)^(1/D), walls
three particles thick at that dx, no snapshots, and an end time of (steps - 1/2) fluid steps estimated
from Eq. 49 at rest (20 steps below 5e4 particles, 8 below 5e5, 3 above). From each run's
summary.json it reports fluid particle-steps per second of stepping time, structure particle-substeps per
second of the structure phase, the mean
Krylov iterations of the PPE and the per-phase times. With --kernels it adds, at the same sizes, the
neighbour-pass table of build/isph_pair_bench (pair evaluations per second of one pass) and the SpMV
table of build/isph_ppe_bench --spmv-only (bandwidth as a fraction of the copy bandwidth).
Markdown goes to stdout and DIR/sweep.md; every run's summary.json is kept under DIR.
"""
import argparse
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ISPH = os.environ.get("ISPH", os.path.join(ROOT, "build", "isph"))
G = 9.81

# The scaled geometry of each case: the fluid's area (2D) or volume (3D) and height (for dx and the
# reference velocity of Eq. 49) and its walls as rectangles or boxes of the wall thickness t = 3 dx (the
# case files use their own dx).
TANK_3D = (3.22, 1.0, 1.0)  # cases/dam_break_obstacle_3d.toml
CASES = {
    "dam_break": {
        "file": "cases/dam_break.toml",
        "fluid_measure": 0.146 * 0.292,
        "fluid_height": 0.292,
        "walls": lambda t: {
            "floor": ([-t, -t], [4 * 0.146 + t, 0.0]),
            "left_wall": ([-t, 0.0], [0.0, 8 * 0.146]),
            "right_wall": ([4 * 0.146, 0.0], [4 * 0.146 + t, 8 * 0.146]),
        },
    },
    "elastic_gate": {
        "file": "cases/elastic_gate.toml",
        "sets": ["bodies.gate.refinement=1"],  # the gate at the water's spacing, as the sizes scale both
        "fluid_measure": 0.1 * 0.14,
        "fluid_height": 0.14,
        "walls": lambda t: {
            "floor": ([-t, -t], [0.5 + t, 0.0]),
            "left_wall": ([-t, 0.0], [0.0, 0.2]),
            "right_wall": ([0.5, 0.0], [0.5 + t, 0.2]),
        },
    },
    "dam_break_3d": {
        "file": "cases/dam_break_obstacle_3d.toml",
        "dimension": 3,
        "fluid_measure": 1.228 * 1.0 * 0.55,
        "fluid_height": 0.55,
        "walls": lambda t: {
            "floor": ([-t, -t, -t], [TANK_3D[0] + t, TANK_3D[1] + t, 0.0]),
            "wall_x0": ([-t, 0.0, 0.0], [0.0, TANK_3D[1], TANK_3D[2]]),
            "wall_x1": ([TANK_3D[0], 0.0, 0.0], [TANK_3D[0] + t, TANK_3D[1], TANK_3D[2]]),
            "wall_y0": ([-t, -t, 0.0], [TANK_3D[0] + t, 0.0, TANK_3D[2]]),
            "wall_y1": ([-t, TANK_3D[1], 0.0], [TANK_3D[0] + t, TANK_3D[1] + t, TANK_3D[2]]),
        },
    },
}
PHASES = ("neighbours", "predictor", "free_surface", "ppe_assembly", "ppe_solve", "projection", "shifting",
          "interaction", "structure")


def run_args(case, size, args):
    c = CASES[case]
    dimension = c.get("dimension", 2)
    dx = (c["fluid_measure"] / size) ** (1 / dimension)
    steps = 20 if size < 5e4 else (8 if size < 5e5 else 3)
    dt = 0.1 * 1.2 * dx / math.sqrt(2 * G * c["fluid_height"])  # Eq. 49 at rest, default courant 0.1
    sets = [f"dx={dx:.9g}", f"end_time={(steps - 0.5) * dt:.9g}", "output.snapshots=false",
            f"fluid.ppe.backend={args.backend}"] + c.get("sets", [])
    if args.preconditioner:
        sets.append(f"fluid.ppe.preconditioner={args.preconditioner}")
    for name, (lo, hi) in c["walls"](3 * dx).items():
        shape = "rectangle" if dimension == 2 else "box"
        sets.append(f"bodies.{name}.shape={{type=\"{shape}\",min=[{','.join(f'{v:.9g}' for v in lo)}],"
                    f"max=[{','.join(f'{v:.9g}' for v in hi)}]}}")
    return c["file"], sets


def run(case, size, threads, args):
    out = os.path.join(args.out, f"{case}_{size:.0e}_{args.device}_{threads}t")
    case_file, sets = run_args(case, size, args)
    cmd = [ISPH, "run", os.path.join(ROOT, case_file), "--out", out, "--threads", str(threads), "--device",
           args.device, "--quiet"] + [a for s in sets for a in ("--set", s)]
    try:
        result = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout or None)
    except subprocess.TimeoutExpired:
        return None, f"stopped after {args.timeout:g} s (--timeout)"
    summary = os.path.join(out, "summary.json")
    if not os.path.exists(summary):
        return None, (result.stderr.strip().splitlines() or ["no summary.json"])[-1]
    return json.load(open(summary)), None


def row(case, size, threads, s, error):
    if s is None:
        return f"| {case} | {size:.0e} | {threads} | failed: {error} |" + " |" * (8 + len(PHASES))
    ph, p, parts = s["phases"], s["performance"], s["particles"]
    stepping = sum(v for k, v in ph.items() if k not in ("setup", "output"))
    fluid_rate = parts["fluid"] * s["steps"]["fluid"] / stepping if stepping > 0 else 0
    structure_time = ph.get("structure", 0)
    structure_rate = parts["structure"] * s["steps"]["structure"] / structure_time if structure_time > 0 else 0
    status = "" if s["status"] == "completed" else f" ({s['status']})"
    return (f"| {case} | {parts['fluid']} | {parts['wall']} | {parts['structure']} | {threads} | {s['device']} | "
            f"{s['ppe']['solver']} | {s['steps']['fluid']} | {stepping:.2f}{status} | {fluid_rate:.3g} | "
            f"{structure_rate:.3g} | {s['ppe']['mean_iterations']:.1f} | " +
            " | ".join(f"{ph.get(k, 0):.2f}" for k in PHASES) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="dam_break,elastic_gate")
    ap.add_argument("--sizes", default="1e4,1e5,1e6,4e6")
    ap.add_argument("--device", default="cpu", choices=("cpu", "cuda"))
    ap.add_argument("--threads", default="1")
    ap.add_argument("--backend", default="eigen")
    ap.add_argument("--preconditioner", default="")
    ap.add_argument("--out", default=os.path.join(ROOT, "runs", "bench", "case_sweep"))
    ap.add_argument("--kernels", action="store_true")
    ap.add_argument("--timeout", type=float, default=0, help="seconds after which a run is stopped (0: none)")
    args = ap.parse_args()
    cases = args.cases.split(",")
    for c in cases:
        if c not in CASES:
            sys.exit(f"case_sweep: unknown case '{c}' (known: {', '.join(CASES)})")
    sizes = [float(s) for s in args.sizes.split(",")]
    threads = [int(t) for t in args.threads.split(",")]
    os.makedirs(args.out, exist_ok=True)
    lines = [
        "| case | fluid | wall | structure | threads | device | PPE solver | fluid steps | stepping time [s] | "
        "fluid particle-steps/s | structure particle-substeps/s (structure phase) | PPE iterations | " +
        " | ".join(f"{k} [s]" for k in PHASES) + " |",
        "|---|---:|---:|---:|---:|---|---|---:|---:|---:|---:|---:|" + "---:|" * len(PHASES),
    ]
    print("\n".join(lines), flush=True)
    for case in cases:
        for size in sizes:
            for t in threads:
                s, error = run(case, size, t, args)
                lines.append(row(case, size, t, s, error))
                print(lines[-1], flush=True)
    if args.kernels:
        env = dict(os.environ, OMP_NUM_THREADS=str(max(threads)))
        for tool in (["isph_pair_bench"], ["isph_ppe_bench", "--spmv-only"]):
            cmd = [os.path.join(os.path.dirname(ISPH), tool[0])] + tool[1:] + [f"{s:g}" for s in sizes]
            text = subprocess.run(cmd, capture_output=True, text=True, env=env).stdout
            lines += ["", text.strip()]
            print("\n" + text.strip(), flush=True)
    with open(os.path.join(args.out, "sweep.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
