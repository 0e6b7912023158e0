#pragma once
// Total Lagrangian SPH particle loops (seed 001 §2.2; Lin et al. 2015; Ganzenmüller 2015).
// Every loop is a plain-data functor that writes only particle a, so it runs unchanged on the
// host (OpenMP) and on a CUDA device through parallel_for.
#include "core/neighbour_search.hpp"
#include "core/rigid_motion.hpp"
#include "core/types.hpp"
#include "structure/elastic_law.hpp"

namespace isph {

// Rigid obstacles a structure may touch (the fluid's walls; for_each_wall_overlap): the candidates of
// particle a are offset[a] .. offset[a + 1] in point and radius.
template <int D>
struct ObstacleView {
  const Index* offset;
  const Vec<D>* point;
  const Real* radius;
};

template <int D>
struct TlsphView {
  Index n;
  // reference configuration, built once
  const Vec<D>* X;          // reference positions
  const Index* nbr_offset;  // CSR neighbours in the reference configuration (same body only)
  const Index* nbr;
  const Vec<D>* cgrad;      // c_ab, the corrected pair gradient of the reference configuration (Eq. 36)
  const Vec<D>* rcgrad;     // c_ba, the reverse pair's gradient, stored with pair (a, b)
  const Vec<D>* cgrad_sum;  // S_a = sum_b c_ab
  const Real* hg_weight;    // w_ab = V_b W(|X_ab|) / |X_ab|^2, for hourglass control
  const Mat<D>* hg_moment;  // G_a = sum_b w_ab X_ab ⊗ X_ab, for the linear-exact hourglass error (TlsphStress)
  const Real* volume;
  const Real* cell_moment;  // M_a / V_a = V_a^(2/D) / 12, the cell's second moment per volume (cell quadrature)
  const int* material;
  const ElasticMaterial* materials;
  const unsigned char* fixed;  // clamped particles: prescribed zero displacement
  // Where clamps stand still, the particles whose stress can change (the free ones and the clamped ones
  // within the stress passes' reach of them) and the free ones; null: every particle. A clamped particle
  // further in keeps F = I, no stress and no energy, as every neighbour of it stays in place.
  const Index* strained;
  Index strained_count;
  const Index* moving;
  Index moving_count;
  bool clamps_move;  // some clamps move: clamped particles get their free acceleration (TlsphAcceleration)
  // state
  const Vec<D>* x;
  const Vec<D>* v;
  // external loads: acc = gravity + sum_k load_factor[k] * load_acc[k * n + a]
  const Vec<D>* load_acc;
  int loads;
  Real load_factor[8];
  Vec<D> gravity;
  const Vec<D>* interaction;  // the fluid's pressure acceleration alpha(f->s) (Eq. 48), or null
  ObstacleView<D> obstacles;  // rigid obstacles the particles may touch (the fluid's walls)
  Real damping;               // mass-proportional damping rate [1/s]
  Real hourglass;             // Ganzenmüller's alpha (0 = off)
  bool quadratic;        // the pair gradients are exact for quadratic fields (the hourglass error is then symmetric)
  bool cell_quadrature;  // the strain energy of each particle's cell with the strain's linear variation (below)
  // outputs
  Mat<D>* F;                // deformation gradient
  Mat<D>* stress;           // T_a = P_a + kappa H_a: the first Piola-Kirchhoff stress and the hourglass moment
  Real* psi;                // strain energy per unit reference volume (hourglass energy included)
  Mat<D>* strain;           // cell quadrature: the Green strain E_a
  Mat<D>* gradient_stress;  // cell quadrature: Q_a,d = M_a C:G_a,d, D per particle (index a * D + d)
  Vec<D>* acc;
};

// The internal energy and the force that derives from it. With pair gradients c_ab fixed in the
// reference configuration (Eq. 36 with L_a g_ab, or with QuadraticCorrection), F_a = I + sum_b u_ab ⊗ c_ab
// and the stored energy
//   U = sum_a V_a psi(F_a) + kappa/2 sum_a V_a sum_b w_ab |eps_ab|^2
// (X_ab = X_b - X_a, x_ab = x_b - x_a, kappa = alpha E / 2; eps_ab below), the force per unit mass
// -dU/dx_a / (rho V_a) is
//   acc_a = 1/rho_a [ T_a S_a - sum_b (V_b / V_a) T_b c_ba - kappa sum_b w_ab (eps_ab - eps_ba) ]    (*)
// with S_a = sum_b c_ab, T_a = P_a + kappa H_a, P = F S (St. Venant-Kirchhoff) and
// H_a = sum_b w_ab eps_ab ⊗ X_ab. Without hourglass control and with c_ab = L_a g_ab, (*) is Eq. 42,
// sum_b V_b (P_a L_a + P_b L_b) grad_a W_ab / rho_a. The pairs' forces cancel in the sum, so momentum is
// conserved, and the flow (*) conserves U plus the kinetic energy exactly.
// Hourglass control (alpha > 0) is a penalty on the part of each pair's deformation that the
// deformation gradient does not describe, after Ganzenmüller (2015) but derived from an energy:
//   linear-exact c_ab:     eps_ab = F_a X_ab - x_ab (Ganzenmüller's error; zero for affine maps);
//   quadratic-exact c_ab:  eps_ab = (F_a + F_b)/2 X_ab - x_ab, zero also for every quadratic
//                          displacement (F is then linear and the pair's trapezoidal rule exact), so
//                          that it does not stiffen smooth bending.
// In both, eps_ab - eps_ba = (F_a + F_b) X_ab - 2 x_ab. Both are positive for the zero-energy
// (odd-even) modes of the particle gradient. A body's particles share one material, so kappa is the
// particle's own.

// The pair's antisymmetric hourglass error eps_ab - eps_ba = (F_a + F_b) X_ab - 2 x_ab.
template <int D>
ISPH_HD inline Vec<D> hourglass_difference(const TlsphView<D>& s, Index a, Index b) {
  return (s.F[a] + s.F[b]) * (s.X[b] - s.X[a]) - 2.0 * (s.x[b] - s.x[a]);
}

// Hourglass control with quadratic-exact pair gradients: T_a += kappa H_a and the hourglass energy
// density kappa/2 sum_b w_ab |eps_ab|^2, with the symmetric error, which reads the neighbours' F: a pass
// of its own after TlsphStress. The linear-exact error needs only F_a and is summed inside TlsphStress.
template <int D>
ISPH_HD inline void add_hourglass(const TlsphView<D>& s, Index a) {
  Mat<D> H = Mat<D>::zero();
  Real e = 0;
  for (Index k = s.nbr_offset[a]; k < s.nbr_offset[a + 1]; ++k) {
    const Index b = s.nbr[k];
    const Vec<D> eab = 0.5 * hourglass_difference(s, a, b);
    H = H + s.hg_weight[k] * outer(eab, s.X[b] - s.X[a]);
    e += s.hg_weight[k] * norm2(eab);
  }
  const Real kappa = 0.5 * s.hourglass * s.materials[s.material[a]].youngs_modulus;
  s.stress[a] = s.stress[a] + kappa * H;
  s.psi[a] += 0.5 * kappa * e;
}

template <int D>
struct TlsphHourglass {
  TlsphView<D> s;
  ISPH_HD void operator()(Index a) const { add_hourglass(s, a); }
};

// Deformation gradient (Eq. 36, written with displacements so that F = I exactly at rest), the
// material's second Piola-Kirchhoff stress S (elastic_law.hpp) and the first Piola-Kirchhoff stress
// P = F S, the reference-frame stress of Eq. 42.
// With linear-exact pair gradients the hourglass moment and energy come from the same loop: with
// u_ab = x_ab - X_ab, eps_ab = (F_a - I) X_ab - u_ab, so
//   H_a = (F_a - I) G_a - sum_b w_ab u_ab ⊗ X_ab,
//   sum_b w_ab |eps_ab|^2 = (F_a - I)^T (F_a - I) : G_a - 2 (F_a - I) : sum_b w_ab u_ab ⊗ X_ab + sum_b w_ab |u_ab|^2
// with the reference moment G_a = sum_b w_ab X_ab ⊗ X_ab (TlsphView::hg_moment).
template <int D>
struct TlsphStress {
  TlsphView<D> s;
  ISPH_HD void operator()(Index a) const {
    const Vec<D> ua = s.x[a] - s.X[a];
    const bool hourglass = s.hourglass > 0 && !s.quadratic;
    Mat<D> F = Mat<D>::identity(), uX = Mat<D>::zero();
    Real uu = 0;
    for (Index k = s.nbr_offset[a]; k < s.nbr_offset[a + 1]; ++k) {
      const Index b = s.nbr[k];
      const Vec<D> uab = (s.x[b] - s.X[b]) - ua;
      const Vec<D> g = s.cgrad[k];
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) F(i, j) += uab[i] * g[j];
      if (hourglass) {
        const Real w = s.hg_weight[k];
        uX = uX + outer(w * uab, s.X[b] - s.X[a]);
        uu += w * norm2(uab);
      }
    }
    Real psi = 0;
    const Mat<D> E = green_strain(F);
    const ElasticMaterial m = s.materials[s.material[a]];
    const Mat<D> S = second_piola_stress(F, E, m, &psi);
    s.F[a] = F;
    Mat<D> T = F * S;
    if (hourglass) {
      const Mat<D> Fm = F - Mat<D>::identity(), G = s.hg_moment[a];
      const Real kappa = 0.5 * s.hourglass * m.youngs_modulus;
      T = T + kappa * (Fm * G - uX);
      psi += 0.5 * kappa * (ddot(transpose(Fm) * Fm, G) - 2 * ddot(Fm, uX) + uu);
    }
    s.stress[a] = T;
    s.psi[a] = psi;
    if (s.cell_quadrature) s.strain[a] = E;
  }
};

