#pragma once
// Particle loops of the ISPH predictor and projection (seed 001 Eqs. 10-13, 18-19). Each functor
// writes only particle a and reads its neighbours; wall particles are skipped unless stated.
#include <type_traits>

#include "core/parallel.hpp"
#include "core/rigid_motion.hpp"
#include "kernels/fluid_view.hpp"

namespace isph {

// Corrected velocity gradient G_a = sum_b (u_b - u_a) ⊗ L_a V_b grad W_ab  (G_ij = du_i/dx_j, Eq. 2
// per component), with walls seen through FluidView::velocity_seen (no_slip) or velocity_mirrored
// (free slip). With `smagorinsky` > 0 it also
// gives the sub-particle-scale eddy viscosity of Gotoh et al. (2001), seed Eq. 10:
//   nu_t = (c_s h)^2 sqrt(2 S:S),  S = (G + G^T)/2.
template <int D>
struct VelocityGradient {
  FluidView<D> v;
  const Mat<D>* L;
  const Vec<D>* u;
  bool no_slip;
  Real smagorinsky;  // c_s; 0: no eddy viscosity
  Mat<D>* grad;
  Real* eddy_viscosity;
  ISPH_HD void operator()(Index a) const {
    if (!v.is_fluid(a)) return;
    const OperatorView<D>& op = v.op;
    Mat<D> s = Mat<D>::zero();
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      const Vec<D> ub = no_slip ? v.velocity_seen(a, b, u) : v.velocity_mirrored(a, b, u);
      s = s + outer(ub - u[a], op.volume[b] * op.gradient(a, b, op.r(a, b)));
    }
    const Mat<D> g = s * transpose(L[a]);  // sum (u_b - u_a) ⊗ (L g_ab) = S L^T
    grad[a] = g;
    if (smagorinsky > 0) {
      const Mat<D> strain = 0.5 * (g + transpose(g));
      const Real filter = smagorinsky * op.own_kernel(a).h;
      eddy_viscosity[a] = filter * filter * sqrt(2 * ddot(strain, strain));
    }
  }
};

