#!/usr/bin/python3
"""The pairwise pressure force of a fluid on a flat wall, summed over the particle lattice, against the
continuum's (docs/VALIDATION.md section 33).

The force density on a wall particle a is f_a = -sum_b V_b (p_a + p_b) grad_a W_ab over the fluid
particles b (structure/interaction.hpp, BoundaryPressureForce). Under a uniform pressure P the force on
the wall, per unit area, is then P times

    2 / dx^(D-1) * sum over a in one column of wall particles, b in the fluid, of V_a V_b (-dW_ab/dn),

which is 1 for the continuum (the double integral of the kernel gradient over the two half-spaces is
1/2) and a constant of the kernel and h/dx on a lattice: it does not change with dx. A linear pressure
adds nothing in the continuum (its part is odd about the wall). Particles sit on cell centres, the wall's
rows at -dx/2, -3dx/2, ..., the fluid's at dx/2, 3dx/2, ...

With --offsets the fluid's lattice is shifted along the wall by a fraction of dx (its rows no longer stand
over the wall's columns, as in water flowing along a wall): the constant then depends on the shift. The
same table gives the force normalised by the aligned lattice's constant, which equals the first moment m
of the kernel gradient, sum_b V_b (r_b - r_a) (x) grad W_ab = m I on a full lattice (what a kernel gradient
correction, Bonet & Lok 1999, divides by there): exact on the aligned lattice, larger than 1 on average
over shifts.

    /usr/bin/python3 scripts/validate/lattice_wall_force.py [--h-factors 1.0 1.2 1.5]
    /usr/bin/python3 scripts/validate/lattice_wall_force.py --offsets 8 [--h-factors 1.2]
"""
import argparse
import itertools
import math


def cubic_spline_derivative(r, h, dimension):
    """dW/dr of the cubic B-spline with support 2h (Monaghan 1992)."""
    sigma = 10 / (7 * math.pi * h**2) if dimension == 2 else 1 / (math.pi * h**3)
    q = r / h
    if q < 1:
        return sigma * (-3 * q + 2.25 * q * q) / h
    if q < 2:
        return -sigma * 0.75 * (2 - q) ** 2 / h
    return 0.0


def lattice_factor(h_factor, dimension, dx=1.0, offset=0.0):
    h = h_factor * dx
    layers = math.ceil(2 * h_factor) + 1   # rows within the support on either side
    volume = dx**dimension
    total = 0.0
    for i in range(layers):                # the wall column's particles a, at (0, ..., -(i + 1/2) dx)
        ya = -(i + 0.5) * dx
        for j in range(layers):            # the fluid's rows b, at ((k...) dx, (j + 1/2) dx)
            yb = (j + 0.5) * dx
            for k in itertools.product(range(-layers, layers + 1), repeat=dimension - 1):
                tangential = [(kk + (offset if i_axis == 0 else 0.0)) * dx for i_axis, kk in enumerate(k)]
                r = math.sqrt(sum(t * t for t in tangential) + (yb - ya) ** 2)
                # the normal component (into the fluid) of grad_a W_ab = dW/dr (r_a - r_b) / r
                total += volume * volume * cubic_spline_derivative(r, h, dimension) * (ya - yb) / r
    return 2 * total / dx ** (dimension - 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--h-factors", type=float, nargs="+", default=[1.0, 1.2, 1.3, 1.5, 2.0])
    parser.add_argument("--offsets", type=int, default=0, help="shift the fluid along the wall by k/N dx, k < N")
    a = parser.parse_args()
    if a.offsets:
        for hf in a.h_factors:
            for dim in (2, 3):
                aligned = lattice_factor(hf, dim)
                raw = [lattice_factor(hf, dim, offset=k / a.offsets) for k in range(a.offsets)]
                print(f"h / dx = {hf:g}, {dim}D: shift / dx | pairwise | normalised by m")
                for k, value in enumerate(raw):
                    print(f"  {k / a.offsets:.3f} | {value:.5f} | {value / aligned:.5f}")
                mean = sum(raw) / len(raw)
                print(f"  mean | {mean:.5f} | {mean / aligned:.5f}")
        return
    print("| h / dx | 2D | 3D |")
    print("|---|---|---|")
    for hf in a.h_factors:
        print(f"| {hf:g} | {lattice_factor(hf, 2):.5f} | {lattice_factor(hf, 3):.5f} |")


if __name__ == "__main__":
    main()