// Cell quadrature of the strain energy. A particle stands for a cell of volume V_a; evaluating psi at
// its centre is the midpoint rule, which misses the energy of the strain's variation across the cell:
// across a bent beam of N particle rows it gives the second moment sum V y^2 = I (1 - 1/N^2), 1 % too
// soft at N = 10. With the Green strain linear across the cell, E(X) = E_a + sum_d G_a,d (X - X_a)_d,
// St. Venant-Kirchhoff's energy of the cell is exact with one more term (the Taylor-expansion
// stabilisation of nodal integration: Liu, Ong & Uras 1985; Hillman & Chen 2016):
//   U_a = V_a psi(E_a) + 1/2 sum_d M_a G_a,d : C : G_a,d,    M_a = V_a s_a^2 / 12, s_a = V_a^(1/D),
// with G_a,d = sum_b (E_b - E_a) (c_ab)_d the particle gradient of E. Its variation is
// sum_a R_a : dE_a with
//   R_a = sum_d [ sum_b (c_ba)_d Q_b,d - (S_a)_d Q_a,d ],   Q_a,d = M_a C:G_a,d,   S_a = sum_b c_ab,
// so the force (*) holds with the second Piola-Kirchhoff stress S_a + R_a / V_a: T_a += F_a R_a / V_a.
// C is the linear law's: exact for St. Venant-Kirchhoff, the small-strain tangent for the hyperelastic laws.
// Two passes after TlsphStress (which stores E_a): the gradient stresses Q, then R into T.
template <int D>
struct TlsphStrainGradient {
  TlsphView<D> s;
  ISPH_HD void operator()(Index a) const {
    const Mat<D> Ea = s.strain[a];
    Mat<D> G[D];
    for (int d = 0; d < D; ++d) G[d] = Mat<D>::zero();
    for (Index k = s.nbr_offset[a]; k < s.nbr_offset[a + 1]; ++k) {
      const Mat<D> dE = s.strain[s.nbr[k]] - Ea;
      const Vec<D> c = s.cgrad[k];
      for (int d = 0; d < D; ++d) G[d] = G[d] + c[d] * dE;
    }
    const ElasticMaterial m = s.materials[s.material[a]];
    const Real moment = s.cell_moment[a];
    Real energy = 0;
    for (int d = 0; d < D; ++d) {
      const Mat<D> CG = elastic_stress(G[d], m);
      energy += ddot(G[d], CG);
      s.gradient_stress[a * D + d] = (moment * s.volume[a]) * CG;
    }
    s.psi[a] += 0.5 * moment * energy;
  }
};