// Viscous acceleration lap_nu u_a of seed Eqs. 12-13, with the Fatehi-Manzari renormalised Laplacian
// (kernels/operators.hpp) applied per component and the pair viscosity nu_ab = (nu_a + nu_b)/2
// (nu = laminar + eddy; the seed's mu_ab/rho_a for one density):
//   lap_nu u_a = sum_b w_ab nu_ab ((u_a - u_b)/|r_ab| - (G_a r_ab)/|r_ab|),  w_ab = 2 e_ab · B^_a g_ab.
// An explicit update needs a dissipative operator of bounded size, so B^ is used only within a factor
// 2 of I (eigenvalues in (1/2, 2)), and the plain form B^ = I (Morris et al. 1997, always dissipative)
// elsewhere:
//  - where the renormalisation of a truncated support is not positive definite (a free surface meeting
//    a wall), w_ab takes the wrong sign and the update amplifies velocity differences at a rate
//    independent of dt (measured: sunflower oil, nu = 5e-5, at rest in a tank blows up at the surface
//    corners within 0.1 s, at dt = 4.8e-4 and at 1e-4);
//  - where it is positive definite but large, the viscous step limit (viscous_number h^2 / nu, which
//    assumes B^ ~ I) is short by its largest eigenvalue. At the free surface that eigenvalue is
//    arbitrary: B^ is exact for quadratic fields on any support, but on a truncated one only through
//    large cancelling weights. In the rolling tank (dx = 1 mm) interior particles' eigenvalues lay in
//    0.90-1.21 and near-surface ones' up to 3, while surface particles' ran from -4.6e4 to 2.3e4; one
//    with 2.3e4 turned the oil's viscosity into a kick of 1,100 m/s^2 that set off the free surface
//    (docs/VALIDATION.md §18). Shared by the ISPH predictor
// and the weakly compressible model (sim/wcsph_functors.hpp); as a loop it writes zero on non-fluid
// particles.
template <int D>
struct ViscousAcceleration {
  FluidView<D> v;
  const Mat<D>* Bhat;
  const Mat<D>* grad;
  const Vec<D>* u;
  const Real* eddy_viscosity;  // nullptr: laminar only
  Real viscosity;
  Vec<D>* out = nullptr;
  // Calls term(b, c_ab) for each neighbour b of fluid particle a with its pair term
  //   c_ab = nu_ab w_ab ((u_a - u_b) - G_a r_ab)/|r_ab|,  lap_nu u_a = sum_b c_ab,
  // or, with `flux_form`, Morris et al.'s c_ab = nu_ab w_ab (u_a - u_b)/|r_ab| with B^ = I: the momentum
  // that crosses from b to a, so that the terms of a wall's particles sum to its traction on a. (The
  // corrected terms vanish pair by pair in a linear shear, which carries a stress all the same.)
  template <class Term>
  ISPH_HD void for_each_term(Index a, bool flux_form, Term term) const {
    const OperatorView<D>& op = v.op;
    const Real nu_a = viscosity_at(a);
    const Mat<D> I = Mat<D>::identity();
    const bool bounded = !flux_form && positive_definite(Bhat[a] - 0.5 * I) && positive_definite(2.0 * I - Bhat[a]);
    const Mat<D> bhat = bounded ? Bhat[a] : I;
    const Mat<D> G = flux_form ? Mat<D>::zero() : grad[a];
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      term(b, pair_term(a, b, nu_a, bhat, G));
    }
  }
  // nu = laminar + eddy (the eddy viscosity lives on fluid particles only).
  ISPH_HD Real viscosity_at(Index a) const {
    return viscosity + (eddy_viscosity && v.is_fluid(a) ? eddy_viscosity[a] : 0);
  }
  // The pair term c_ab of for_each_term, given a's viscosity, B^ and G (zero for b = a).
  ISPH_HD Vec<D> pair_term(Index a, Index b, Real nu_a, const Mat<D>& bhat, const Mat<D>& G) const {
    return pair_weight(a, b, nu_a, bhat) * (u[a] - v.velocity_seen(a, b, u) - G * v.op.r(a, b));
  }
  // Its weight nu_ab w_ab / |r_ab| (zero for b = a).
  ISPH_HD Real pair_weight(Index a, Index b, Real nu_a, const Mat<D>& bhat) const {
    const OperatorView<D>& op = v.op;
    const Vec<D> r_ab = op.r(a, b);
    const Real rho = sqrt(norm2(r_ab));
    if (!(rho > 0)) return 0;
    const Real nu_b = viscosity_at(b);
    return 0.5 * (nu_a + nu_b) * laplacian_pair_weight(bhat, r_ab, rho, op.volume[b] * op.gradient(a, b, r_ab)) / rho;
  }
  ISPH_HD Vec<D> at(Index a) const {
    Vec<D> lap = Vec<D>::zero();
    for_each_term(a, false, [&](Index, const Vec<D>& c) { lap += c; });
    return lap;
  }
  ISPH_HD void operator()(Index a) const { out[a] = v.is_fluid(a) ? at(a) : Vec<D>::zero(); }
};

// Power of the walls' viscous traction on fluid particle a: its wall neighbours act on it with the
// force m_a c_ab (ViscousAcceleration's flux form) and move with U_b, so they work at
//   P_a = rho V_a sum_{b wall} c_ab · U_b
// (fixed walls give 0; structures do not count: they feel the traction back, ViscousBoundaryForce, and
// their energy is in the books). With their
// pressure's, the moving walls' work on the fluid (ParticleSet::moving_wall_power); on the plate of
// Couette flow it is mu U^2/H per area.
template <int D>
struct ViscousWallPower {
  ViscousAcceleration<D> viscous;
  Real density;
  Real* power;
  ISPH_HD void operator()(Index a) const {
    const FluidView<D>& v = viscous.v;
    Real p = 0;
    if (v.is_fluid(a))
      viscous.for_each_term(a, true, [&](Index b, const Vec<D>& c) {
        if (v.kind[b] == FluidKind::wall) p += dot(c, v.wall_velocity[b]);
      });
    power[a] = density * v.op.volume[a] * p;
  }
};

