#pragma once
// The pressure Poisson equation as a sparse matrix, one row per particle, assembled straight from
// the CSR neighbour list (seed 001 Eqs. 14-16). Row a holds the diagonal first and then one entry
// per neighbour, in neighbour-list order, so row_offset[a] = a + nbr_offset[a] and no counting pass
// is needed. Entries are gathered: the loop writes only row a.
//
// Fluid row (Eq. 15, multiplied by -1 so that the diagonal is positive), made exact for linear fields:
//   sum_b c_ab (p_a - p_b) - m1_a · <grad p>_a = -(1/dt) <div u*>_a,
//   c_ab = -2 V_b r_ab · (L_a grad W_ab) / (rho |r_ab|^2),   m1_a = sum_b c_ab r_ab,
// with L_a the gradient correction (the matrix is therefore not symmetric), <grad p>_a the corrected
// gradient (Eq. 2: sum_b V_b (p_b - p_a) L_a grad W_ab, the same neighbours, so the row keeps its
// stencil) and <div u*> the corrected divergence (Eq. 3). For a linear p the two-point sum is
// m1_a · grad p, which the correction removes: Eq. 15 alone is exact for linear fields only where the
// support is symmetric (m1 = 0). Without it, the hydrostatic field is not a solution of the discrete
// equation wherever the support is not: at walls and free surfaces (an O(dx) offset of the whole
// field) and, in the interior, where a structure finer than the water meets it. There the first
// fluid rows took an odd-even pressure pattern that neither the divergence nor the gradient of the
// projection sees, and still water over a fine floor grew currents exponentially (docs/VALIDATION.md
// section 23). The correction is the first-order part of the Laplacian's consistency condition (the
// renormalised Laplacian of Fatehi & Manzari 2011, seed Eq. 4, with B^ = I). It is made only in rows
// where the PPE holds in full (Skillen's alpha_a = 1): in a row blended with the surface condition the
// neighbourhood is cut by the surface, m1 and <grad p>_a are one-sided, and the corrected weights of a
// thin sheet or a closing cavity answered with pressures that threw particles apart (the dam break's
// plunging wave created 43 % more energy before 0.85 s and stopped at t sqrt(g/a) = 7.34;
// docs/VALIDATION.md section 10). The hydrostatic field stays exact: the surface condition carries it there.
//
// Density-invariant term (density_relaxation gamma > 0, full rows): with the particles' kernel sum
// sigma_a = sum_b (V_b / V_a) W_ab (FluidView::kernel_sum; self included, walls count), S on a regular
// lattice (full_kernel_sum) and S rho*/rho0 where the particles have spread or crowded, the row's source becomes
// -(1/dt) <div u*>_a - gamma (1 - sigma_a / S) / dt^2, so that the projected velocity has
// div u = gamma (sigma / S - 1) / dt: a region whose particles have spread contracts by the fraction
// gamma of its deficit per step (the stabilised ISPH of Asai, Aly, Sonoda & Sakai 2012, J. Appl. Math.
// 2012:139583). ISPH keeps div u = 0 but not the particles' spacing: in an open channel the flow around
// an obstacle spread the particles at its shoulders until more fluid left through the outlet than came
// in (docs/VALIDATION.md section 35). Rows beside a structure take no such term: its particles lie on a
// lattice of their own, where sigma is not S even at rest (10 kPa in the water around a clamped bar).
//
// Free-surface condition, blended by Skillen's coefficient alpha_a (Eq. 17). With the PPE row divided
// by its diagonal, P_a(p) = 0, and a surface condition S_a(p) = 0, row a is
//   alpha_a P_a(p) + (1 - alpha_a) S_a(p) = 0.
// "zero":         S_a = p_a, the seed's Dirichlet condition; the blend is then exactly Eq. 16,
//                 A_aa p_a + alpha_a sum_b A_ab p_b = alpha_a B_a.
// "extrapolated": p = 0 half a particle spacing beyond the particle, where the fluid ends, imposed by
//                 first-order extrapolation along the outward normal n_a (Eq. 25):
//                 S_a = p_a + (dx/2) n_a · <grad p>_a,  <grad p>_a = L_a sum_b V_b (p_b - p_a) grad W_ab.
//                 It removes the O(dx) offset that p_a = 0 gives the whole pressure field (rho g dx/2 in
//                 still water), and as both P and S hold for a hydrostatic field, so does every blend
//                 (with "zero", particles with 0 < alpha < 1, e.g. at the corner of a free surface and
//                 a wall, get a pressure alpha times too small).
// Splash particles (and surface particles without a normal) get p = 0; an outlet's buffer particles
// get its pressure (sim/open_boundary.hpp).
//
// Wall row (a wall or structure particle with fluid neighbours): the pressure extrapolation of Adami, Hu & Adams
// (2012, J. Comput. Phys. 231:7057), solved together with the fluid rather than after it:
//   sum_f W_wf (p_w - p_f) = rho sum_f W_wf (g - a_w) · (r_w - r_f),
// divided by sum_f W_wf, so that its diagonal is 1 like the fluid rows' (each divided by its own
// diagonal). BoomerAMG needs the rows on one scale: with the wall rows left at W / rho it diverged on
// the elastic gate's first step, and on the plate it took 6.1 iterations instead of 4.8 (each step's
// last solve).
// The row imposes the pressure gradient rho (g - a_w) of the momentum equation at a wall (exactly for
// a hydrostatic field), so fluid is kept out of the wall by the projection.
//
// Structure rows with the structure's inertia (added_mass > 0; sim/coupling.hpp). A structure particle's
// acceleration over the fluid step answers its own pressure force: with the pairwise force per unit
// volume f_s(p) = -sum_f V_f (p_s + p_f) grad W_sf (structure/interaction.hpp), its step acceleration is
//   a_s = a~_s + beta f_s(p) / rho_s,
// a~_s the part the pressure does not give (elastic forces, gravity: handed in as wall_acceleration) and
// beta the chord acceleration's response to a force held over the step, 1/2 for a free particle
// (x^{n+1} - x^n = v dt + f dt^2 / (2 rho_s)). The row's right-hand side (g - a_s) · M then holds p, and
// that part moves to the left:
//   p_s - sum_f w_sf p_f - (beta / rho_s) sum_f V_f (M · grad W_sf) (p_s + p_f) = (g - a~_s) · M,
// with M the row's moment (wall_moment) and w_sf = W_sf / sum W. The structure's mass then stands in
// the pressure equation beside the fluid's, so a fluid much heavier than the structure (the added mass
// of Causin, Gerbeau & Nobile 2005) no longer needs the interface iterations to hold it: they correct
// only what beta does not describe (the structure's elastic response within the step). The extrapolation
// assumes fluid between the wall and its neighbours: a wall particle whose fluid neighbours are all
// free-surface or splash particles (alpha = 0: a thin jet running up the wall, a drop sliding along
// it) gets p = 0, or it would hold them up against gravity. So do a wall particle without fluid
// neighbours and the pinned particle of a scene without any Dirichlet row (closed or periodic boxes,
// where p is fixed only up to a constant).
#include "poisson/free_surface.hpp"

