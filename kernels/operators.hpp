#pragma once
// Corrected discrete SPH operators (seed 001 Eqs. 2-7) as particle-loop functors.
//
// Notation, for particle a and each neighbour b of its CSR list:
//   r_ab = r_a - r_b,  rho_ab = |r_ab|,  e_ab = r_ab / rho_ab,  g_ab = V_b grad_a W(r_ab, h_ab),
//   L_a  = M_a^{-T},   M_a = sum_b (r_b - r_a) ⊗ g_ab          (gradient_correction.hpp)
// L_a is the Bonet-Lok correction; seed Eq. 5 writes the same operator as B_a with the transpose
// convention (B_a · grad W  ==  L_a grad W).
//
//  GradientCorrection      L_a as above.
//  CorrectedGradient       <grad f>_a = sum_b (f_b - f_a) L_a g_ab                       (Eq. 2)
//                          exact for linear f.
//  CorrectedDivergence     <div u>_a  = sum_b (u_b - u_a) · (L_a g_ab)                   (Eq. 3)
//                          exact for linear u.
//  PositionDivergence      <div r>_a  = -sum_b r_ab · g_ab  (uncorrected)
//                          = D in a full support, smaller at a free surface (Eq. 17 uses 1.4 / 1.6
//                          in 2D).
//  RenormalisedLaplacian   <lap f>_a  = B^_a : sum_b 2 e_ab ⊗ g_ab ((f_a - f_b)/rho_ab - e_ab · <grad f>_a)
//                                     = sum_b 2 (e_ab · B^_a g_ab) ((f_a - f_b)/rho_ab - e_ab · <grad f>_a)
//                          (Eq. 4; Fatehi & Manzari 2011, Comput. Math. Appl. 61:482-498), with
//                          <grad f>_a the corrected gradient above.
//  LaplacianRenormalisation  the symmetric D x D tensor B^_a (seed Eqs. 6-7, garbled in the seed's
//                          copy; derived here from the exactness requirement):
//
//   For f = ½ x^T Q x + c·x + d, put y_b = r_b - r_a = -rho_ab e_ab. Then
//     f_b - f_a = grad f_a · y_b + ½ rho_ab^2 e_ab^T Q e_ab,
//     <grad f>_a = grad f_a + delta,  delta = ½ L_a sum_c rho_ac^2 (e_ac^T Q e_ac) g_ac
//   (the linear part is reproduced exactly by L_a), so the bracket of the Laplacian is
//     (f_a - f_b)/rho_ab - e_ab · <grad f>_a = -½ rho_ab e_ab^T Q e_ab - e_ab · delta
//   (linear and constant parts cancel), and the operator returns  -B^_ij T_ijkl Q_kl  with
//     T_ijkl = A_ijkl + E_ijm L_mp C_pkl,
//     A_ijkl = sum_b rho_ab e_i g_j e_k e_l,  E_ijm = sum_b e_i g_j e_m,  C_pkl = sum_b rho_ab^2 g_p e_k e_l
//   (all per pair ab; this is the structure of seed Eqs. 6-7: B^ : [sum V r e e gradW + (sum V e e gradW)
//   · B · (sum V r r gradW)] = -I). Exactness for every symmetric Q (lap f = tr Q) requires
//     B^_ij T_ijkl = -delta_kl   for the D(D+1)/2 pairs k <= l   (T is symmetric in k, l),
//   and with B^ symmetric this is a square D(D+1)/2 system (3 in 2D, 6 in 3D), solved per particle by
//   Gaussian elimination with partial pivoting. On a full, uniform support B^ ≈ I.
//   Fallback: when that system is singular (isolated particles, too few neighbour directions) or the
//   solution is not finite, B^ = I, i.e. the standard (un-renormalised) form
//     <lap f>_a = sum_b 2 (e_ab · g_ab) ((f_a - f_b)/rho_ab - e_ab · <grad f>_a).
//
// All functors read neighbours and write only particle i; they are device-safe (ISPH_HD, fixed-size
// arrays, no std:: containers). Pairs at zero distance (coincident particles) are skipped.
#include "core/neighbour_search.hpp"
#include "core/periodic.hpp"
#include "core/types.hpp"
#include "kernels/gradient_correction.hpp"
#include "kernels/smoothing_kernel.hpp"