// The viscous force per unit volume on boundary particle w of kind `target` (zero on the others): each
// fluid neighbour a feels m_a c_aw from it (ViscousAcceleration's flux form), so w takes
//   f_w = -(rho / V_w) sum_{a fluid} V_a c_aw.
// Summed over a wall body with its volumes (ParticleSet::body_viscous_force), the drag's viscous part;
// on structure particles, the fluid's shear on the structure (added to the pressure's, coupling.cpp),
// with `impedance` Z_w = -df_w/dU_w = -(rho / V_w) sum_a V_a (nu w / |r|)_aw (1 + d_w / d_a) >= 0, by
// which the structure's substeps answer their own velocity (docs/VALIDATION.md section 36).
template <int D>
struct ViscousBoundaryForce {
  ViscousAcceleration<D> viscous;
  Real density;
  FluidKind target;
  Vec<D>* force_density;
  Real* impedance = nullptr;
  ISPH_HD void operator()(Index w) const {
    const FluidView<D>& v = viscous.v;
    if (v.kind[w] != target) return;
    Vec<D> f = Vec<D>::zero();
    Real z = 0;
    for (Index k = v.op.nbr_offset[w]; k < v.op.nbr_offset[w + 1]; ++k) {
      const Index a = v.op.nbr[k];
      if (!v.is_fluid(a)) continue;
      const Real weight = viscous.pair_weight(a, w, viscous.viscosity_at(a), Mat<D>::identity());
      f += (v.op.volume[a] * weight) * (viscous.u[a] - v.velocity_seen(a, w, viscous.u));
      z += v.op.volume[a] * weight * v.no_slip_gain(a, w);
    }
    force_density[w] = (-density / v.op.volume[w]) * f;
    if (impedance) impedance[w] = (-density / v.op.volume[w]) * z;
  }
};

// One pass of the outlet buffers' velocity (sim/open_boundary.hpp): each buffer particle b takes the
// velocity of the particle nearest the point one spacing ahead of it, x_b + dx n (n: the normal into
// the fluid), fluid or buffer, within dx/2 of it; out = in elsewhere. As many passes as the buffer has
// layers carry the velocity the fluid has beside the plane through the whole buffer, row by row: the
// flow leaves with zero gradient along n and the buffer moves as one. (A kernel average across the
// rows flattened the channel's profile at the outlet to 4.4 % of its peak; buffer particles that kept
// the velocity they crossed with were overtaken by faster ones behind them as the inflow ramped up,
// and the buffer drew fluid out of the channel: docs/VALIDATION.md section 34.)
// The last pass also sets the buffer's wall velocity, with which it moves (Drift, Advance).
template <int D>
struct OutletVelocityPass {
  FluidView<D> v;
  const Vec<D>* in;
  Vec<D>* out;
  Vec<D>* wall_velocity = nullptr;  // the last pass's
  ISPH_HD void operator()(Index b) const {
    out[b] = in[b];
    if (!v.is_outlet(b)) return;
    const Vec<D> ahead = v.dx * v.wall_normal[b];  // the point, relative to x_b
    Real nearest2 = 0.25 * v.dx * v.dx;
    for (Index k = v.op.nbr_offset[b]; k < v.op.nbr_offset[b + 1]; ++k) {
      const Index a = v.op.nbr[k];
      if (!v.is_fluid(a) && !v.is_outlet(a)) continue;
      const Real d2 = norm2(ahead + v.op.r(b, a));  // |x_a - (x_b + ahead)|^2
      if (d2 < nearest2) nearest2 = d2, out[b] = in[a];
    }
    if (wall_velocity) wall_velocity[b] = out[b];
  }
};

// Intermediate velocity, Eqs. 12-13: u*_a = u_a + dt (g + lap_nu u_a) (ViscousAcceleration).
// Wall and structure particles get the intermediate velocity that the projection would turn into
// their own new velocity: u*_w = U_w + dt g, which the wall pressure gradient rho (g - a_w) of
// PpeRowFill takes to U_w + dt a_w; so a fluid at rest stays at rest.
template <int D>
struct VelocityPredictor {
  ViscousAcceleration<D> viscous;
  Vec<D> gravity;
  Real dt;
  Vec<D>* u_star;
  ISPH_HD void operator()(Index a) const {
    const FluidView<D>& v = viscous.v;
    if (!v.is_fluid(a)) {
      u_star[a] = v.wall_velocity[a] + dt * gravity;
      return;
    }
    u_star[a] = viscous.u[a] + dt * (gravity + viscous.at(a));
  }
};