template <int D>
struct TlsphGradientStress {
  TlsphView<D> s;
  ISPH_HD void operator()(Index a) const {
    Mat<D> R = Mat<D>::zero();
    for (Index k = s.nbr_offset[a]; k < s.nbr_offset[a + 1]; ++k) {
      const Index b = s.nbr[k];
      const Vec<D> c = s.rcgrad[k];
      for (int d = 0; d < D; ++d) R = R + c[d] * s.gradient_stress[b * D + d];
    }
    const Vec<D> sum = s.cgrad_sum[a];
    for (int d = 0; d < D; ++d) R = R - sum[d] * s.gradient_stress[a * D + d];
    s.stress[a] = s.stress[a] + (1.0 / s.volume[a]) * (s.F[a] * R);
  }
};

// Contact with rigid obstacles (the fluid's wall particles): a penalty on overlap. Particle a is a disc
// (a sphere in 3D) of radius s_a / 2, s_a = V_a^(1/D) its spacing, and obstacle point c one of radius
// r_c (half the wall's spacing). Where they overlap, delta = s_a / 2 + r_c - |x_a - y_c| > 0, and a is
// pushed along e = (x_a - y_c) / |x_a - y_c| by the force k delta with
//   k = M s_a^(D-2),   M = lambda + 2 mu (the P-wave modulus):
// the overlap compresses one particle layer of a's own material across its face s_a^(D-1). The
// acceleration is M delta / (rho_a s_a^2) e, and the pair stores the energy k delta^2 / 2. A particle on
// the penalty alone oscillates at c_p / s_a, which the structure's own step, courant h / c_p, resolves.
// Calls f(e, delta, M / (rho_a s_a^2), k) for every overlapping candidate of particle a (material m,
// volume V_a, position x_a).
template <int D, class F>
ISPH_HD inline void for_each_wall_overlap(const ObstacleView<D>& o, Index a, const ElasticMaterial& m, Real volume,
                                          const Vec<D>& xa, F&& f) {
  if (o.offset[a] == o.offset[a + 1]) return;
  const Real modulus = m.lambda + 2 * m.mu;
  const Real spacing = particle_spacing<D>(volume);
  const Real stiffness = modulus * pow(spacing, D - 2.0);
  const Real rate = modulus / (m.density * spacing * spacing);
  for (Index k = o.offset[a]; k < o.offset[a + 1]; ++k) {
    const Vec<D> r = xa - o.point[k];
    const Real distance = sqrt(norm2(r));
    const Real overlap = 0.5 * spacing + o.radius[k] - distance;
    if (overlap > 0 && distance > 0) f((1.0 / distance) * r, overlap, rate, stiffness);
  }
}