namespace isph {

// The smoothing kernels of a particle set with more than one resolution (a structure finer than the
// water around it): one kernel per particle spacing, sorted by h, and each particle's level, its index
// in the table. A pair is seen with the kernel of its coarser particle, h_ab = max(h_a, h_b): the
// fluid's smoothing length for fluid-structure pairs, as in the multi-resolution FSI of Zhang, Rezavand &
// Hu (2021, J. Comput. Phys. 429:110028). The rule is symmetric in a and b, so that pair forces stay equal
// and opposite (seed 001 Eq. 46), and a fluid particle's support is the fluid's whatever the resolution
// of its neighbours (docs/VALIDATION.md section 23). One level: every pair has the one kernel. The
// neighbour search keeps the pairs within the support of their own kernel (core/neighbour_search.hpp
// LevelReach, reach()).
template <int D>
struct KernelTable {
  SmoothingKernel<D> kernel[kMaxLevels];
  int levels = 1;
  KernelTable() = default;
  KernelTable(const SmoothingKernel<D>& only) { kernel[0] = only; }  // one resolution
  ISPH_HD const SmoothingKernel<D>& pair(int la, int lb) const { return kernel[la > lb ? la : lb]; }
  ISPH_HD Real largest_support() const { return kernel[levels - 1].support(); }
  // The neighbour search's reach per level, for the levels of `level`.
  LevelReach reach(const unsigned char* level) const {
    LevelReach r;
    if (levels == 1) return r;
    r.level = level;
    for (int l = 0; l < levels; ++l) r.reach2[l] = kernel[l].support() * kernel[l].support();
    return r;
  }
};

template <int D>
struct OperatorView {
  Index n;
  const Vec<D>* x;
  const Real* volume;
  const Index* nbr_offset;  // CSR: neighbours of a are nbr[nbr_offset[a] .. nbr_offset[a+1])
  const Index* nbr;
  KernelTable<D> kernels;
  Periodicity<D> period = {};            // minimum-image pair vectors on periodic axes
  const unsigned char* level = nullptr;  // each particle's index in `kernels` (null: all on level 0)

  ISPH_HD Vec<D> r(Index a, Index b) const { return period.delta(x[a], x[b]); }
  ISPH_HD int level_of(Index a) const { return level ? level[a] : 0; }
  // The kernel of pair (a, b), and of particle a alone (its own spacing's).
  ISPH_HD const SmoothingKernel<D>& kernel(Index a, Index b) const { return kernels.pair(level_of(a), level_of(b)); }
  ISPH_HD const SmoothingKernel<D>& own_kernel(Index a) const { return kernels.kernel[level_of(a)]; }
  // grad_a W(r_ab, h_ab), with r_ab = r(a, b).
  ISPH_HD Vec<D> gradient(Index a, Index b, const Vec<D>& r_ab) const { return kernel(a, b).gradient(r_ab); }
};

// L_a = M_a^{-T} (identity when M_a is singular).
template <int D>
struct GradientCorrection {
  OperatorView<D> v;
  Mat<D>* L;
  ISPH_HD void operator()(Index a) const {
    Mat<D> m = Mat<D>::zero();
    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      const Index b = v.nbr[k];
      const Vec<D> r_ab = v.r(a, b);
      const Vec<D> g = v.volume[b] * v.gradient(a, b, r_ab);
      m = m + outer((-1.0) * r_ab, g);
    }
    L[a] = correction_from_moment(m);
  }
};

// Eq. 2: grad[a] = sum_b (f_b - f_a) L_a g_ab.
template <int D>
struct CorrectedGradient {
  OperatorView<D> v;
  const Mat<D>* L;
  const Real* f;
  Vec<D>* grad;
  ISPH_HD void operator()(Index a) const {
    Vec<D> s = Vec<D>::zero();
    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      const Index b = v.nbr[k];
      s += (v.volume[b] * (f[b] - f[a])) * v.gradient(a, b, v.r(a, b));
    }
    grad[a] = L[a] * s;
  }
};

