#pragma once
// A manufactured PPE-like linear system, for the solver tests and the solver benchmark.
//
// An n x n grid on the unit square with a `stencil`-point neighbourhood (5, 9 or 21; 21 points is
// about the 20-30 neighbours of a 2D SPH particle): a_ij = -(1/r_ij^2) (1 + 0.6 cos theta_ij) for the
// neighbours inside the grid (a Laplacian plus an upwind-like convection along (1, 0.5)), perturbed
// per entry by +-20 % like a disordered particle cloud; a_ii = sum_j |a_ij|: a weakly diagonally
// dominant, non-symmetric M-matrix with zero row sums, Neumann-like at the walls. The top row(s)
// (the free surface) and every 97th row (splashed particles) are identity rows with b_i = x*_i;
// the other rows keep those columns, as the PPE does. x* is smooth; b = A x*.
#include <vector>

#include "poisson/linear_solver.hpp"

namespace isph {

struct ManufacturedSystem {
  CsrMatrix A;
  std::vector<double> x_star, b;
};

ManufacturedSystem manufactured_ppe_system(int n, int stencil);

// ||a - b|| / ||b||
double relative_difference(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace isph