// Each particle's obstacle candidates: the obstacle points within reach of x_a (a cell list over them),
// none for clamped particles or without obstacles. Counted into count[a] (count = offset + 1, then
// summed into offsets), then copied, in the cell list's order, to offset[a] .. offset[a + 1].
template <int D>
struct CountObstacleCandidates {
  CellListView<D> near;  // over the obstacle points
  bool any;              // false: no obstacles (near is not built)
  const unsigned char* fixed;
  const Vec<D>* x;
  Index* count;
  ISPH_HD void operator()(Index a) const {
    Index found = 0;
    if (any && !fixed[a]) near.for_each_near(x[a], [&](Index, const Vec<D>&) { ++found; });
    count[a] = found;
  }
};
template <int D>
struct FillObstacleCandidates {
  CellListView<D> near;
  bool any;
  const unsigned char* fixed;
  const Vec<D>* x;
  const Real* obstacle_radius;
  const Index* offset;
  Vec<D>* point;
  Real* radius;
  ISPH_HD void operator()(Index a) const {
    if (!any || fixed[a]) return;
    Index k = offset[a];
    near.for_each_near(x[a], [&](Index c, const Vec<D>&) {
      point[k] = near.x[c];
      radius[k++] = obstacle_radius[c];
    });
  }
};