// Eq. 3: div[a] = sum_b (u_b - u_a) · (L_a g_ab) = L_a : sum_b (u_b - u_a) ⊗ g_ab.
template <int D>
struct CorrectedDivergence {
  OperatorView<D> v;
  const Mat<D>* L;
  const Vec<D>* u;
  Real* div;
  ISPH_HD void operator()(Index a) const {
    Mat<D> s = Mat<D>::zero();
    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      const Index b = v.nbr[k];
      s = s + outer(u[b] - u[a], v.volume[b] * v.gradient(a, b, v.r(a, b)));
    }
    div[a] = ddot(L[a], s);
  }
};

// Uncorrected divergence of the position: div_r[a] = -sum_b V_b r_ab · grad_a W_ab.
template <int D>
struct PositionDivergence {
  OperatorView<D> v;
  Real* div_r;
  ISPH_HD void operator()(Index a) const {
    Real s = 0;
    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      const Index b = v.nbr[k];
      const Vec<D> r_ab = v.r(a, b);
      s -= v.volume[b] * dot(r_ab, v.gradient(a, b, r_ab));
    }
    div_r[a] = s;
  }
};

namespace detail {

// Index pairs (i <= j) of a symmetric D x D tensor: p -> (i, j).
template <int D>
struct SymPairs {
  static constexpr int count = D * (D + 1) / 2;
  ISPH_HD static void get(int p, int& i, int& j) {
    int q = 0;
    for (int r = 0; r < D; ++r)
      for (int c = r; c < D; ++c, ++q)
        if (q == p) {
          i = r;
          j = c;
        }
  }
};

// Solves a x = rhs (n <= 6) by Gaussian elimination with partial pivoting. Returns false when a
// pivot is below tol_rel times the largest entry of a (singular or nearly so), or a is zero.
template <int N>
ISPH_HD inline bool solve_small(Real (&a)[N][N], Real (&rhs)[N], Real (&x)[N], Real tol_rel) {
  Real amax = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) amax = fmax(amax, fabs(a[i][j]));
  if (!(amax > 0)) return false;
  for (int c = 0; c < N; ++c) {
    int piv = c;
    for (int r = c + 1; r < N; ++r)
      if (fabs(a[r][c]) > fabs(a[piv][c])) piv = r;
    if (!(fabs(a[piv][c]) > tol_rel * amax)) return false;
    if (piv != c) {
      for (int j = 0; j < N; ++j) {
        const Real t = a[c][j];
        a[c][j] = a[piv][j];
        a[piv][j] = t;
      }
      const Real t = rhs[c];
      rhs[c] = rhs[piv];
      rhs[piv] = t;
    }
    for (int r = c + 1; r < N; ++r) {
      const Real f = a[r][c] / a[c][c];
      for (int j = c; j < N; ++j) a[r][j] -= f * a[c][j];
      rhs[r] -= f * rhs[c];
    }
  }
  for (int r = N - 1; r >= 0; --r) {
    Real s = rhs[r];
    for (int j = r + 1; j < N; ++j) s -= a[r][j] * x[j];
    x[r] = s / a[r][r];
  }
  for (int r = 0; r < N; ++r)
    if (!(fabs(x[r]) < 1e300)) return false;  // NaN or inf
  return true;
}

}  // namespace detail