// The velocity whose divergence is the PPE's source when the projection constrains the step's weighted
// velocity theta u^{n+1} + (1 - theta) u^n rather than u^{n+1} alone (fluid.constraint_weight; docs/VALIDATION.md
// section 36): with u^{n+1} = u* - (dt/rho) grad p, that constraint is div(u* + ((1 - theta)/theta) u^n) =
// (dt/rho) div grad p. All particles (walls and structures carry their own velocity in u).
template <int D>
struct ConstrainedVelocity {
  const Vec<D>* u_star;
  const Vec<D>* u;
  Real old_weight;  // (1 - theta) / theta
  Vec<D>* out;
  ISPH_HD void operator()(Index a) const { out[a] = u_star[a] + old_weight * u[a]; }
};

// A box without a Dirichlet row (closed or periodic) fixes its pressure at one pinned particle, whose row then
// carries p = 0 in place of its divergence equation; the equations it drops must add up to nothing, i.e. the
// source must sum to zero over the box (Gauss: no flux through its walls), or the pinned particle takes the
// discrete sum's remainder as a point source (docs/VALIDATION.md section 11). FluidVolumeSum gives
// sum V_a value_a over the fluid particles (value null: their volume), RemoveFromFluid subtracts the mean
// totals[0] / totals[1] (the two sums, left where the sums ran: no copy to the host).
struct FluidVolumeSum {
  const FluidKind* kind;
  const Real* volume;
  const Real* value;
  ISPH_HD double operator()(Index a) const {
    return kind[a] == FluidKind::fluid ? volume[a] * (value ? value[a] : Real{1}) : 0.0;
  }
};
struct RemoveFromFluid {
  const FluidKind* kind;
  const double* totals;
  Real* value;
  ISPH_HD void operator()(Index a) const {
    if (kind[a] == FluidKind::fluid) value[a] -= totals[0] / totals[1];
  }
};

// Projection, Eq. 18: u^{n+1}_a = u*_a - (dt/rho) <grad p>_a, with <grad p> the corrected gradient
// (CorrectedGradient), followed by a kinematic impermeability condition: a fluid particle closer than
// dx/2 to the surface of its nearest wall neighbour loses the velocity component (relative to the
// wall) that carries it further in. The PPE keeps interior fluid out of walls through the wall
// pressure, but free-surface particles (p = 0, alpha = 0: a thin front running along a floor) carry no
// incompressibility constraint, and without this they can drift into the wall. The same holds for
// every other fixed wall's surface the particle lies within dx/2 of, on either side: in an edge or a
// corner of walls it is that near two or three faces, and with the nearest particle's face alone it
// slid through another (docs/VALIDATION.md section 30). Faces of the first layer only (depth dx/2,
// convex corners' bisectors included): the particles beneath a concave edge face it diagonally, across
// the water's corner, and their face, added to the two it joins, threw the water out of the corner. A
// structure's faces are planes only near each particle (normals turned by F, depths fixed), so there
// the nearest particle's face alone counts. A confined flow (fluid.free_surface = false) has no such
// particles: every row holds the PPE and its wall rows keep the fluid out, so the condition is off there
// (`kinematic_walls`); the divergence it left in a channel drove a pressure over the whole channel
// (docs/VALIDATION.md section 35).
template <int D>
struct Project {
  FluidView<D> v;
  const Vec<D>* grad_p;
  const Vec<D>* u_star;
  Real density;
  Real dt;
  Vec<D>* u_new;
  bool kinematic_walls = true;      // the impermeability condition (above)
  const Index* body = nullptr;      // with contact_force: the force of the condition on the walls
  Vec<D>* contact_force = nullptr;  // per unit volume of a, on the body of the last face it met
  Index* contact_body = nullptr;    // that body (-1: none)
  ISPH_HD void operator()(Index a) const {
    if (contact_force) contact_force[a] = Vec<D>::zero(), contact_body[a] = -1;
    if (!v.is_fluid(a)) return;
    Vec<D> u = u_star[a] - (dt / density) * grad_p[a];
    if (!kinematic_walls) {
      u_new[a] = u;
      return;
    }
    const auto faced = [&](Index b) { return !v.is_fluid(b) && !v.is_open(b) && norm2(v.wall_normal[b]) > 0; };
    Real r2;
    const Index nearest = v.nearest_neighbour(a, faced, r2);
    for (Index k = v.op.nbr_offset[a]; k < v.op.nbr_offset[a + 1]; ++k) {
      const Index b = v.op.nbr[k];
      if (!faced(b)) continue;
      const Real beyond = v.beyond_surface(a, b);
      const bool other_wall_face =
          v.kind[b] == FluidKind::wall && v.wall_depth[b] < 0.75 * v.dx && beyond > -0.5 * v.dx;
      if (!(beyond < 0.5 * v.dx && (b == nearest || other_wall_face))) continue;
      const Vec<D> n = v.wall_normal[b];
      const Real approach = dot(u - v.wall_velocity[b], n);
      if (!(approach < 0)) continue;
      u = u - approach * n;
      if (contact_force) contact_force[a] += (density * approach / dt) * n, contact_body[a] = body[b];
    }
    u_new[a] = u;
  }
};