// Particle a's overlaps with its candidates (for_each_wall_overlap) as a functor Index -> Real for the
// reductions of TlsphSolver::obstacle_contact: their stored energy, the deepest, or their number.
template <int D>
struct ObstacleOverlap {
  enum class Measure { energy, deepest, pairs };
  ObstacleView<D> obstacles;
  const ElasticMaterial* materials;
  const int* material;
  const Real* volume;
  const Vec<D>* x;
  Measure measure;
  ISPH_HD Real operator()(Index a) const {
    Real energy = 0, deepest = 0, pairs = 0;
    for_each_wall_overlap(obstacles, a, materials[material[a]], volume[a], x[a],
                          [&](const Vec<D>&, Real overlap, Real, Real k) {
                            energy += 0.5 * k * overlap * overlap;
                            deepest = overlap > deepest ? overlap : deepest;
                            pairs += 1;
                          });
    return measure == Measure::energy ? energy : measure == Measure::deepest ? deepest : pairs;
  }
};

// The acceleration (*) above, plus gravity, damping, the applied loads, the fluid's interaction and the
// contact with obstacles.
// Clamped particles get zero, or where clamps move the acceleration they would have free, which the
// clamp cancels (the integrators keep them on its path) and whose power is the clamp's work.
template <int D>
struct TlsphAcceleration {
  TlsphView<D> s;
  ISPH_HD void operator()(Index a) const {
    if (s.fixed[a] && !s.clamps_move) {
      s.acc[a] = Vec<D>::zero();
      return;
    }
    const ElasticMaterial m = s.materials[s.material[a]];
    const Real kappa = 0.5 * s.hourglass * m.youngs_modulus;
    const Real inverse_volume = 1.0 / s.volume[a];
    Vec<D> f = s.stress[a] * s.cgrad_sum[a];
    for (Index k = s.nbr_offset[a]; k < s.nbr_offset[a + 1]; ++k) {
      const Index b = s.nbr[k];
      f += (-s.volume[b] * inverse_volume) * (s.stress[b] * s.rcgrad[k]);
      if (s.hourglass > 0) f += (-kappa * s.hg_weight[k]) * hourglass_difference(s, a, b);
    }
    Vec<D> acc = (1.0 / m.density) * f + s.gravity - s.damping * s.v[a];
    for (int l = 0; l < s.loads; ++l) acc += s.load_factor[l] * s.load_acc[static_cast<long>(l) * s.n + a];
    if (s.interaction) acc += s.interaction[a];
    for_each_wall_overlap(s.obstacles, a, m, s.volume[a], s.x[a],
                          [&](const Vec<D>& e, Real overlap, Real rate, Real) { acc += (rate * overlap) * e; });
    s.acc[a] = acc;
  }
};

// One stage of an explicit Runge-Kutta update, per particle:
//   x_sum += w_sum dt v,  v_sum += w_sum dt acc        (accumulate the final combination)
//   x = x0 + w_next dt v, v = v0 + w_next dt acc       (the next stage's state)
// Classical RK4 (Eqs. 43-45) uses w_sum = 1/6, 1/3, 1/3, 1/6 and w_next = 1/2, 1/2, 1; the last
// stage writes the step's result instead, x = x_sum, v = v_sum (in place, so that a recorded graph of
// the step keeps addressing the same arrays). Clamped particles keep x = X and v = 0.
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
  bool last;
  ISPH_HD void operator()(Index a) const {
    if (fixed[a]) return;
    const Vec<D> va = v[a];
    x_sum[a] += (w_sum * dt) * va;
    v_sum[a] += (w_sum * dt) * acc[a];
    if (last) {
      x[a] = x_sum[a];
      v[a] = v_sum[a];
    } else {
      x[a] = x0[a] + (w_next * dt) * va;
      v[a] = v0[a] + (w_next * dt) * acc[a];
    }
  }
};

// The start of an RK4 step: x0 = x_sum = x, v0 = v_sum = v.
template <int D>
struct StartRungeKutta {
  const Vec<D>* x;
  const Vec<D>* v;
  Vec<D>* x0;
  Vec<D>* v0;
  Vec<D>* x_sum;
  Vec<D>* v_sum;
  ISPH_HD void operator()(Index a) const {
    x0[a] = x_sum[a] = x[a];
    v0[a] = v_sum[a] = v[a];
  }
};