// Pair gradients exact for quadratic fields (used by TLSPH for the deformation gradient, Eq. 36):
// per-pair vectors c_ab with  sum_b (f_b - f_a) c_ab = grad f_a  for every quadratic f, also at free
// surfaces and corners, where L_a g_ab is exact only for linear f (its error there is O(h) times the
// second derivative: a bent plate's surface particles see the strain of a point inside).
// c_ab is the smallest correction of L_a g_ab (in sum_b |c_ab - L_a g_ab|^2) that adds exactness for
// the quadratic monomials. With y_b = (r_b - r_a)/h, p_b = [y ; y_i y_j (i < j), y_i^2 / 2]
// (m = D + D(D+1)/2 monomials), the Gram matrix G_a = sum_b p_b p_b^T and the quadratic moments
// Q_a = sum_b L_a g_ab (p_b's quadratic part)^T (D x D(D+1)/2):
//    c_ab = L_a g_ab + A_a p_b,   A_a G_a = [0 | -Q_a]
// (the linear columns stay exact, the quadratic ones become exact). On a full, symmetric support
// Q_a = 0 and c_ab = L_a g_ab. The correction is the smallest possible, which keeps the surface
// stencils close to the one-sided finite-difference ones (and the stable step close to the linear
// gradient's; docs/VALIDATION.md section 21).
// The functor adds A_a p_b to pair_gradient, which holds L_a g_ab on entry. Where G_a is singular (a
// body one or two particles thick, too few neighbours) it leaves L_a g_ab.
template <int D>
struct QuadraticCorrection {
  OperatorView<D> v;
  Vec<D>* pair_gradient;  // one per CSR pair: L_a g_ab on entry, c_ab on exit
  static constexpr int kQuadratic = D * (D + 1) / 2, kMonomials = D + kQuadratic;
  ISPH_HD void monomials(Index a, Index b, Real (&p)[kMonomials]) const {
    const Vec<D> y = (-1.0 / v.own_kernel(a).h) * v.r(a, b);
    int m = 0;
    for (int i = 0; i < D; ++i) p[m++] = y[i];
    for (int i = 0; i < D; ++i)
      for (int j = i; j < D; ++j) p[m++] = (i == j ? 0.5 : 1.0) * y[i] * y[j];
  }
  ISPH_HD void operator()(Index a) const {
    Real gram[kMonomials][kMonomials] = {}, moment[D][kQuadratic] = {};
    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      Real p[kMonomials];
      monomials(a, v.nbr[k], p);
      for (int i = 0; i < kMonomials; ++i)
        for (int j = 0; j < kMonomials; ++j) gram[i][j] += p[i] * p[j];
      for (int d = 0; d < D; ++d)
        for (int q = 0; q < kQuadratic; ++q) moment[d][q] += pair_gradient[k][d] * p[D + q];
    }
    // row d of A_a solves G_a A_d = [0 ; -Q_a row d] (G_a is symmetric)
    Real A[D][kMonomials];
    for (int d = 0; d < D; ++d) {
      Real sys[kMonomials][kMonomials], rhs[kMonomials] = {};
      for (int i = 0; i < kMonomials; ++i)
        for (int j = 0; j < kMonomials; ++j) sys[i][j] = gram[i][j];
      for (int q = 0; q < kQuadratic; ++q) rhs[D + q] = -moment[d][q];
      if (!detail::solve_small<kMonomials>(sys, rhs, A[d], 1e-10)) return;
    }
    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      Real p[kMonomials];
      monomials(a, v.nbr[k], p);
      for (int d = 0; d < D; ++d)
        for (int i = 0; i < kMonomials; ++i) pair_gradient[k][d] += A[d][i] * p[i];
    }
  }
};

// The Laplacian's weight of pair ab: 2 (e_ab · B^_a g_ab), so that
//   <lap f>_a = sum_b w_ab ((f_a - f_b)/rho_ab - e_ab · <grad f>_a).
// Returns 0 for coincident particles (rho_ab = 0). Shared with the PPE assembly.
template <int D>
ISPH_HD inline Real laplacian_pair_weight(const Mat<D>& bhat, const Vec<D>& r_ab, Real rho_ab, const Vec<D>& g_ab) {
  if (!(rho_ab > 0)) return 0;
  return 2 * dot((1.0 / rho_ab) * r_ab, bhat * g_ab);
}

