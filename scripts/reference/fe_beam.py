#!/usr/bin/python3
"""The beams of cases/cantilever.toml, cases/hydrostatic_plate_dry.toml and cases/liao_plate_dry.toml as
2D continua, by finite elements: a check, by another method, of what the particle solution converges
to (docs/VALIDATION.md sections 1, 13 and 19).

The references of ../shared/reference/README.md are beam theories: the elastica (an inextensible,
shear-rigid line) for the cantilever, thin-plate theory for the clamped plate. The solver models a 2D
St. Venant-Kirchhoff solid, which also shears and stretches, and whose ends are clamped over their whole
faces. This script solves that solid: total-Lagrangian biquadratic (Q9) elements, 3x3 Gauss points, the
Green strain and S = lambda tr(E) I + 2 mu E, Newton's method on the residual f_int(u) = f_ext in load
steps, until the update is 1e-12 of u. Dead loads with consistent nodal forces (Simpson's weights per
element edge).

  cantilever  L = 0.1, T = 0.01, E = 210 GPa, nu = 0.3, plane stress; u = 0 on x = 0; a uniform traction
              on x = L (--load, N per m of depth). Prints u at the end face's centre (L, 0), the tip probe.
  plate       L = 1 (between the clamps' faces), T = 0.05, E = 67.5 GPa, nu = 0.34, plane strain, rho = 2700;
              u = 0 on x = 0 and x = L; the water's pressure rho_w g H = 19,620 Pa on the top face and the
              plate's weight (g = 9.81). Prints u at mid-span, mid-thickness, the midspan probe.
  liao        the elastic plate of cases/baffle_liao.toml: L = 0.09, T = 0.004, E = 3.5 MPa, nu = 0.45, plane
              strain, weightless; u = 0 on x = 0; a uniform traction on one long face (--load, Pa; dead,
              normal to the undeformed face). Prints u at the free end's centre, the tip probe. The
              beam's x is the plate's height and the load's direction its -y.
  gate        the free part of the elastic gate of cases/elastic_gate.toml, loaded like liao: L = 0.079,
              T = 0.005, E = 12 MPa, nu = 0.4, plane strain (docs/VALIDATION.md section 25).

    /usr/bin/python3 scripts/reference/fe_beam.py cantilever --elements 40 4            # elastica load, 1.75e6 N/m
    /usr/bin/python3 scripts/reference/fe_beam.py cantilever --elements 40 4 --load 1.75e4
    /usr/bin/python3 scripts/reference/fe_beam.py plate --elements 160 8
    /usr/bin/python3 scripts/reference/fe_beam.py liao --elements 60 3 --load 400 --steps 20    # about 3 minutes

Dense linear algebra (numpy only): 80 x 8 elements (5,474 unknowns) takes a few minutes.
"""
import argparse
from dataclasses import dataclass

import numpy as np


@dataclass
class Beam:
    length: float
    thickness: float
    youngs: float
    poisson: float
    plane: str                 # "stress" or "strain"
    density: float = 0.0       # [kg/m^3], with gravity 9.81 m/s^2 downwards (0: weightless)
    clamped_ends: tuple = (0,)  # faces with u = 0: 0 at x = 0, 1 at x = length
    end_load: float = 0.0      # downward force per unit depth on the face x = length [N/m]
    top_pressure: float = 0.0  # downward traction on the top face [Pa]
    probe_x: float = 0.0       # where u is printed, on the mid-line


def cantilever(load):
    return Beam(0.1, 0.01, 210e9, 0.3, "stress", end_load=load, probe_x=0.1)


def plate(_load):
    return Beam(1.0, 0.05, 67.5e9, 0.34, "strain", density=2700.0, clamped_ends=(0, 1),
                top_pressure=1000.0 * 9.81 * 2.0, probe_x=0.5)


def liao(load):
    return Beam(0.09, 0.004, 3.5e6, 0.45, "strain", top_pressure=load, probe_x=0.09)


