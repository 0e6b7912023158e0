#pragma once
// Kernel gradient correction (Bonet & Lok 1999; the shape tensor of seed 001 Eq. 35).
// With g_ab = V_b grad_a W_ab and the moment matrix
//    M_a = sum_b (r_b - r_a) ⊗ g_ab,
// the corrected gradient  g~_ab = L_a g_ab,  L_a = M_a^{-T},
// satisfies sum_b (r_b - r_a) ⊗ g~_ab = I, so  sum_b (f_b - f_a) g~_ab  is exact for linear f.
// (Seed 001 writes K_a^{-1} grad W with K defined as the transpose of M; it is the same operator.)
#include "core/types.hpp"

namespace isph {

// Returns L = M^{-T}, or the identity when M is singular (isolated particles, fewer than D
// independent neighbour directions): the uncorrected gradient is then used.
template <int D>
ISPH_HD inline Mat<D> correction_from_moment(const Mat<D>& moment) {
  const Real det = determinant(moment);
  Real scale = 0;
  for (int i = 0; i < D; ++i) scale += moment(i, i) * moment(i, i);
  // relative singularity test: |det| small against the diagonal's size^D
  const Real ref = (D == 2) ? scale : scale * sqrt(scale);
  if (!(fabs(det) > 1e-12 * ref)) return Mat<D>::identity();
  return transpose(inverse(moment));
}

}  // namespace isph
