#pragma once
// Fluid-structure interaction through the pressure field (seed 001 §2.3). Structure particles sit in
// the fluid's particle set as moving boundary particles (FluidKind::structure): their positions and
// velocities enter the PPE, whose wall rows give the wetted ones a pressure continuous with the
// fluid's (the particles deeper than the kernel support below the wetted surface keep p = 0).
//
// The pressure force per unit volume on a structure particle s, f_s = rho_s alpha(f->s)_s:
//  "gradient" (Eq. 48): f_s = -<grad p>_s, the corrected gradient over all neighbours, fluid and
//      structure (and walls), at full volume: <grad p>_s = L_s sum_k V_k (p_k - p_s) grad W_sk.
//  "pairwise": f_s = -sum_f V_f (p_s + p_f) grad W_sf over the fluid neighbours only: the symmetric
//      SPH pressure force, so the force on s from f and on f from s are equal and opposite pair by pair
//      (Eq. 46 holds exactly), and for a uniform pressure p the sum over the structure is p n A (the
//      kernel sum of the fluid is 1/2 on the interface).
// The difference form of Eq. 48 does not split into pair forces; its sum over the structure is the
// pressure force on the wetted surface only as far as the discrete gradient telescopes across the
// interface layer (docs/VALIDATION.md measures both).
#include "kernels/fluid_view.hpp"
#include "kernels/operators.hpp"

namespace isph {

// f at the boundary particles of one kind (structure, or wall for the work of moving walls); the L
// of the gradient form is that of the full neighbourhood: all volumes, dry boundary particles included.
template <int D>
struct BoundaryPressureForce {
  FluidView<D> v;
  const Real* p;
  Mat<D>* L;
  Vec<D>* grad_p;
  Vec<D>* force_density;
  bool pairwise;
  FluidKind target;
  ISPH_HD void operator()(Index a) const {
    if (v.kind[a] != target) return;
    if (pairwise) {
      const OperatorView<D>& op = v.op;
      Vec<D> s = Vec<D>::zero();
      for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
        const Index b = op.nbr[k];
        if (v.is_fluid(b)) s += (op.volume[b] * (p[a] + p[b])) * op.gradient(a, b, op.r(a, b));
      }
      force_density[a] = -1.0 * s;
      return;
    }
    GradientCorrection<D>{v.op, L}(a);
    CorrectedGradient<D>{v.op, L, p, grad_p}(a);
    force_density[a] = -1.0 * grad_p[a];
  }
};

// alpha(f->s) = f_s / rho_s (Eq. 48) of each structure particle (TLSPH's indexing), from the pressure
// force per unit volume; with T = Mat<D>, the impedance rate Gamma_s = Z_s / rho_s the same way.
template <int D, class T = Vec<D>>
struct InteractionAcceleration {
  const T* force_density;
  const Real* density;
  T* alpha;
  ISPH_HD void operator()(Index a) const { alpha[a] = (1.0 / density[a]) * force_density[a]; }
};

// The rate Gamma_s = Z_s / rho_s of an isotropic resistance Z_s (the fluid's shear: ViscousBoundaryForce),
// in place of Z_s, and as the matrix Gamma_s I the substeps take (zero where 1/rho_s is: clamped particles).
template <int D>
struct IsotropicRate {
  Real* rate;  // in: Z_s
  const Real* inverse_density;
  Mat<D>* matrix;
  ISPH_HD void operator()(Index a) const {
    rate[a] *= inverse_density[a];
    matrix[a] = rate[a] * Mat<D>::identity();
  }
};

// Component d of V_s f_s, whose sum over the structure's particles is the pressure force on it; with
// `body`, only the particles of body `target` count (a force probe's body, ParticleSet::body_force).
template <int D>
struct ForceComponent {
  const Real* volume;
  const Vec<D>* force_density;
  int d;
  const Index* body = nullptr;
  Index target = 0;
  ISPH_HD Real operator()(Index s) const { return body && body[s] != target ? 0 : volume[s] * force_density[s][d]; }
};

// The structure's motion over a fluid step as the fluid sees it (sim/coupling.hpp): the chord velocity
// vbar^{n+1} = (x^{n+1} - x^n)/dt and, where asked, the acceleration a_s = (vbar^{n+1} - vbar^n)/dt.
template <int D>
struct ChordMotion {
  const Vec<D>* x;
  const Vec<D>* x_old;
  const Vec<D>* v_mean;  // vbar^n
  Real inverse_dt;
  Vec<D>* v_new;
  Vec<D>* a_new;  // null: the velocity only
  ISPH_HD void operator()(Index a) const {
    v_new[a] = inverse_dt * (x[a] - x_old[a]);
    if (a_new) a_new[a] = inverse_dt * (v_new[a] - v_mean[a]);
  }
};

