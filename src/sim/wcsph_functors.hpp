#pragma once
// Particle loops of the weakly compressible comparator (seed 002 §2; sim/wcsph.hpp). Each functor
// writes only particle a and reads its neighbours (from the neighbour list of the advection step, with
// kernel values at the current positions).
//
// Notation: for particle a and neighbour b, r_ab = x_a - x_b, g_ab = grad_a W(r_ab) (no volume),
// e_ab = -r_ab/|r_ab| the unit vector from a to b, V_b = m_b/rho_b the neighbour's volume.
#include "kernels/fluid_view.hpp"

namespace isph {

// Density reinitialisation at the start of an advection step, seed 002 Eqs. 11-12:
//   free surface: rho_a = max(rho*_a, rho0 sum_b W_ab / sum_b W0_ab),  otherwise rho_a = rho0 sum_b W_ab / sum_b W0_ab,
// with the sums over all neighbours and a itself (FluidView::kernel_sum, each neighbour with its mass's
// share V_b / V_a); sum W0 is the sum of a full lattice of spacing dx (the initial particle arrangement).
template <int D>
struct DensityReinitialisation {
  FluidView<D> v;
  Real density, full_sum;
  bool free_surface;
  Real* rho;
  ISPH_HD void operator()(Index a) const {
    if (!v.is_fluid(a)) return;
    bool beside_structure;
    const Real rho_sum = density * v.kernel_sum(a, beside_structure) / full_sum;
    rho[a] = free_surface ? fmax(rho[a], rho_sum) : rho_sum;
  }
};

// Pressure and density of wall and structure particles from the fluid around them (Adami, Hu & Adams
// 2012, J. Comput. Phys. 231:7057, Eq. 27): p_w = (sum_f p_f W_wf + (g - a_w) · sum_f rho_f r_wf W_wf) / sum_f W_wf,
// which gives the hydrostatic pressure below a wall surface and the pressure that stops a wall's
// acceleration; rho_w from the equation of state (Eq. 2 inverted). Dry boundary particles get p = 0.
// Structure particles carry a_w = 0 here (sim/coupling.hpp says why).
template <int D>
struct BoundaryPressure {
  FluidView<D> v;
  Vec<D> gravity;
  Real density, sound_speed;
  Real* p;
  Real* rho;
  ISPH_HD void operator()(Index w) const {
    if (v.is_fluid(w)) return;
    const Vec<D> g = gravity - v.wall_acceleration[w];
    Real num = 0, den = 0;
    for (Index k = v.op.nbr_offset[w]; k < v.op.nbr_offset[w + 1]; ++k) {
      const Index f = v.op.nbr[k];
      if (!v.is_fluid(f)) continue;
      const Vec<D> r = v.op.r(w, f);
      const Real W = v.op.kernel(w, f).value(sqrt(norm2(r)));
      num += W * (p[f] + rho[f] * dot(g, r));
      den += W;
    }
    p[w] = den > 0 ? num / den : 0;
    rho[w] = density + p[w] / (sound_speed * sound_speed);
  }
};

// The pair interactions of seed 002 Eqs. 3-4 with the inter-particle averages replaced by the solution
// of a linearised Riemann problem along e_ab (Eq. 6; Zhang, Hu & Adams 2017, J. Comput. Phys. 335:605):
//   left state a: U_L = v_a · e_ab, P_L = p_a;  right state b: U_R = v_b · e_ab, P_R = p_b;
//   U* = (rho_L U_L + rho_R U_R + (P_L - P_R)/c) / (rho_L + rho_R),
//   P* = (rho_L P_R + rho_R P_L + rho_L rho_R c beta (U_L - U_R)) / (rho_L + rho_R),
//   beta = min(eta max(U_L - U_R, 0)/c, 1)   (the low-dissipation limiter: no dissipation in expansion),
//   or beta = 1 with eta = 0 (the plain linearised acoustic Riemann solver).
// Since g_ab = |W'| e_ab is parallel to e_ab, only the normal velocity of Eq. 6's average enters:
//   continuity  drho_a/dt = 2 rho_a sum_b V_b (U_L - U*) (e_ab · g_ab),
//   momentum    dv_a/dt   = -(2/rho_a) sum_b V_b P* g_ab.
// A boundary particle b (wall or structure) enters with its prescribed velocity and the pressure and
// density of BoundaryPressure, volume V0_b. On a boundary particle a, the momentum pass gives the
// pressure force per unit volume from its fluid neighbours, f_a = -2 sum_f V_f P* g_af, equal and
// opposite to the force on them pair by pair (seed 001 Eq. 46), and, where asked, the impedance
//   Z_a = -df_a/dv_a = 2 sum_f V_f (rho_L rho_R c beta / (rho_L + rho_R)) |g_af| e_af e_af^T,
// the dissipative part of P* differentiated with beta held: the fluid's acoustic resistance to the
// boundary particle's motion (StructureCoupling::explicit_step).
template <int D>
struct RiemannInteraction {
  FluidView<D> v;
  const Vec<D>* u;  // fluid velocity (boundary particles use v.wall_velocity)
  const Real* rho;
  const Real* p;
  Real density, sound_speed, limiter;
  Real* drho_dt;           // continuity pass when not null (fluid particles)
  Vec<D>* acceleration;    // momentum pass when not null: the fluid's pressure acceleration ...
  Vec<D>* boundary_force;  // ... and the boundary particles' force density
  Mat<D>* impedance;       // ... and their impedance Z_a, when not null