// Inelastic collisions of fluid particles that come closer than `distance` (Kruisbrink, Korzilius, Pearce
// & Morvan 2018, J. Appl. Math. Phys. 6:1860; the collision model of MPS, Lee et al. 2011, Comput.
// Methods Appl. Mech. Eng. 200:1113): for each such pair still approaching along n_ab = r_ab/|r_ab|,
//   u_a += -(1 + e) (m_b / (m_a + m_b)) min(0, (u_a - u_b) · n_ab) n_ab,
// the velocity change of a collision with restitution e, from the pair's velocities before any
// collision of this step (a gather: each pair's two changes are equal and opposite in momentum, and
// with e <= 1 they take kinetic energy out, never in). Free-surface particles carry p = 0, so nothing
// else stops two surface layers that meet, as where the dam break's plunging wave closes its air cavity;
// there they clumped at 0.4-0.6 dx until the PPE, once they counted as interior, threw them apart
// (docs/VALIDATION.md section 10). A regular particle distribution has no pair closer than about 0.8 dx
// and is not touched.
template <int D>
struct ParticleCollision {
  FluidView<D> v;
  const Vec<D>* u;  // u^{n+1} from Project
  Real distance;    // [m]
  Real restitution;
  Vec<D>* out;
  ISPH_HD void operator()(Index a) const {
    Vec<D> change = Vec<D>::zero();  // walls and structures keep their velocity
    for (Index k = v.op.nbr_offset[a]; k < v.op.nbr_offset[a + 1] && v.is_fluid(a); ++k) {
      const Index b = v.op.nbr[k];
      if (!v.is_fluid(b)) continue;
      const Vec<D> r = v.op.r(a, b);
      const Real r2 = norm2(r);
      if (!(r2 > 0) || r2 >= distance * distance) continue;
      const Vec<D> n = (1.0 / sqrt(r2)) * r;
      const Real approach = dot(u[a] - u[b], n);
      const Real share = v.op.volume[b] / (v.op.volume[a] + v.op.volume[b]);  // m_b / (m_a + m_b)
      if (approach < 0) change += (-(1 + restitution) * share * approach) * n;
    }
    out[a] = u[a] + change;
  }
};

// Position update, Eq. 19: r^{n+1}_a = r^n_a + dt (u^n_a + u^{n+1}_a)/2 (u holds u^n on entry and
// u^{n+1} on exit). Walls move with their prescribed velocity.
template <int D>
struct Advance {
  const FluidKind* kind;
  const Vec<D>* wall_velocity;
  const Vec<D>* u_new;
  const Vec<D>* x_old;
  Real dt;
  Periodicity<D> period;
  Vec<D>* u;
  Vec<D>* x;
  ISPH_HD void operator()(Index a) const {
    if (kind[a] != FluidKind::fluid) {
      x[a] = period.wrap(x_old[a] + dt * wall_velocity[a]);
      return;
    }
    x[a] = period.wrap(x_old[a] + (0.5 * dt) * (u[a] + u_new[a]));
    u[a] = u_new[a];
  }
};