def gate(load):
    return Beam(0.079, 0.005, 12e6, 0.4, "strain", top_pressure=load, probe_x=0.079)


def lagrange(s):
    """The three quadratic shape functions on [-1, 1] and their derivatives."""
    return np.array([s * (s - 1) / 2, 1 - s * s, s * (s + 1) / 2]), np.array([s - 0.5, -2 * s, s + 0.5])


class Q9Solid:
    """The beam as a mesh of nx x ny Q9 elements: nodes, degrees of freedom, loads and the element loops."""

    def __init__(self, beam, nx, ny):
        self.beam, self.nx, self.ny = beam, nx, ny
        E, nu = beam.youngs, beam.poisson
        self.mu = E / (2 * (1 + nu))
        self.lam = E * nu / (1 - nu**2) if beam.plane == "stress" else E * nu / ((1 + nu) * (1 - 2 * nu))
        self.nodes_x, self.nodes_y = 2 * nx + 1, 2 * ny + 1
        self.n_nodes = self.nodes_x * self.nodes_y
        self.elements = np.array([[self.node(2 * ex + a, 2 * ey + b) for a in range(3) for b in range(3)]
                                  for ex in range(nx) for ey in range(ny)])
        self.hx, self.hy = beam.length / nx, beam.thickness / ny
        gauss, weight = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]), np.array([5 / 9, 8 / 9, 5 / 9])
        grads, shapes, weights = [], [], []
        for a in range(3):
            for b in range(3):
                (na, da), (nb, db) = lagrange(gauss[a]), lagrange(gauss[b])
                grads.append(np.stack([np.outer(da, nb).ravel() * 2 / self.hx, np.outer(na, db).ravel() * 2 / self.hy], 1))
                shapes.append(np.outer(na, nb).ravel())
                weights.append(weight[a] * weight[b] * self.hx * self.hy / 4)
        self.G = np.array(grads)     # (gauss point, node of the element, reference direction)
        self.N = np.array(shapes)    # (gauss point, node of the element)
        self.w = np.array(weights)
        self.dofs = np.stack([2 * self.elements, 2 * self.elements + 1], 2).reshape(len(self.elements), 18)
        clamped = np.array([self.node(0 if end == 0 else self.nodes_x - 1, j)
                            for end in beam.clamped_ends for j in range(self.nodes_y)])
        self.free = np.setdiff1d(np.arange(2 * self.n_nodes), np.concatenate([2 * clamped, 2 * clamped + 1]))

    def node(self, i, j):
        return i * self.nodes_y + j

    def assemble(self, per_element):
        """The global matrix of per-element 18 x 18 blocks."""
        n = 2 * self.n_nodes
        return np.bincount((self.dofs[:, :, None] * n + self.dofs[:, None, :]).ravel(), per_element.ravel(),
                           n * n).reshape(n, n)

    def dead_load(self):
        """The beam's end load, top pressure and weight as consistent nodal forces (Simpson's weights along
        an element edge, the element's shape functions for the weight), downwards."""
        beam, f_ext = self.beam, np.zeros(2 * self.n_nodes)
        simpson = (1 / 6, 4 / 6, 1 / 6)
        for ey in range(self.ny):
            for k, c in enumerate(simpson):
                f_ext[2 * self.node(self.nodes_x - 1, 2 * ey + k) + 1] -= beam.end_load / beam.thickness * self.hy * c
        for ex in range(self.nx):
            for k, c in enumerate(simpson):
                f_ext[2 * self.node(2 * ex + k, self.nodes_y - 1) + 1] -= beam.top_pressure * self.hx * c
        if beam.density > 0:
            body = np.einsum("g,ga->a", self.w, self.N) * beam.density * 9.81
            np.add.at(f_ext, self.dofs[:, 1::2], -body)
        return f_ext

    def mass(self):
        """The consistent mass matrix, M_ab = integral of rho N_a N_b, per displacement component."""
        Me = np.zeros((len(self.elements), 18, 18))
        block = self.beam.density * np.einsum("g,ga,gb->ab", self.w, self.N, self.N)
        Me[:, 0::2, 0::2] = block
        Me[:, 1::2, 1::2] = block
        return self.assemble(Me)

    def point_loads(self, points):
        """The matrix that maps forces at reference points (k, component) to nodal forces: each force is
        spread on its element's nodes with the shape functions at its point."""
        P = np.zeros((2 * self.n_nodes, 2 * len(points)))
        for k, (x, y) in enumerate(points):
            ex, ey = min(int(x / self.hx), self.nx - 1), min(int(y / self.hy), self.ny - 1)
            (na, _), (nb, _) = lagrange(2 * x / self.hx - 2 * ex - 1), lagrange(2 * y / self.hy - 2 * ey - 1)
            for dof, n_a in zip(self.dofs[ex * self.ny + ey].reshape(9, 2), np.outer(na, nb).ravel()):
                P[dof, [2 * k, 2 * k + 1]] += n_a
        return P

    def tangent_and_residual(self, u):
        lam, mu, G, w = self.lam, self.mu, self.G, self.w
        ue = u[self.dofs].reshape(len(self.elements), 9, 2)                  # (e, node, i)
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
        C = np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])
        Sv = np.stack([S[..., 0, 0], S[..., 1, 1], S[..., 0, 1]], -1)
        Re = np.einsum("g,egvk,egv->ek", w, B, Sv)
        Ke = np.einsum("g,egvk,vw,egwl->ekl", w, B, C, B, optimize=True)
        geometric = np.einsum("g,gaI,egIJ,gbJ->eab", w, G, S, G, optimize=True)  # G S G^T, per displacement component
        Ke[:, 0::2, 0::2] += geometric
        Ke[:, 1::2, 1::2] += geometric
        return self.assemble(Ke), np.bincount(self.dofs.ravel(), Re.ravel(), 2 * self.n_nodes)

    def probe(self, u):
        """u at the probe, on the mid-line."""
        i = round(self.beam.probe_x / self.beam.length * (self.nodes_x - 1))
        return u.reshape(-1, 2)[self.node(i, self.ny)]