// B^_a of Fatehi & Manzari (2011): the symmetric tensor that makes RenormalisedLaplacian exact for
// quadratic fields (derivation at the top of this file). It needs L_a, whose moment M_a it sums in the
// same loop: it writes L_a as GradientCorrection does, so that one pass over the pairs gives both.
template <int D>
struct LaplacianRenormalisation {
  OperatorView<D> v;
  Mat<D>* L;
  Mat<D>* Bhat;
  ISPH_HD void operator()(Index a) const {
    constexpr int P = detail::SymPairs<D>::count;
    Real A[D][D][P];  // A_ij(kl) = sum rho e_i g_j e_k e_l
    Real E[D][D][D];  // E_ijm = sum e_i g_j e_m
    Real C[D][P];     // C_p(kl) = sum rho^2 g_p e_k e_l
    int pk[P], pl[P];
    for (int p = 0; p < P; ++p) detail::SymPairs<D>::get(p, pk[p], pl[p]);
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) {
        for (int p = 0; p < P; ++p) A[i][j][p] = 0;
        for (int m = 0; m < D; ++m) E[i][j][m] = 0;
      }
    for (int i = 0; i < D; ++i)
      for (int p = 0; p < P; ++p) C[i][p] = 0;
    Mat<D> moment = Mat<D>::zero();  // M_a of GradientCorrection

    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      const Index b = v.nbr[k];
      const Vec<D> r_ab = v.r(a, b);
      const Vec<D> g = v.volume[b] * v.gradient(a, b, r_ab);
      moment = moment + outer((-1.0) * r_ab, g);
      const Real rho = sqrt(norm2(r_ab));
      if (!(rho > 0)) continue;
      const Vec<D> e = (1.0 / rho) * r_ab;
      for (int p = 0; p < P; ++p) {
        const Real ekl = e[pk[p]] * e[pl[p]];
        for (int i = 0; i < D; ++i) {
          C[i][p] += rho * rho * g[i] * ekl;
          for (int j = 0; j < D; ++j) A[i][j][p] += rho * e[i] * g[j] * ekl;
        }
      }
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j)
          for (int m = 0; m < D; ++m) E[i][j][m] += e[i] * g[j] * e[m];
    }

    // LC_m(kl) = L_mp C_p(kl)
    const Mat<D> l = correction_from_moment(moment);
    L[a] = l;
    Real LC[D][P];
    for (int m = 0; m < D; ++m)
      for (int p = 0; p < P; ++p) {
        Real s = 0;
        for (int q = 0; q < D; ++q) s += l(m, q) * C[q][p];
        LC[m][p] = s;
      }

    // System: row (kl), column (ij) of the symmetric unknown B^_ij.
    Real sys[P][P], rhs[P], sol[P];
    for (int r = 0; r < P; ++r) {
      rhs[r] = (pk[r] == pl[r]) ? -1.0 : 0.0;
      for (int c = 0; c < P; ++c) {
        const int i = pk[c], j = pl[c];
        Real t_ij = A[i][j][r], t_ji = A[j][i][r];
        for (int m = 0; m < D; ++m) {
          t_ij += E[i][j][m] * LC[m][r];
          t_ji += E[j][i][m] * LC[m][r];
        }
        sys[r][c] = (i == j) ? t_ij : t_ij + t_ji;
      }
    }
    Mat<D> bh = Mat<D>::identity();
    if (detail::solve_small<P>(sys, rhs, sol, 1e-10)) {
      for (int c = 0; c < P; ++c) {
        bh(pk[c], pl[c]) = sol[c];
        bh(pl[c], pk[c]) = sol[c];
      }
    }
    Bhat[a] = bh;
  }
};

// Eq. 4: lap[a] = sum_b 2 (e_ab · B^_a g_ab) ((f_a - f_b)/rho_ab - e_ab · grad[a]), with grad the
// corrected gradient of f (CorrectedGradient) and Bhat from LaplacianRenormalisation.
template <int D>
struct RenormalisedLaplacian {
  OperatorView<D> v;
  const Mat<D>* Bhat;
  const Real* f;
  const Vec<D>* grad;
  Real* lap;
  ISPH_HD void operator()(Index a) const {
    const Mat<D> bh = Bhat[a];
    const Vec<D> ga = grad[a];
    Real s = 0;
    for (Index k = v.nbr_offset[a]; k < v.nbr_offset[a + 1]; ++k) {
      const Index b = v.nbr[k];
      const Vec<D> r_ab = v.r(a, b);
      const Real rho = sqrt(norm2(r_ab));
      if (!(rho > 0)) continue;
      const Real w = laplacian_pair_weight(bh, r_ab, rho, v.volume[b] * v.gradient(a, b, r_ab));
      s += w * ((f[a] - f[b]) / rho - dot(r_ab, ga) / rho);
    }
    lap[a] = s;
  }
};

}  // namespace isph
