#!/usr/bin/python3
"""The elastic gate of a coupled run, by finite elements under the same load history: is the particle gate's
response to the water's load right? (docs/VALIDATION.md section 25, issue 37)

Reads a run of cases/elastic_gate.toml with snapshots (every 0.5 ms: --set output.snapshot_interval=0.0005)
and takes, at every snapshot, the force the water put on each gate particle: its mass times the
interaction acceleration of seed Eq. 48 (the snapshot field structure_interaction). These forces act on the
finite-element gate of scripts/reference/fe_beam.py (plane-strain Q9, St. Venant-Kirchhoff, total Lagrangian) at the
particles' reference positions, spread on the nodes with the element's shape functions, linear in time
between snapshots, with the gate's weight. The gate is integrated by Newmark's average acceleration
(beta = 1/4, gamma = 1/2: no numerical damping), Newton's method in each step, from rest, and its tip is
set beside the run's tip probe. The loop is open: the finite-element gate's motion does not change the load.

    /usr/bin/python3 scripts/reference/fe_gate_history.py RUN [--elements 40 4] [--csv FILE] [--figure FILE]
"""
import argparse
import csv
import os
import sys

import numpy as np

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from fe_beam import Beam, Q9Solid
from gate_load import GateRun


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run")
    parser.add_argument("--elements", type=int, nargs=2, default=[40, 4], metavar=("NX", "NY"))
    parser.add_argument("--csv", help="write time, the finite-element tip and the run's tip here")
    parser.add_argument("--figure", help="plot both tips here (PNG)")
    a = parser.parse_args()

    run = GateRun(a.run)
    times, reference, forces = [], None, []
    for time, X, _, force, _ in run.snapshots():
        times.append(time)
        forces.append(force)
        reference = X
    times, forces = np.array(times), np.array(forces)
    case, material, x0, x1, clamp_y = run.case, run.material, run.x0, run.x1, run.clamp_y
    # The beam's axis runs from the clamp down to the free end; its y across the gate from the upstream
    # face: X = clamp_y - y, Y = x - x0, a rotation by 90 degrees, so that a force (f_x, f_y) is (-f_y, f_x).
    beam = Beam(clamp_y, x1 - x0, material["youngs_modulus"], material["poisson_ratio"], material.get("plane", "strain"),
                density=material["density"], probe_x=clamp_y)
    solid = Q9Solid(beam, *a.elements)
    points = np.stack([clamp_y - reference[:, 1], reference[:, 0] - x0], 1)
    P = solid.point_loads(points)
    beam_forces = np.stack([-forces[:, :, 1], forces[:, :, 0]], 2).reshape(len(times), -1)
    M = solid.mass()
    gravity = np.tile([-case["gravity"][1], case["gravity"][0]], solid.n_nodes)
    weight = M @ gravity
    free = solid.free
    Mf = M[np.ix_(free, free)]

    def load(k):
        return P @ beam_forces[k] + weight

    n = 2 * solid.n_nodes
    u, v, acc = np.zeros(n), np.zeros(n), np.zeros(n)
    K, R = solid.tangent_and_residual(u)
    acc[free] = np.linalg.solve(Mf, (load(0) - R)[free])
    tip = [solid.probe(u)]
    for k in range(1, len(times)):
        dt = times[k] - times[k - 1]
        # Newmark, beta = 1/4: a_new = 4 (u_new - u - dt v) / dt^2 - a; v_new = v + dt (a + a_new) / 2.
        u_new, f = u + dt * v + dt * dt / 4 * acc, load(k)
        for _ in range(30):
            a_new = 4 * (u_new - u - dt * v) / dt**2 - acc
            K, R = solid.tangent_and_residual(u_new)
            residual = (f - R - M @ a_new)[free]
            du = np.linalg.solve(K[np.ix_(free, free)] + 4 / dt**2 * Mf, residual)
            u_new[free] += du
            if np.linalg.norm(du) <= 1e-10 * max(np.linalg.norm(u_new), 1e-12):
                break
        else:
            raise RuntimeError(f"Newton did not converge at t = {times[k]:.4f} s")
        a_new = 4 * (u_new - u - dt * v) / dt**2 - acc
        v = v + dt / 2 * (acc + a_new)
        u, acc = u_new, a_new
        tip.append(solid.probe(u))
    tip = np.array(tip)
    fe_ux, fe_uy = tip[:, 1], -tip[:, 0]   # back to the tank's axes

    rows = list(csv.DictReader(open(f"{a.run}/probes.csv")))
    t_run = np.array([float(r["time"]) for r in rows])
    run_ux = np.interp(times, t_run, [float(r["tip.ux"]) for r in rows])
    run_uy = np.interp(times, t_run, [float(r["tip.uy"]) for r in rows])
    if a.csv:
        with open(a.csv, "w") as out:
            out.write("time,fe.ux,fe.uy,run.ux,run.uy\n")
            for row in zip(times, fe_ux, fe_uy, run_ux, run_uy):
                out.write(",".join(f"{x:.6g}" for x in row) + "\n")

    def summary(name, ux, uy):
        peak = int(np.argmax(ux))
        low = peak + int(np.argmin(ux[peak:]))
        print(f"{name:>16}: peak u_x {1e3 * ux[peak]:.2f} mm at {times[peak]:.3f} s, minimum after it "
              f"{1e3 * ux[low]:.2f} mm at {times[low]:.3f} s, u_x at 0.20 s {1e3 * np.interp(0.2, times, ux):.2f} mm, "
              f"largest u_y {1e3 * uy.max():.2f} mm")
    print(f"{len(times)} snapshots, {len(reference)} loaded particles, Q9 {a.elements[0]} x {a.elements[1]}")
    summary("finite elements", fe_ux, fe_uy)
    summary("the run", run_ux, run_uy)
    print(f"RMS difference: u_x {1e3 * np.sqrt(np.mean((fe_ux - run_ux)**2)):.2f} mm, "
          f"u_y {1e3 * np.sqrt(np.mean((fe_uy - run_uy)**2)):.2f} mm")
    if a.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot(times, 1e3 * run_ux, label="the coupled run (TLSPH): u_x")
        ax.plot(times, 1e3 * fe_ux, "--", label="finite elements under its load: u_x")
        ax.plot(times, 1e3 * run_uy, label="the coupled run (TLSPH): u_y")
        ax.plot(times, 1e3 * fe_uy, "--", label="finite elements under its load: u_y")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("tip displacement [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.figure, dpi=120)


if __name__ == "__main__":
    main()