// Structure particles with a non-finite position or velocity, or moved farther than sqrt(limit2) from
// their reference place: a structure that has blown up (TlsphSolver::first_runaway).
template <int D>
struct RunawayParticle {
  const Vec<D>* x;
  const Vec<D>* X;
  const Vec<D>* v;
  Real limit2;
  ISPH_HD bool operator()(Index a) const {
    const Real u2 = norm2(x[a] - X[a]);
    return !finite_value(u2) || !finite_value(norm2(v[a])) || u2 > limit2;
  }
};

// Moving clamps at time t: x = x(X, t) and v = v(X, t) of particle a's motion (pose[m], RigidPose).
template <int D>
struct PrescribeClamps {
  const Index* motion;
  PoseTable<D> pose;
  const Vec<D>* X;
  Vec<D>* x;
  Vec<D>* v;
  ISPH_HD void operator()(Index a) const {
    if (motion[a] < 0) return;
    x[a] = pose[motion[a]].position(X[a]);
    v[a] = pose[motion[a]].velocity(X[a]);
  }
};

// Per-particle terms of the structure's energy books, summed by ordered_sum (TlsphSolver): the kinetic
// energy m_a |v_a|^2 / 2 and the power factor m_a acc_a · v_a of an acceleration field (the interaction,
// a load, or, with factor -1, what a clamp holds its particles against: TlsphSolver::clamp_power), of
// every particle or, with clamped_by given, of the clamped ones only (those with a motion); the strain
// energy V_a psi_a; and the potential energy of gravity -m_a g · (x_a - X_a).
template <int D>
struct KineticEnergyTerm {
  const Index* clamped_by;  // null: every particle
  const Real* mass;
  const Vec<D>* v;
  ISPH_HD Real operator()(Index a) const { return clamped_by && clamped_by[a] < 0 ? 0 : 0.5 * mass[a] * norm2(v[a]); }
};
template <int D>
struct PowerTerm {
  const Index* clamped_by;  // null: every particle
  const Real* mass;
  const Vec<D>* acc;
  const Vec<D>* v;
  Real factor;
  ISPH_HD Real operator()(Index a) const {
    return clamped_by && clamped_by[a] < 0 ? 0 : factor * mass[a] * dot(acc[a], v[a]);
  }
};
struct StrainEnergyTerm {
  const Real* volume;
  const Real* psi;
  ISPH_HD Real operator()(Index a) const { return volume[a] * psi[a]; }
};
template <int D>
struct GravityEnergyTerm {
  const Real* mass;
  Vec<D> gravity;
  const Vec<D>* x;
  const Vec<D>* X;
  ISPH_HD Real operator()(Index a) const { return -mass[a] * dot(gravity, x[a] - X[a]); }
};

// The interaction field alpha(f->s) of a step (TlsphSolver::set_interaction, advance; InteractionSchedule):
// to, or with from the ramp from + s (to - from), and with an impedance minus Gamma_a (v_a - w_a).
// Velocity-Verlet's stored acceleration, where given, moves by the field's change: the field is one
// additive term of it.
template <int D>
struct SetInteraction {
  const Vec<D>* from;  // null: no ramp
  const Vec<D>* to;
  Real s;
  const Mat<D>* impedance;  // null: none
  const Vec<D>* reference_velocity;
  const Vec<D>* v;
  Vec<D>* interaction;
  Vec<D>* acc;  // null: nothing stored
  ISPH_HD void operator()(Index a) const {
    Vec<D> value = from ? from[a] + s * (to[a] - from[a]) : to[a];
    if (impedance) value = value - impedance[a] * (v[a] - reference_velocity[a]);
    if (acc) acc[a] += value - interaction[a];
    interaction[a] = value;
  }
};

// The state kept for a repeated coupled step (save_state, restore_state): to = from for x and v.
template <int D>
struct CopyMotion {
  const Vec<D>* from_x;
  const Vec<D>* from_v;
  Vec<D>* to_x;
  Vec<D>* to_v;
  ISPH_HD void operator()(Index a) const {
    to_x[a] = from_x[a];
    to_v[a] = from_v[a];
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
