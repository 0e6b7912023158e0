#!/usr/bin/python3
"""The plate of cases/hydrostatic_plate_3d.toml as a 3D continuum, by finite elements: the reference
that the particle solution is checked against (docs/VALIDATION.md section 32).

A square aluminium plate, a = 1 m (--span) between the clamps' faces and T = 0.05 m thick (E = 67.5 GPa,
nu = 0.34, rho = 2700 kg/m^3), clamped over its whole edge faces (u = 0 on x = 0, x = a, y = 0, y = a, as
the particles in the clamps beyond the walls hold it), loaded by a pressure on its top face (--pressure;
by default rho_w g H under the case's 0.5 m of water) and by its own weight. Deflections are a
thousandth of the thickness, so linear elasticity is the limit of the solver's St. Venant-Kirchhoff solid.

One quarter of the plate, with symmetry (u_x = 0 on x = a/2, u_y = 0 on y = a/2), in triquadratic
(27-node) hexahedra with 3 x 3 x 3 Gauss points; consistent nodal forces for the pressure and the
weight. Dense linear algebra (numpy only). Prints the deflection at the centre, mid-thickness (the
probe `centre`), beside thin-plate (Kirchhoff) theory: w = 0.00126 q a^4 / D, D = E T^3 / (12 (1 - nu^2))
(Timoshenko & Woinowsky-Krieger 1959, Theory of Plates and Shells, Table 35, clamped square plate under
a uniform load q).

    /usr/bin/python3 scripts/reference/fe_plate_3d.py --elements 8 1       # seconds
    /usr/bin/python3 scripts/reference/fe_plate_3d.py --elements 16 2      # 15,000 unknowns, minutes
    /usr/bin/python3 scripts/reference/fe_plate_3d.py --span 0.5 --pressure 1e5   # the plate of tests/regression/test_plate_3d.cpp
"""
import argparse

import numpy as np

from fe_beam import lagrange

THICKNESS = 0.05
YOUNGS, POISSON, DENSITY = 67.5e9, 0.34, 2700.0
WATER_DENSITY, GRAVITY, HEAD = 1000.0, 9.81, 0.5  # the case's water column


def thin_plate(span, pressure):
    """Kirchhoff's centre deflection 0.00126 q a^4 / D under the pressure and the plate's weight."""
    load = pressure + DENSITY * GRAVITY * THICKNESS
    return 0.00126 * load * span**4 / (YOUNGS * THICKNESS**3 / (12 * (1 - POISSON**2)))


def element_stiffness(size, C):
    """K_e = sum over Gauss points of B^T C B det J w, for a box element of the given edge lengths;
    nodes ordered (i, j, k) with k fastest, each with its three displacement components."""
    gauss, weights = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]), np.array([5, 8, 5]) / 9
    K = np.zeros((81, 81))
    jacobian = np.asarray(size) / 2
    for gx, wx in zip(gauss, weights):
        for gy, wy in zip(gauss, weights):
            for gz, wz in zip(gauss, weights):
                (nx, dx), (ny, dy), (nz, dz) = lagrange(gx), lagrange(gy), lagrange(gz)
                grad = np.stack([np.einsum("i,j,k->ijk", dx, ny, nz).ravel() / jacobian[0],
                                 np.einsum("i,j,k->ijk", nx, dy, nz).ravel() / jacobian[1],
                                 np.einsum("i,j,k->ijk", nx, ny, dz).ravel() / jacobian[2]])
                B = np.zeros((6, 81))  # Voigt: xx, yy, zz, yz, xz, xy (engineering shear)
                for d in range(3):
                    B[d, d::3] = grad[d]
                B[3, 1::3], B[3, 2::3] = grad[2], grad[1]
                B[4, 0::3], B[4, 2::3] = grad[2], grad[0]
                B[5, 0::3], B[5, 1::3] = grad[1], grad[0]
                K += B.T @ C @ B * (wx * wy * wz * np.prod(jacobian))
    return K


def isotropic(E, nu):
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[np.arange(3), np.arange(3)] += 2 * mu
    C[np.arange(3, 6), np.arange(3, 6)] = mu
    return C


def solve(n_plane, n_thick, span, pressure):
    half = span / 2
    size = (half / n_plane, half / n_plane, THICKNESS / n_thick)
    nodes = (2 * n_plane + 1, 2 * n_plane + 1, 2 * n_thick + 1)
    node = lambda i, j, k: (i * nodes[1] + j) * nodes[2] + k
    dofs = 3 * np.prod(nodes)
    K = np.zeros((dofs, dofs))
    f = np.zeros(dofs)
    Ke = element_stiffness(size, isotropic(YOUNGS, POISSON))
    # Consistent nodal weights of a uniform load over one element: products of Simpson's 1/6, 4/6, 1/6.
    simpson = np.array([1, 4, 1]) / 6
    volume_weights = np.einsum("i,j,k->ijk", simpson, simpson, simpson).ravel() * np.prod(size)
    face_weights = np.outer(simpson, simpson) * size[0] * size[1]
    for ex in range(n_plane):
        for ey in range(n_plane):
            for ez in range(n_thick):
                local = [node(2 * ex + a, 2 * ey + b, 2 * ez + c) for a in range(3) for b in range(3) for c in range(3)]
                element_dofs = np.array([[3 * n, 3 * n + 1, 3 * n + 2] for n in local]).ravel()
                K[np.ix_(element_dofs, element_dofs)] += Ke
                f[3 * np.array(local) + 2] -= DENSITY * GRAVITY * volume_weights
                if ez == n_thick - 1:  # the top face, z = 0
                    for a in range(3):
                        for b in range(3):
                            f[3 * node(2 * ex + a, 2 * ey + b, nodes[2] - 1) + 2] -= pressure * face_weights[a, b]
    fixed = []
    for i in range(nodes[0]):
        for j in range(nodes[1]):
            for k in range(nodes[2]):
                n = node(i, j, k)
                if i == 0 or j == 0:  # the clamped faces x = 0 and y = 0
                    fixed += [3 * n, 3 * n + 1, 3 * n + 2]
                if i == nodes[0] - 1:  # symmetry about x = a/2
                    fixed.append(3 * n)
                if j == nodes[1] - 1:  # symmetry about y = a/2
                    fixed.append(3 * n + 1)
    free = np.setdiff1d(np.arange(dofs), np.unique(fixed))
    u = np.zeros(dofs)
    u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
    return u[3 * node(nodes[0] - 1, nodes[1] - 1, n_thick) + 2], free.size


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--elements", type=int, nargs=2, default=[8, 1], metavar=("N_PLANE", "N_THICK"),
                        help="elements along the quarter plate's side and through the thickness")
    parser.add_argument("--span", type=float, default=1.0, help="a [m] (default: the case's 1 m)")
    parser.add_argument("--pressure", type=float, default=WATER_DENSITY * GRAVITY * HEAD,
                        help="on the top face [Pa] (default: rho_w g H under the case's 0.5 m of water)")
    args = parser.parse_args()
    w, unknowns = solve(*args.elements, args.span, args.pressure)
    weight = DENSITY * GRAVITY * THICKNESS
    print(f"elements {args.elements[0]} x {args.elements[0]} x {args.elements[1]} (quarter), {unknowns} unknowns")
    print(f"load q = {args.pressure + weight:.1f} Pa (pressure {args.pressure:.1f}, plate weight {weight:.1f})")
    print(f"centre deflection, 3D continuum: {-w:.5e} m")
    print(f"thin-plate theory 0.00126 q a^4 / D: {thin_plate(args.span, args.pressure):.5e} m")


if __name__ == "__main__":
    main()