// The first iterate of a coupled step (sim/coupling.hpp): its chord acceleration predicted from the
// state at its start. Under accelerations held over the step, x^{n+1} - x^n = v^n dt + (e + alpha) dt^2 / 2
// gives a_s = (v^n - vbar^n)/dt + (e + alpha)/2, with e the structure's own acceleration (stress, gravity,
// loads, contact) and alpha the pressure's (for the interpolated alpha, alpha^n/3 + alpha^{n+1}/6 in place
// of alpha/2). The PPE's structure rows take it without beta alpha^{n+1} (PpeRowFill); with the last
// step's field for alpha^{n+1}, the prediction is
//   a~_s = (v^n - vbar^n)/dt + e/2 + (1/2 - beta) alpha^n.
// The first term carries the last step's load into this one (vbar^n lags v^n by half the last step's
// acceleration), which a start from the last step's a~_s misses: the step-to-step change of a_s along a
// heavily loaded structure is mostly that term.
// Clamped particles follow their clamp whatever the pressure: no alpha, no beta (their rows take a_s).
template <int D>
struct ChordPrediction {
  const Vec<D>* v;       // v^n, the structure's own velocity
  const Vec<D>* v_mean;  // vbar^n
  const Vec<D>* own;     // e
  const Vec<D>* alpha;   // alpha^n (null: none yet)
  const unsigned char* fixed;
  Real inverse_dt, alpha_share;
  Vec<D>* out;
  ISPH_HD void operator()(Index a) const {
    Vec<D> p = inverse_dt * (v[a] - v_mean[a]) + 0.5 * own[a];
    if (alpha && !fixed[a]) p += alpha_share * alpha[a];
    out[a] = p;
  }
};

// The part of a step's chord acceleration that the PPE's structure rows take, a~_s = a_s - beta alpha
// (PpeRowFill), in place; clamped particles keep a_s.
template <int D>
struct PressureShareRemoved {
  const Vec<D>* alpha;
  const unsigned char* fixed;
  Real beta;
  Vec<D>* a;
  ISPH_HD void operator()(Index k) const {
    if (!fixed[k]) a[k] += (-beta) * alpha[k];
  }
};

// Fluid particles beside a body (the structure, or the walls): whether the particle lies inside the
// body, and its distance to the nearest of the body's particles (or a large value). Inside means both
//  - the body's kernel sum (its colour function) at the particle, c_a = sum_b V_b W(x_a - x_b), exceeds
//    1/2, its value on a flat face: the particle has crossed the body's surface, which lies dx/2 beyond
//    the outer particles; and
//  - the particle is behind the surface face of the nearest body particle b: (x_a - x_b) . n_b < d_b,
//    with n_b the outward normal and d_b the depth of b below the surface (from the set-up).
// Each test alone fails at one kind of corner (tests/unit/test_structure_contact.cpp):
//  - the face test at convex corners: with only the corner particle in reach, water running out a full
//    dx below the elastic gate's end was behind the plane of that particle's side face;
//  - the colour test in concave corners, where c is 3/4 at the corner point: a fluid particle pressed
//    to 0.35 dx from both faces of a tank's corner has c = 1/2.
// Inside a body a particle is behind every face and c > 1/2 except within about dx/2 of a convex
// corner (c = 1/4 at the corner), where it is counted once it is about dx/2 in.
// The depth of a particle inside is how far it lies behind that face, d_b - (x_a - x_b) . n_b (0 outside).
// The distance is kOutOfReach for a particle with none of the body's particles within the kernel support
// (and for particles that are not fluid).
inline constexpr Real kOutOfReach = 1e300;
template <int D>
struct BodyContact {
  FluidView<D> v;
  FluidKind body;
  unsigned char* inside;
  Real* distance;
  Real* depth;
  ISPH_HD void operator()(Index a) const {
    inside[a] = 0;
    distance[a] = kOutOfReach;
    depth[a] = 0;
    if (!v.is_fluid(a)) return;
    Real colour = 0;
    Index nearest = -1;
    for (Index k = v.op.nbr_offset[a]; k < v.op.nbr_offset[a + 1]; ++k) {
      const Index b = v.op.nbr[k];
      if (v.kind[b] != body) continue;
      const Real r = sqrt(norm2(v.op.r(a, b)));
      if (r < distance[a]) distance[a] = r, nearest = b;
      colour += v.op.volume[b] * v.op.kernel(a, b).value(r);
    }
    if (!(colour > 0.5)) return;
    const Real behind = -v.beyond_surface(a, nearest);
    inside[a] = behind > 0;
    if (inside[a]) depth[a] = behind;
  }
};

}  // namespace isph
