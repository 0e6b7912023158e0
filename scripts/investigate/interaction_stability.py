#!/usr/bin/python3
"""Where the interpolated alpha(f->s) fails: the hydrostatic plate under water columns of growing depth.

`coupling.substep_interaction = "interpolated"` ramps the interaction acceleration over the substeps
from the previous step's converged value to the iterate's, so part of the load that moves the
structure in a step is the previous step's: an explicit share of the added mass. This script runs the
plate (cases/hydrostatic_plate.toml, T/dx = 4) under columns H deep with both settings, writing a probe
row every fluid step, and compares what it measures with a model of that loop.

Measured, per run: the chord acceleration at mid-span, a^{n+1} = (vbar^{n+1} - vbar^n)/dt with
vbar^{n+1} = (u^{n+1} - u^n)/dt (what the fluid is handed), and its growth per step over the longest
stretch in which it changes sign every step and grows.

Model: one rigid mode of mass m under an added mass M (the fluid's force on it is -M a), its motion over a
step integrated exactly under the load of that step: held, f^{n+1} throughout; interpolated, the ramp
from f^n to f^{n+1}, which puts f^n and f^{n+1} into the chord displacement with weights 1/3 and 1/6
(dt^2/m). The step's amplification matrix has an eigenvalue that changes sign every step:
-M/(M + 2m) held (always inside the unit circle), and for interpolated one that passes -1 at M = 3m.

M/m for the plate's first clamped-clamped mode phi: potential flow between the side walls, with p = 0 at
the free surface (the fast-load limit), expanded in cos(n pi x/L): M = rho sum_n c_n^2 (L/2) tanh(k_n H)/k_n
(n >= 1) + rho H (int phi)^2/L (n = 0, the column moving with the mean deflection), against the mode's
mass m = rho_s T int phi^2.

Writes <out>/interaction_stability.md (the table), <figures>/coupled_plate_interaction_stability.png,
and prints the table.

  /usr/bin/python3 scripts/investigate/interaction_stability.py --out runs/interaction_stability
"""
import argparse
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

# the sibling folders' modules (scripts/README.md)
sys.path[:0] = [os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, d)
                for d in ("lib", "validate", "reference")]
from report_common import ROOT, plt, np, read_probes, save, summary

L, T, RHO, RHO_S = 1.0, 0.05, 1000.0, 2700.0  # span, thickness, water and aluminium densities
E, NU, G = 67.5e9, 0.34, 9.81


def static_deflection(column):
    """Seed Eq. 53 (plane strain, the plate's weight included)."""
    return 12 * G * (1 - NU * NU) * (RHO * column + RHO_S * T) * L**4 / (384 * E * T**3)


def mode_shape(x):
    """First bending mode of a beam clamped at x = 0 and x = L."""
    b = 4.730040745
    s = (np.cosh(b) - np.cos(b)) / (np.sinh(b) - np.sin(b))
    xi = b * x / L
    return np.cosh(xi) - np.cos(xi) - s * (np.sinh(xi) - np.sin(xi))


def added_mass_ratio(column, terms=400):
    x = np.linspace(0.0, L, 20001)
    phi = mode_shape(x)
    added = RHO * column * np.trapz(phi, x) ** 2 / L
    for n in range(1, terms):
        k = n * np.pi / L
        c = 2 * np.trapz(phi * np.cos(k * x), x) / L
        added += RHO * c * c * (L / 2) * np.tanh(k * column) / k
    return added / (RHO_S * T * np.trapz(phi * phi, x))


def model_growth(mu, interpolated):
    """Largest |eigenvalue| of one step of the rigid mode (m = 1, dt = 1) under the added mass mu, the
    eigenvalue 1 of the mode's own uniform motion left out; the state is (v^n, vbar^n, f^n): end
    velocity, chord velocity and the step's load."""
    w_old, w_new = (1 / 3, 1 / 6) if interpolated else (0.0, 0.5)  # weights of f^n, f^{n+1} in vbar^{n+1}
    u_old, u_new = (0.5, 0.5) if interpolated else (0.0, 1.0)      # ... and in v^{n+1}
    # f^{n+1} = -mu (vbar^{n+1} - vbar^n), solved for f^{n+1}:
    f_new = np.array([-mu, mu, -mu * w_old]) / (1 + mu * w_new)
    step = np.array([np.array([1, 0, u_old]) + u_new * f_new, np.array([1, 0, w_old]) + w_new * f_new, f_new])
    eigenvalues = sorted(np.linalg.eigvals(step), key=lambda z: abs(z - 1))
    return max(abs(z) for z in eigenvalues[1:])


def chord_acceleration(run):
    p = read_probes(run)
    t, u = p["time"], p["midspan.uy"]
    dt = np.diff(t)
    vbar = np.diff(u) / dt
    return t[2:], np.diff(vbar) / dt[1:]


