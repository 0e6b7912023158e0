#pragma once
// Loops over vectors and CSR rows that the project's Krylov solver (poisson/krylov.hpp) and its AMG
// preconditioner (poisson/aggregation_amg.hpp) share, written once for the host and the device.
#include "core/parallel.hpp"

namespace isph {

// y = a (d ⊙ x) + b y, with d = 1 when d is null; b = 0 overwrites y (which may hold NaN).
struct ScaledAxpby {
  double a, b;
  const double* d;
  const double* x;
  double* y;
  ISPH_HD void operator()(Index i) const {
    const double dx = d ? d[i] * x[i] : x[i];
    y[i] = b == 0 ? a * dx : a * dx + b * y[i];
  }
};

// y_i = sum_k A_ik x_k over row i of a CSR matrix (the host SpMV).
struct CsrRowProduct {
  const int* row_offset;
  const int* col;
  const double* val;
  const double* x;
  double* y;
  ISPH_HD void operator()(Index i) const {
    double s = 0;
    for (int k = row_offset[i]; k < row_offset[i + 1]; ++k) s += val[k] * x[col[k]];
    y[i] = s;
  }
};

// x_i y_i, the terms of a dot product (for ordered_sum).
struct ProductAt {
  const double* x;
  const double* y;
  ISPH_HD double operator()(Index i) const { return x[i] * y[i]; }
};

// r_i - sum_k A_ik z_k over row i of a CSR matrix.
ISPH_HD inline double row_residual(const int* row_offset, const int* col, const double* val, const double* r,
                                   const double* z, Index i) {
  double s = r[i];
  for (int k = row_offset[i]; k < row_offset[i + 1]; ++k) s -= val[k] * z[col[k]];
  return s;
}

// A CSR matrix as pointers, in whichever memory holds it.
struct CsrView {
  int rows = 0;
  const int* row_offset = nullptr;
  const int* col = nullptr;
  const double* val = nullptr;
};

// dinv_i = 1 / A_ii, or 0 where row i has no (or a zero) diagonal entry.
struct InverseDiagonal {
  CsrView A;
  double* dinv;
  ISPH_HD void operator()(Index i) const {
    double diag = 0;
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k)
      if (A.col[k] == i) diag = A.val[k];
    dinv[i] = diag != 0 ? 1.0 / diag : 0.0;
  }
};

// i where dinv_i = 0, else the largest Index (its minimum is the first row without a diagonal).
struct RowWithoutDiagonal {
  const double* dinv;
  ISPH_HD Index operator()(Index i) const { return dinv[i] == 0 ? i : kNoRow; }
  static constexpr Index kNoRow = 0x7fffffff;
};

}  // namespace isph
