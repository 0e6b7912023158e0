#!/usr/bin/python3
"""Largest stable Courant number of the structure integrators, by bisection.

For each variant (integrator x kernel correction) the case is run for a short time at a trial
Courant number; a run is *stable* when it completes (no divergence) and its total energy stays
within --energy-tol of the initial value (a growing energy is the first sign of instability).
Writes <out>/stability.csv and <out>/stability.md (a table) and prints the table.

  /usr/bin/python3 scripts/validate/stability_courant.py cases/oscillating_plate.toml --out runs/stability
"""
import argparse
import csv
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run_is_stable(isph, case, out, courant, sets, end_time, energy_tol):
    cmd = [isph, "run", case, "--out", out, "--quiet", "--set", f"end_time={end_time}",
           "--set", f"structure.courant={courant}", "--set", "output.snapshots=false"]
    for s in sets:
        cmd += ["--set", s]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode not in (0, 3):
        sys.exit(f"isph failed ({proc.returncode}): {proc.stderr.strip()}")
    if proc.returncode == 3:
        return False, "diverged"
    with open(os.path.join(out, "energy.csv")) as f:
        rows = list(csv.DictReader(f))
    e0 = float(rows[0]["total"])
    drift = max(abs(float(r["total"]) - e0) for r in rows) / abs(e0)
    return drift <= energy_tol, f"energy drift {drift:.2e}"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("case")
    p.add_argument("--out", default="runs/stability")
    p.add_argument("--isph", default=os.path.join(ROOT, "build", "isph"))
    p.add_argument("--end-time", type=float, default=0.2)
    p.add_argument("--energy-tol", type=float, default=0.01)
    p.add_argument("--low", type=float, default=0.05)
    p.add_argument("--high", type=float, default=4.0)
    p.add_argument("--iterations", type=int, default=7)
    p.add_argument("--set", action="append", default=[], help="extra overrides for every run")
    a = p.parse_args(argv)

    variants = [(integ, corr) for integ in ("rk4", "verlet") for corr in ("true", "false")]
    os.makedirs(a.out, exist_ok=True)
    results = []
    for integ, corr in variants:
        lo, hi = a.low, a.high
        name = f"{integ}_correction_{corr}"
        run_dir = os.path.join(a.out, name)
        sets = a.set + [f'structure.integrator="{integ}"', f"kernel.correction={corr}"]
        ok, why = run_is_stable(a.isph, a.case, run_dir, lo, sets, a.end_time, a.energy_tol)
        if not ok:
            results.append((integ, corr, 0.0, lo, why))
            continue
        for _ in range(a.iterations):
            mid = 0.5 * (lo + hi)
            ok, why = run_is_stable(a.isph, a.case, run_dir, mid, sets, a.end_time, a.energy_tol)
            lo, hi = (mid, hi) if ok else (lo, mid)
            print(f"  {name}: courant {mid:.3f} -> {'stable' if ok else 'unstable'} ({why})", flush=True)
        results.append((integ, corr, lo, hi, ""))

    with open(os.path.join(a.out, "stability.csv"), "w") as f:
        f.write("integrator,correction,largest_stable_courant,smallest_unstable_courant\n")
        for integ, corr, lo, hi, _ in results:
            f.write(f"{integ},{corr},{lo:.4f},{hi:.4f}\n")
    table = ["| integrator | kernel correction | largest stable Courant | smallest unstable |", "|---|---|---|---|"]
    for integ, corr, lo, hi, why in results:
        table.append(f"| {integ} | {'on' if corr == 'true' else 'off'} | {lo:.3f} | {hi:.3f} {why} |")
    text = "\n".join(table) + "\n"
    with open(os.path.join(a.out, "stability.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
