#!/usr/bin/python3
"""The cantilever of cases/cantilever.toml as a 2D continuum, by finite elements: a check, by another
method, of what the particle solution converges to (docs/VALIDATION.md section 1).

The elastica (the reference of ../shared/reference/README.md) is an inextensible, shear-rigid line. The
solver models a 2D plane-stress St. Venant-Kirchhoff solid, which also shears and stretches, and whose
end is clamped over its whole face. This script solves that solid: total-Lagrangian biquadratic (Q9)
elements, 3x3 Gauss points, the Green strain and S = lambda tr(E) I + 2 mu E, Newton's method on the
residual f_int(u) = f_ext in load steps, until the update is 1e-12 of u. u = 0 on the face x = 0; a uniform dead traction on the face
x = L (consistent nodal forces, Simpson's weights per element edge). It prints the displacement of the
end face's centre (L, 0), the solver's tip probe.

    /usr/bin/python3 scripts/fe_cantilever.py --elements 40 4            # elastica load, 1.75e6 N/m
    /usr/bin/python3 scripts/fe_cantilever.py --elements 40 4 --load 1.75e4

Dense linear algebra (numpy only): 80 x 8 elements (5,474 unknowns) takes a few minutes.
"""
import argparse

import numpy as np

LENGTH, THICKNESS = 0.1, 0.01
YOUNGS, POISSON = 210e9, 0.3


def lagrange(s):
    """The three quadratic shape functions on [-1, 1] and their derivatives."""
    return np.array([s * (s - 1) / 2, 1 - s * s, s * (s + 1) / 2]), np.array([s - 0.5, -2 * s, s + 0.5])


def solve(nx, ny, load, steps):
    lam = YOUNGS * POISSON / (1 - POISSON**2)  # plane stress
    mu = YOUNGS / (2 * (1 + POISSON))
    nodes_y = 2 * ny + 1
    node = lambda i, j: i * nodes_y + j
    n_nodes = (2 * nx + 1) * nodes_y
    elements = np.array([[node(2 * ex + a, 2 * ey + b) for a in range(3) for b in range(3)]
                         for ex in range(nx) for ey in range(ny)])
    hx, hy = LENGTH / nx, THICKNESS / ny
    gauss, weight = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]), np.array([5 / 9, 8 / 9, 5 / 9])
    grads, weights = [], []
    for a in range(3):
        for b in range(3):
            (na, da), (nb, db) = lagrange(gauss[a]), lagrange(gauss[b])
            grads.append(np.stack([np.outer(da, nb).ravel() * 2 / hx, np.outer(na, db).ravel() * 2 / hy], 1))
            weights.append(weight[a] * weight[b] * hx * hy / 4)
    G = np.array(grads)          # (gauss point, node of the element, reference direction)
    w = np.array(weights)
    C = np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])

    dofs = np.stack([2 * elements, 2 * elements + 1], 2).reshape(len(elements), 18)
    clamped = np.array([node(0, j) for j in range(nodes_y)])
    free = np.setdiff1d(np.arange(2 * n_nodes), np.concatenate([2 * clamped, 2 * clamped + 1]))
    f_ext = np.zeros(2 * n_nodes)
    for ey in range(ny):
        for k, c in enumerate((1 / 6, 4 / 6, 1 / 6)):
            f_ext[2 * node(2 * nx, 2 * ey + k) + 1] -= load / THICKNESS * hy * c

    def tangent_and_residual(u):
        ue = u[dofs].reshape(len(elements), 9, 2)                            # (e, node, i)
        F = np.eye(2) + np.einsum("eai,gaJ->egiJ", ue, G)                    # F_iJ at each Gauss point
        E = 0.5 * (np.einsum("egiI,egiJ->egIJ", F, F) - np.eye(2))
        S = lam * np.trace(E, axis1=2, axis2=3)[..., None, None] * np.eye(2) + 2 * mu * E
        # B: dE (Voigt: 11, 22, 2*12) per nodal displacement du_{a,i}
        B = np.zeros(F.shape[:2] + (3, 9, 2))
        B[..., 0, :, :] = np.einsum("egi,ga->egai", F[..., :, 0], G[..., 0])
        B[..., 1, :, :] = np.einsum("egi,ga->egai", F[..., :, 1], G[..., 1])
        B[..., 2, :, :] = (np.einsum("egi,ga->egai", F[..., :, 0], G[..., 1]) +
                           np.einsum("egi,ga->egai", F[..., :, 1], G[..., 0]))
        B = B.reshape(F.shape[:2] + (3, 18))
        Sv = np.stack([S[..., 0, 0], S[..., 1, 1], S[..., 0, 1]], -1)
        Re = np.einsum("g,egvk,egv->ek", w, B, Sv)
        Ke = np.einsum("g,egvk,vw,egwl->ekl", w, B, C, B, optimize=True)
        geometric = np.einsum("g,gaI,egIJ,gbJ->eab", w, G, S, G, optimize=True)               # G S G^T, per displacement component
        Ke[:, 0::2, 0::2] += geometric
        Ke[:, 1::2, 1::2] += geometric
        n = 2 * n_nodes
        K = np.bincount((dofs[:, :, None] * n + dofs[:, None, :]).ravel(), Ke.ravel(), n * n).reshape(n, n)
        R = np.bincount(dofs.ravel(), Re.ravel(), n)
        return K, R

    u = np.zeros(2 * n_nodes)
    for step in range(1, steps + 1):
        target = f_ext * step / steps
        for _ in range(30):
            K, R = tangent_and_residual(u)
            du = np.linalg.solve(K[np.ix_(free, free)], (target - R)[free])
            u[free] += du
            if np.linalg.norm(du) <= 1e-12 * np.linalg.norm(u):
                break
        else:
            raise RuntimeError(f"Newton did not converge in load step {step}")
    return u.reshape(-1, 2)[node(2 * nx, ny)]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--elements", type=int, nargs=2, default=[40, 4], metavar=("NX", "NY"))
    parser.add_argument("--load", type=float, default=1.75e6, help="end load per unit depth [N/m]")
    parser.add_argument("--steps", type=int, default=10, help="load steps")
    a = parser.parse_args()
    ux, uy = solve(a.elements[0], a.elements[1], a.load, a.steps)
    print(f"Q9 {a.elements[0]} x {a.elements[1]}, load {a.load:g} N/m: tip u_x = {ux * 1e3:.6f} mm, "
          f"u_y = {uy * 1e3:.6f} mm (delta_v/L = {-uy / LENGTH:.6f}, delta_h/L = {-ux / LENGTH:.6f})")


if __name__ == "__main__":
    main()