// The drift of Eq. 11 and its reverse: to = from + step u for fluid particles and from + step U_w for
// wall and structure particles (step = +dt or -dt), wrapped into the periodic box when `wrap`.
template <int D>
struct Drift {
  const FluidKind* kind;
  const Vec<D>* u;
  const Vec<D>* wall_velocity;
  Real step;
  bool wrap;
  Periodicity<D> period;
  const Vec<D>* from;
  Vec<D>* to;
  ISPH_HD void operator()(Index a) const {
    const Vec<D> to_a = from[a] + step * (kind[a] == FluidKind::fluid ? u[a] : wall_velocity[a]);
    to[a] = wrap ? period.wrap(to_a) : to_a;
  }
};

// Values reduced over the particles (parallel_reduce): |u|^2 of fluid particles (0 for the others);
// (a per-particle scalar: ScalarAt, core/parallel.hpp); 1 for a fluid row with a Dirichlet condition
// (alpha = 0); a per-particle flag (to count, or to select); and the key id * 2^32 + a of the particles
// a selector accepts (the largest key for the others), whose minimum names the selected particle of
// lowest stable id (lowest_id_particle).
template <int D>
struct FluidSpeed2 {
  const FluidKind* kind;
  const Vec<D>* u;
  ISPH_HD Real operator()(Index a) const { return kind[a] == FluidKind::fluid ? norm2(u[a]) : 0; }
};
struct DirichletRow {
  const FluidKind* kind;
  const Real* alpha;
  ISPH_HD Index operator()(Index a) const { return kind[a] == FluidKind::fluid && alpha[a] == 0; }
};
struct Flagged {
  const unsigned char* flag;
  ISPH_HD Index operator()(Index a) const { return flag[a]; }
};
struct IsFluid {
  const FluidKind* kind;
  ISPH_HD bool operator()(Index a) const { return kind[a] == FluidKind::fluid; }
};
inline constexpr long long kNoIdKey = 0x7fffffffffffffffLL;
template <class Select>
struct IdKey {
  Select select;
  const Index* id;
  ISPH_HD long long operator()(Index a) const {
    return select(a) ? (static_cast<long long>(id[a]) << 32) + a : kNoIdKey;
  }
};

// The particle of lowest stable id among those `select` accepts, or -1.
template <class Select>
Index lowest_id_particle(const Exec& exec, Index n, Select select, const Index* id) {
  const long long key = parallel_reduce(exec, n, kNoIdKey, IdKey<Select>{select, id}, MinOf{});
  return key == kNoIdKey ? -1 : static_cast<Index>(key & 0xffffffffLL);
}

// Particles with a non-finite position, velocity or pressure.
template <int D>
struct NonFiniteState {
  const Vec<D>* x;
  const Vec<D>* u;
  const Real* p;
  ISPH_HD bool operator()(Index a) const {
    return !finite_value(norm2(x[a])) || !finite_value(norm2(u[a])) || !finite_value(p[a]);
  }
};

// Fluid particles outside the box [lo, hi].
template <int D>
struct FluidOutsideBox {
  const FluidKind* kind;
  const Vec<D>* x;
  Vec<D> lo, hi;
  ISPH_HD bool operator()(Index a) const {
    if (kind[a] != FluidKind::fluid) return false;
    bool outside = false;
    for (int d = 0; d < D; ++d) outside = outside || x[a][d] < lo[d] || x[a][d] > hi[d];
    return outside;
  }
};

// A value of structure particle k to its TLSPH index (the pressure force density, plus the viscous one
// where `added` is given; the impedance; with `unit`, a vector's direction: of its PPE row's moment,
// zero where the row has none).
template <int D, class T = Vec<D>>
struct ScatterToStructure {
  const Index* structure_index;
  const T* value;
  bool unit;
  T* out;
  const T* added = nullptr;
  ISPH_HD void operator()(Index k) const {
    const Index s = structure_index[k];
    if (s < 0) return;
    const T sum = added ? value[k] + added[k] : value[k];
    if constexpr (std::is_same_v<T, Vec<D>>) {
      const Real len = sqrt(norm2(sum));
      out[s] = !unit ? sum : len > 0 ? (1.0 / len) * sum : Vec<D>::zero();
    } else {
      out[s] = sum;
    }
  }
};