  ISPH_HD Real volume(Index b) const { return v.is_fluid(b) ? density * v.op.volume[b] / rho[b] : v.op.volume[b]; }
  ISPH_HD Vec<D> velocity(Index b) const { return v.is_fluid(b) ? u[b] : v.wall_velocity[b]; }

  ISPH_HD void operator()(Index a) const {
    const bool fluid_a = v.is_fluid(a);
    const Real c = sound_speed;
    Real continuity = 0;
    Vec<D> momentum = Vec<D>::zero();
    Mat<D> resistance = Mat<D>::zero();
    for (Index k = v.op.nbr_offset[a]; k < v.op.nbr_offset[a + 1]; ++k) {
      const Index b = v.op.nbr[k];
      if (!fluid_a && !v.is_fluid(b)) continue;  // boundary particles feel the fluid only
      const Vec<D> g = v.op.gradient(a, b, v.op.r(a, b));
      const Real g_len = sqrt(norm2(g));
      if (!(g_len > 0)) continue;
      const Vec<D> e = (1.0 / g_len) * g;  // g_ab = W'(r) r_ab/r = |W'| e_ab (W' < 0)
      const Real uL = dot(velocity(a), e), uR = dot(velocity(b), e);
      const Real rL = rho[a], rR = rho[b];
      const Real Vb = volume(b);
      if (drho_dt) {
        const Real u_star = (rL * uL + rR * uR + (p[a] - p[b]) / c) / (rL + rR);
        continuity += Vb * (uL - u_star) * dot(e, g);
      }
      if (acceleration) {
        const Real beta = limiter > 0 ? fmin(limiter * fmax(uL - uR, 0.0) / c, 1.0) : 1.0;
        const Real p_star = (rL * p[b] + rR * p[a] + rL * rR * c * beta * (uL - uR)) / (rL + rR);
        momentum += (Vb * p_star) * g;
        if (!fluid_a && impedance) {  // d(beta (uL - uR))/d(uL - uR): 2 beta where the limiter acts, else beta
          const Real slope = limiter > 0 && beta < 1 ? 2 * beta : beta;
          resistance = resistance + (2 * Vb * rL * rR * c * slope / (rL + rR) * g_len) * outer(e, e);
        }
      }
    }
    if (drho_dt && fluid_a) drho_dt[a] = 2 * rho[a] * continuity;
    if (!acceleration) return;
    if (fluid_a)
      acceleration[a] = (-2.0 / rho[a]) * momentum;
    else
      boundary_force[a] = -2.0 * momentum;
    if (!fluid_a && impedance) impedance[a] = resistance;
  }
};

// Velocity-Verlet half kick of the fluid, seed 002 Eqs. 13 and 15: v += dt/2 (a_p + a_visc + g).
template <int D>
struct VerletKick {
  const FluidKind* kind;
  const Vec<D>* acceleration;
  const Vec<D>* viscous;
  Vec<D> gravity;
  Real half_dt;
  Vec<D>* u;
  ISPH_HD void operator()(Index a) const {
    if (kind[a] == FluidKind::fluid) u[a] += half_dt * (acceleration[a] + viscous[a] + gravity);
  }
};

// Positions, Eq. 14: the fluid with its half-step velocity, walls along their prescribed chord
// (structure particles are placed by the coupling).
template <int D>
struct VerletDrift {
  const FluidKind* kind;
  const Vec<D>* u;
  const Vec<D>* wall_velocity;
  Real dt;
  Periodicity<D> period;
  Vec<D>* x;
  ISPH_HD void operator()(Index a) const {
    if (kind[a] == FluidKind::fluid)
      x[a] = period.wrap(x[a] + dt * u[a]);
    else if (kind[a] == FluidKind::wall)
      x[a] = period.wrap(x[a] + dt * wall_velocity[a]);
  }
};

// Density of the fluid advanced by dt drho/dt (Eq. 14; none when drho_dt is null), and its pressure
// from the equation of state p = c^2 (rho - rho0) (Eq. 2).
template <int D>
struct EquationOfState {
  const FluidKind* kind;
  const Real* drho_dt;
  Real dt, density, sound_speed;
  Real* rho;
  Real* p;
  ISPH_HD void operator()(Index a) const {
    if (kind[a] != FluidKind::fluid) return;
    if (drho_dt) rho[a] += dt * drho_dt[a];
    p[a] = sound_speed * sound_speed * (rho[a] - density);
  }
};

}  // namespace isph