namespace isph {

// row_offset[a] = a + nbr_offset[a] for a in [0, n]: launched over n + 1 entries.
struct PpeRowOffsets {
  const Index* nbr_offset;
  int* row_offset;
  ISPH_HD void operator()(Index a) const { row_offset[a] = a + nbr_offset[a]; }
};

template <int D>
struct PpeRowFill {
  FluidView<D> v;
  const Mat<D>* L;
  const Real* alpha;
  const Real* div_u_star;
  Real density;
  Real dt;
  Vec<D> gravity;  // g; a wall row takes g - a_w with a_w from the view
  const SurfaceClass* cls;
  const Vec<D>* surface_normal;  // outward unit normal where alpha < 1 (zero if unknown)
  bool extrapolate_surface;      // the "extrapolated" surface condition instead of "zero"
  Index pinned;                  // particle with p = 0 imposed, or -1
  int* col;
  double* val;
  double* rhs;
  Vec<D>* wall_moment;  // wall rows: rho sum_f W_wf r_wf / sum_f W_wf, so that rhs = (g - a_w) · wall_moment
                        // and the row says p_w = sum_f (W_wf / sum W) p_f + rhs
  const Index* structure_index = nullptr;  // with structure_inverse_density: the structure's inertia in its rows
  const Real* structure_inverse_density = nullptr;  // 1 / rho_s, indexed as in TLSPH
  Real added_mass = 0;                              // beta (0: the rows take a_s as given)
  Real density_relaxation = 0;                      // gamma of the density term (see above)
  Real full_kernel_sum = 1;                         // FluidView::kernel_sum on a regular lattice

