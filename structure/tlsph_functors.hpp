#pragma once
// Total Lagrangian SPH particle loops (seed 001 §2.2; Lin et al. 2015; Ganzenmüller 2015).
// Every loop is a plain-data functor that writes only particle a, so it runs unchanged on the
// host (OpenMP) and on a CUDA device through parallel_for.
#include "core/types.hpp"

namespace isph {

// St. Venant-Kirchhoff constants. In 2D plane stress, lambda is already the plane-stress
// value 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2).
struct ElasticMaterial {
  Real density;
  Real lambda;
  Real mu;
  Real youngs_modulus;
};

template <int D>
struct TlsphView {
  Index n;
  // reference configuration, built once
  const Vec<D>* X;          // reference positions
  const Index* nbr_offset;  // CSR neighbours in the reference configuration (same body only)
  const Index* nbr;
  const Vec<D>* grad;       // g_ab = V_b grad_a W(X_a - X_b)
  const Vec<D>* cgrad;      // L_a g_ab, the corrected gradient (Eq. 35-36)
  const Real* vw;           // V_b W(|X_a - X_b|), for hourglass control
  const Mat<D>* L;          // gradient correction L_a = K_a^{-T}
  const int* material;
  const ElasticMaterial* materials;
  const unsigned char* fixed;  // clamped particles: prescribed zero displacement
  // state
  const Vec<D>* x;
  const Vec<D>* v;
  // external loads: acc = gravity + sum_k load_factor[k] * load_acc[k * n + a]
  const Vec<D>* load_acc;
  int loads;
  Real load_factor[8];
  Vec<D> gravity;
  Real damping;    // mass-proportional damping rate [1/s]
  Real hourglass;  // Ganzenmüller's alpha (0 = off)
  // outputs
  Mat<D>* F;       // deformation gradient
  Mat<D>* PL;      // first Piola-Kirchhoff stress times L: P_a L_a
  Real* psi;       // strain energy per unit reference volume
  Vec<D>* acc;
};

// Deformation gradient (Eq. 36, written with displacements so that F = I exactly at rest),
// Green-Lagrange strain E = (F^T F - I)/2, St. Venant-Kirchhoff S = lambda tr(E) I + 2 mu E,
// first Piola-Kirchhoff P = F S (the reference-frame stress of Eq. 42).
template <int D>
struct TlsphStress {
  TlsphView<D> s;
  ISPH_HD void operator()(Index a) const {
    const Vec<D> ua = s.x[a] - s.X[a];
    Mat<D> F = Mat<D>::identity();
    for (Index k = s.nbr_offset[a]; k < s.nbr_offset[a + 1]; ++k) {
      const Index b = s.nbr[k];
      const Vec<D> uab = (s.x[b] - s.X[b]) - ua;
      const Vec<D> g = s.cgrad[k];
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) F(i, j) += uab[i] * g[j];
    }
    const ElasticMaterial m = s.materials[s.material[a]];
    const Mat<D> E = 0.5 * (transpose(F) * F - Mat<D>::identity());
    const Real trE = trace(E);
    Mat<D> S = (2 * m.mu) * E;
    for (int i = 0; i < D; ++i) S(i, i) += m.lambda * trE;
    s.F[a] = F;
    s.PL[a] = (F * S) * s.L[a];
    s.psi[a] = 0.5 * m.lambda * trE * trE + m.mu * ddot(E, E);
  }
};

// Momentum equation in the reference frame (Eq. 42):
//   dv_a/dt = 1/rho_a sum_b (P_a L_a + P_b L_b) g_ab + g + loads - damping v_a
// plus, when hourglass > 0, Ganzenmüller's (2015) hourglass control: with the pair error
// eps^a_ab = F_a X_ab - x_ab (X_ab = X_b - X_a, x_ab = x_b - x_a) and delta^a_ab = eps^a_ab . x_ab/|x_ab|,
//   f_a = -alpha/2 sum_b V_a V_b W_ab E / |X_ab|^2 (delta^a_ab + delta^b_ba) x_ab/|x_ab|.
template <int D>
struct TlsphAcceleration {
  TlsphView<D> s;
  ISPH_HD void operator()(Index a) const {
    if (s.fixed[a]) {
      s.acc[a] = Vec<D>::zero();
      return;
    }
    const ElasticMaterial m = s.materials[s.material[a]];
    const Mat<D> PLa = s.PL[a];
    const Mat<D> Fa = s.F[a];
    const Real hg = 0.5 * s.hourglass * m.youngs_modulus;
    Vec<D> f = Vec<D>::zero();
    for (Index k = s.nbr_offset[a]; k < s.nbr_offset[a + 1]; ++k) {
      const Index b = s.nbr[k];
      f += (PLa + s.PL[b]) * s.grad[k];
      if (hg > 0) {
        const Vec<D> Xab = s.X[b] - s.X[a];
        const Vec<D> xab = s.x[b] - s.x[a];
        const Real r2 = norm2(xab);
        const Real delta_r = dot(Fa * Xab - xab, xab) + dot(s.F[b] * Xab - xab, xab);  // (delta^a + delta^b) |x_ab|
        f += (-hg * s.vw[k] / norm2(Xab) * delta_r / r2) * xab;
      }
    }
    Vec<D> acc = (1.0 / m.density) * f + s.gravity - s.damping * s.v[a];
    for (int l = 0; l < s.loads; ++l) acc += s.load_factor[l] * s.load_acc[static_cast<long>(l) * s.n + a];
    s.acc[a] = acc;
  }
};

// One stage of an explicit Runge-Kutta update, per particle:
//   x_sum += w_sum dt v,  v_sum += w_sum dt acc        (accumulate the final combination)
//   x = x0 + w_next dt v, v = v0 + w_next dt acc       (the next stage's state)
// Classical RK4 (Eqs. 43-45) uses w_sum = 1/6, 1/3, 1/3, 1/6 and w_next = 1/2, 1/2, 1.
// Clamped particles keep x = X and v = 0.
template <int D>
struct RungeKuttaStage {
  Index n;
  const Vec<D>* x0;
  const Vec<D>* v0;
  const Vec<D>* acc;
  const unsigned char* fixed;
  Vec<D>* x;
  Vec<D>* v;
  Vec<D>* x_sum;
  Vec<D>* v_sum;
  Real dt, w_sum, w_next;
  ISPH_HD void operator()(Index a) const {
    if (fixed[a]) return;
    const Vec<D> va = v[a];
    x_sum[a] += (w_sum * dt) * va;
    v_sum[a] += (w_sum * dt) * acc[a];
    x[a] = x0[a] + (w_next * dt) * va;
    v[a] = v0[a] + (w_next * dt) * acc[a];
  }
};

// Velocity-Verlet (kick-drift-kick), the explicit second-order scheme:
//   kick: v += dt/2 acc;   drift: x += dt v.
template <int D>
struct VerletKickDrift {
  const Vec<D>* acc;
  const unsigned char* fixed;
  Vec<D>* x;
  Vec<D>* v;
  Real kick, drift;  // dt/2 and dt (drift = 0 for the closing kick)
  ISPH_HD void operator()(Index a) const {
    if (fixed[a]) return;
    v[a] += kick * acc[a];
    x[a] += drift * v[a];
  }
};

}  // namespace isph