def solve(beam, nx, ny, steps):
    solid = Q9Solid(beam, nx, ny)
    f_ext, free = solid.dead_load(), solid.free
    u = np.zeros(2 * solid.n_nodes)
    for step in range(1, steps + 1):
        target = f_ext * step / steps
        for _ in range(30):
            K, R = solid.tangent_and_residual(u)
            du = np.linalg.solve(K[np.ix_(free, free)], (target - R)[free])
            u[free] += du
            if np.linalg.norm(du) <= 1e-12 * np.linalg.norm(u):
                break
        else:
            raise RuntimeError(f"Newton did not converge in load step {step}")
    return solid.probe(u)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("beam", choices=("cantilever", "plate", "liao", "gate"))
    parser.add_argument("--elements", type=int, nargs=2, default=[40, 4], metavar=("NX", "NY"))
    parser.add_argument("--load", type=float, default=1.75e6,
                        help="cantilever: end load per unit depth [N/m]; liao, gate: traction on the face [Pa]")
    parser.add_argument("--steps", type=int, default=10, help="load steps")
    a = parser.parse_args()
    beam = {"cantilever": cantilever, "plate": plate, "liao": liao, "gate": gate}[a.beam](a.load)
    if a.elements[0] % 2 or (beam.probe_x / beam.length * 2 * a.elements[0]) % 1:
        parser.error("the probe must lie on a node: NX must be even")
    ux, uy = solve(beam, a.elements[0], a.elements[1], a.steps)
    print(f"{a.beam}, Q9 {a.elements[0]} x {a.elements[1]}: u_x = {ux * 1e3:.6f} mm, u_y = {uy * 1e3:.6f} mm "
          f"at ({beam.probe_x:g}, mid-thickness) (delta_v/L = {-uy / beam.length:.6f}, delta_h/L = {-ux / beam.length:.6f})")


if __name__ == "__main__":
    main()