  ISPH_HD void operator()(Index a) const {
    const OperatorView<D>& op = v.op;
    const Index begin = op.nbr_offset[a], end = op.nbr_offset[a + 1];
    const Index row = a + begin;  // diagonal slot; neighbour k goes to row + 1 + (k - begin)
    col[row] = a;
    for (Index k = begin; k < end; ++k) {
      col[row + 1 + (k - begin)] = op.nbr[k];
      val[row + 1 + (k - begin)] = 0;
    }
    val[row] = 1;  // Dirichlet p = 0 unless a row below applies
    rhs[a] = 0;
    wall_moment[a] = Vec<D>::zero();
    if (a == pinned || cls[a] == SurfaceClass::splash) return;
    if (v.is_outlet(a)) {  // an outlet's buffer: p = its pressure (sim/open_boundary.hpp)
      rhs[a] = v.open_rows[v.open_zone[a]].pressure;
      return;
    }
    if (v.is_fluid(a))
      fluid_row(a, begin, end, row);
    else
      wall_row(a, begin, end, row);
  }

  ISPH_HD void fluid_row(Index a, Index begin, Index end, Index row) const {
    const OperatorView<D>& op = v.op;
    const Mat<D> l = L[a];
    const Real al = alpha[a];
    const bool extrapolate = extrapolate_surface && al < 1 && norm2(surface_normal[a]) > 0;
    if (al == 0 && !extrapolate) return;  // Dirichlet
    Real diagonal = 0;
    if (al > 0) {  // alpha P_a, P_a = the PPE row over its diagonal
      for (Index k = begin; k < end; ++k) {
        const Index b = op.nbr[k];
        const Vec<D> r_ab = op.r(a, b);
        const Real r2 = norm2(r_ab);
        const Real c = r2 > 0 ? -2 * op.volume[b] * dot(r_ab, l * op.gradient(a, b, r_ab)) / (density * r2) : 0;
        diagonal += c;
        val[row + 1 + (k - begin)] = -c;
      }
      if (al == 1) {  // linear exactness: - m1 · <grad p>_a, m1 = sum_b c_ab r_ab, in full rows only (see above)
        Vec<D> m1 = Vec<D>::zero();
        for (Index k = begin; k < end; ++k) m1 += (-val[row + 1 + (k - begin)]) * op.r(a, op.nbr[k]);
        for (Index k = begin; k < end; ++k) {
          const Index b = op.nbr[k];
          const Real t = op.volume[b] * dot(m1, l * op.gradient(a, b, op.r(a, b)));
          val[row + 1 + (k - begin)] -= t;
          diagonal += t;
        }
      }
      if (!(diagonal > 0)) {  // no usable Laplacian (degenerate neighbourhood): Dirichlet
        for (Index k = begin; k < end; ++k) val[row + 1 + (k - begin)] = 0;
        return;
      }
      for (Index k = begin; k < end; ++k) val[row + 1 + (k - begin)] *= al / diagonal;
      val[row] = al;
      rhs[a] = -al * div_u_star[a] / (dt * diagonal);
      if (bool beside_structure; al == 1 && density_relaxation > 0) {  // spread particles drawn together (above)
        const Real sigma = v.kernel_sum(a, beside_structure);
        if (!beside_structure) rhs[a] -= density_relaxation * (1 - sigma / full_kernel_sum) / (dt * dt * diagonal);
      }
    } else {
      val[row] = 0;
    }
    if (extrapolate) {                                     // (1 - alpha) S_a
      const Vec<D> ln = transpose(l) * surface_normal[a];  // n · (L g) = (L^T n) · g
      const Real w = (1 - al) * 0.5 * v.dx;
      val[row] += 1 - al;
      for (Index k = begin; k < end; ++k) {
        const Index b = op.nbr[k];
        const Real c = w * op.volume[b] * dot(ln, op.gradient(a, b, op.r(a, b)));
        val[row] -= c;
        val[row + 1 + (k - begin)] += c;
      }
    } else if (al < 1) {  // (1 - alpha) p_a
      val[row] += 1 - al;
    }
  }