def measured_growth(a):
    """Geometric mean of |a_{k+1}/a_k| over the longest run of steps that change sign and grow, with
    the run's length; (nan, 0) when no two consecutive steps do."""
    best, k = (0, 0), 0
    while k < len(a) - 1:
        j = k
        while j < len(a) - 1 and a[j] * a[j + 1] < 0 and abs(a[j + 1]) > abs(a[j]):
            j += 1
        if j - k > best[1] - best[0]:
            best = (k, j)
        k = j + 1
    i, j = best
    return ((abs(a[j]) / abs(a[i])) ** (1.0 / (j - i)), j - i) if j > i else (float("nan"), 0)


def run_plate(isph, out, column, mode, end_time):
    walls = column + 0.1
    cmd = [isph, "run", os.path.join(ROOT, "cases", "hydrostatic_plate.toml"), "--quiet", "--threads", "1",
           "--out", out, "--set", "dx=0.0125", "--set", f"end_time={end_time}",
           "--set", "output.interval=1e-7", "--set", "output.snapshots=false",
           "--set", f'bodies.water.shape={{type="rectangle",min=[0.0,0.0],max=[1.0,{column}]}}',
           "--set", f'bodies.left_wall.shape={{type="rectangle",min=[-0.0375,0.0],max=[0.0,{walls}]}}',
           "--set", f'bodies.right_wall.shape={{type="rectangle",min=[1.0,0.0],max=[1.0375,{walls}]}}',
           "--set", f'coupling.substep_interaction="{mode}"']
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode not in (0, 3):  # 3: the run diverged, which is an outcome here
        sys.exit(f"isph failed ({proc.returncode}): {proc.stdout[-2000:]}{proc.stderr[-2000:]}")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="runs/interaction_stability")
    p.add_argument("--figures", default=os.path.join(ROOT, "docs", "figures"))
    p.add_argument("--isph", default=os.path.join(ROOT, "build", "isph"))
    p.add_argument("--columns", default="0.5,0.75,1.0,1.5,2.0", help="water depths H [m]")
    p.add_argument("--end-time", type=float, default=0.02)
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    p.add_argument("--reuse", action="store_true", help="tabulate the runs already in --out")
    a = p.parse_args(argv)

    columns = [float(c) for c in a.columns.split(",")]
    modes = ("held", "interpolated")
    runs = {(c, m): os.path.join(a.out, f"H{c:g}_{m}") for c in columns for m in modes}
    if not a.reuse:
        with ThreadPoolExecutor(a.jobs) as pool:
            list(pool.map(lambda key: run_plate(a.isph, runs[key], key[0], key[1], a.end_time), runs))

    header = ["H [m]", "column / plate mass", "mode's added / own mass", "alpha(f->s)", "model: growth per step",
              "measured: growth per step (over steps)", "status", "t reached [s]", "peak -u_y / static"]
    rows = []
    fig, (ax_t, ax_mu) = plt.subplots(1, 2, figsize=(12, 4.5))
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(columns)))
    for colour, c in zip(colours, columns):
        mu = added_mass_ratio(c)
        for m in modes:
            run = runs[(c, m)]
            s = summary(run)
            t, acc = chord_acceleration(run)
            growth, steps = measured_growth(acc)
            peak = -read_probes(run)["midspan.uy"].min() / static_deflection(c)
            rows.append([f"{c:g}", f"{RHO * c / (RHO_S * T):.2f}", f"{mu:.2f}", m,
                         f"{model_growth(mu, m == 'interpolated'):.2f}",
                         f"{growth:.2f} ({steps})" if steps >= 4 else "none", s["status"],
                         f"{t[-1]:.4f}" if len(t) else "-", f"{peak:.3g}"])
            ax_t.semilogy(t * 1e3, np.abs(acc), "-" if m == "interpolated" else ":", color=colour,
                          label=f"H = {c:g} m, {m}")
        growth, steps = measured_growth(chord_acceleration(runs[(c, "interpolated")])[1])
        if steps >= 4:
            ax_mu.plot(mu, growth, "o", color=colour)
    mus = np.linspace(0.2, 12, 300)
    ax_mu.plot(mus, [model_growth(x, True) for x in mus], "k-", label="model, interpolated")
    ax_mu.plot(mus, [model_growth(x, False) for x in mus], "k:", label="model, held")
    ax_mu.axhline(1.0, color="grey", lw=0.5)
    ax_mu.set_xlabel("added mass / mode mass, M/m")
    ax_mu.set_ylabel("growth per fluid step")
    ax_mu.set_title("sign-flipping mode: model and runs (dots)")
    ax_mu.legend(fontsize=8)
    ax_t.set_xlabel("t [ms]")
    ax_t.set_ylabel("|chord acceleration at mid-span| [m/s²]")
    ax_t.set_title("hydrostatic plate, T/dx = 4, one row per fluid step")
    ax_t.legend(fontsize=7, ncol=2, loc="upper left")
    fig.tight_layout()

    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "interaction_stability.md"), "w") as f:
        f.write("| " + " | ".join(header) + " |\n|" + "---|" * len(header) + "\n")
        for r in rows:
            f.write("| " + " | ".join(r) + " |\n")
    with open(os.path.join(a.out, "interaction_stability.md")) as f:
        print(f.read(), end="")
    save(fig, a, "coupled_plate_interaction_stability.png")


if __name__ == "__main__":
    main()