// The wall particles as obstacles of the structure (ParticleSet::gather_walls): with
// slot[k + 1] = 1 for a wall and 0 otherwise, summed (inclusive_scan), wall k goes to place slot[k],
// as point x_k with radius V_k^(1/D) / 2.
struct MarkWalls {
  const FluidKind* kind;
  Index* slot;
  ISPH_HD void operator()(Index k) const { slot[k + 1] = kind[k] == FluidKind::wall ? 1 : 0; }
};
template <int D>
struct GatherWalls {
  const FluidKind* kind;
  const Vec<D>* x;
  const Real* volume;
  const Index* slot;
  Vec<D>* point;
  Real* radius;
  ISPH_HD void operator()(Index k) const {
    if (kind[k] != FluidKind::wall) return;
    point[slot[k]] = x[k];
    radius[slot[k]] = 0.5 * particle_spacing<D>(volume[k]);
  }
};

// Boundary particles that belong to a structure take its state from the TLSPH solver (arrays indexed
// as there): position, velocity, and the surface normal turned with the deformation,
// n = F^{-T} N / |F^{-T} N|.
template <int D>
struct FollowStructure {
  const Index* structure_index;
  const Vec<D>* x;
  const Vec<D>* v;
  const Mat<D>* F;
  const Vec<D>* reference_normal;
  Vec<D>* position;
  Vec<D>* velocity;
  Vec<D>* wall_velocity;
  Vec<D>* wall_normal;
  ISPH_HD void operator()(Index k) const {
    const Index s = structure_index[k];
    if (s < 0) return;
    position[k] = x[s];
    velocity[k] = wall_velocity[k] = v[s];
    const Vec<D> n = transpose(inverse(F[s])) * reference_normal[k];
    const Real len = sqrt(norm2(n));
    wall_normal[k] = len > 0 ? (1.0 / len) * n : Vec<D>::zero();
  }
};

// ... and their acceleration over the step.
template <int D>
struct FollowStructureAcceleration {
  const Index* structure_index;
  const Vec<D>* acceleration;
  Vec<D>* wall_acceleration;
  ISPH_HD void operator()(Index k) const {
    if (const Index s = structure_index[k]; s >= 0) wall_acceleration[k] = acceleration[s];
  }
};

// Moving walls over [t, t + dt], from the pose of each motion at t and at t + dt (now[m], next[m]):
// from x(t) they move by their chord of the step, with the velocity (x(t + dt) - x(t))/dt (what the
// fluid sees of a structure too, sim/coupling.hpp), the acceleration (v(t + dt) - v(t))/dt, and their
// normals turned to t + dt.
template <int D>
struct PrescribeWalls {
  const Index* motion;
  PoseTable<D> now, next;
  const Vec<D>* reference_x;
  const Vec<D>* reference_normal;
  Real dt;
  Periodicity<D> period;
  Vec<D>* x;
  Vec<D>* u;
  Vec<D>* wall_velocity;
  Vec<D>* wall_acceleration;
  Vec<D>* wall_normal;
  ISPH_HD void operator()(Index a) const {
    if (motion[a] < 0) return;
    const RigidPose<D>& from = now[motion[a]];
    const RigidPose<D>& to = next[motion[a]];
    const Vec<D>& X = reference_x[a];
    const Vec<D> start = from.position(X);
    x[a] = period.wrap(start);
    u[a] = wall_velocity[a] = (1.0 / dt) * (to.position(X) - start);
    wall_acceleration[a] = (1.0 / dt) * (to.velocity(X) - from.velocity(X));
    wall_normal[a] = to.R * reference_normal[a];
  }
};

// Power of a moving wall particle's pressure force on the fluid, -V_w f_w · u_w (0 for the others).
template <int D>
struct MovingWallPressurePower {
  const Index* motion;
  const Real* volume;
  const Vec<D>* boundary_force;
  const Vec<D>* wall_velocity;
  ISPH_HD Real operator()(Index a) const {
    return motion[a] >= 0 ? -volume[a] * dot(boundary_force[a], wall_velocity[a]) : 0;
  }
};

}  // namespace isph