  ISPH_HD void wall_row(Index a, Index begin, Index end, Index row) const {
    const OperatorView<D>& op = v.op;
    bool wet = false;  // a fluid neighbour below the free surface
    for (Index k = begin; k < end && !wet; ++k) wet = v.is_fluid(op.nbr[k]) && alpha[op.nbr[k]] > 0;
    if (!wet) return;  // p = 0
    Real weight_sum = 0;
    Vec<D> moment = Vec<D>::zero();
    for (Index k = begin; k < end; ++k) {
      const Index b = op.nbr[k];
      if (!v.is_fluid(b)) continue;
      const Vec<D> r_ab = op.r(a, b);
      const Real w = op.kernel(a, b).value(sqrt(norm2(r_ab)));
      weight_sum += w;
      moment += w * r_ab;
      val[row + 1 + (k - begin)] = -w;
    }
    if (!(weight_sum > 0)) return;  // no fluid neighbour: p = 0
    for (Index k = begin; k < end; ++k) val[row + 1 + (k - begin)] /= weight_sum;
    val[row] = 1;
    wall_moment[a] = (density / weight_sum) * moment;
    rhs[a] = dot(gravity - v.wall_acceleration[a], wall_moment[a]);
    if (added_mass > 0 && v.is_structure(a)) {  // the structure's inertia (see above)
      const Real c = added_mass * structure_inverse_density[structure_index[a]];
      for (Index k = begin; k < end; ++k) {
        const Index b = op.nbr[k];
        if (!v.is_fluid(b)) continue;
        const Real t = c * op.volume[b] * dot(wall_moment[a], op.gradient(a, b, op.r(a, b)));
        val[row] -= t;
        val[row + 1 + (k - begin)] -= t;
      }
    }
  }
};

// The assembled rows keep a slot per neighbour, many of them zero (wall-wall pairs, Dirichlet rows).
// The solvers get the matrix without them and with sorted columns, which they need anyway:
// The right-hand side of the wall rows of structure particles for a new structure acceleration
// (acceleration indexed as in TLSPH): rhs = (g - a_s) · wall_moment, as PpeRowFill::wall_row sets it,
// so that only b changes between interface iterations.
template <int D>
struct StructureRowRhs {
  const Index* structure_index;
  const Vec<D>* acceleration;
  Vec<D> gravity;
  const Vec<D>* wall_moment;
  double* rhs;
  ISPH_HD void operator()(Index k) const {
    if (const Index s = structure_index[k]; s >= 0) rhs[k] = dot(gravity - acceleration[s], wall_moment[k]);
  }
};

// CountRowEntries gives each row's length, CompactRow copies the entries (insertion sort by column).
struct CountRowEntries {
  const int* row_offset;
  const int* col;
  const double* val;
  int* count;  // launched over rows + 1: count[0] = 0, count[a + 1] = entries kept in row a
  ISPH_HD void operator()(Index i) const {
    if (i == 0) {
      count[0] = 0;
      return;
    }
    const Index a = i - 1;
    int n = 0;
    for (int k = row_offset[a]; k < row_offset[a + 1]; ++k) n += (val[k] != 0 || col[k] == a);
    count[i] = n;
  }
};

struct CompactRow {
  const int* row_offset;
  const int* col;
  const double* val;
  const int* out_offset;
  int* out_col;
  double* out_val;
  ISPH_HD void operator()(Index a) const {
    const int first = out_offset[a];
    int end = first;
    for (int k = row_offset[a]; k < row_offset[a + 1]; ++k) {
      if (val[k] == 0 && col[k] != a) continue;
      int slot = end++;
      while (slot > first && out_col[slot - 1] > col[k]) {
        out_col[slot] = out_col[slot - 1];
        out_val[slot] = out_val[slot - 1];
        --slot;
      }
      out_col[slot] = col[k];
      out_val[slot] = val[k];
    }
  }
};

}  // namespace isph
