#pragma once
// Particle shifting (seed 001 §2.1, Eqs. 20-26, 31-32), applied after the position update.
//
//  xu   Xu, Stansby & Laurence (2009), generalised by Lind et al. (2012) with the cap |dr| <= 0.2 h:
//         dr_a = C zeta R_a,  R_a = sum_b (rbar_a / r_ab)^2 n_ab,  rbar_a = (1/N_a) sum_b r_ab,   (21-23)
//       zeta = |u|_max dt, n_ab = r_ab / |r_ab|, b over fluid and wall neighbours.
//  ops  xu, and at free-surface and near-surface particles only the tangential part (Khayyer et al.
//       2017):  dr_a <- (I - n_a ⊗ n_a) dr_a,                                                   (24)
//       n_a = -grad Psi_a / |grad Psi_a|,  grad Psi_a = L_a sum_b V_b grad W_ab                  (25-26)
//       (wall particles weighted by their wetness, as in the free-surface detection)
//       (near-surface particles take the normal of their nearest surface neighbour).
//  Splash particles and walls are not shifted. After the shift, velocity and pressure of the
//  particles with a full support (not surface particles, see ApplyShift) are carried to the new
//  position by first-order Taylor series (Eqs. 20, 31-32):
//       u_a <- u_a + G_a dr_a,   p_a <- p_a + <grad p>_a · dr_a,
//  with G_a from the free-slip extension of the velocity into walls (FluidView::velocity_mirrored):
//  the no-slip jump across an unresolved boundary layer is not a field a Taylor series may extend.
#include "sim/fluid_view.hpp"

namespace isph {

enum class ShiftingType : int { none = 0, xu = 1, ops = 2 };

// Pass 1: outward unit normal, Eqs. 25-26, of surface particles and of the fluid particles whose
// Skillen coefficient is below 1 (the PPE's surface condition needs it there); zero elsewhere.
template <int D>
struct SurfaceNormal {
  FluidView<D> v;
  const Mat<D>* L;
  const SurfaceClass* cls;
  const Real* alpha;
  Vec<D>* surface_normal;
  ISPH_HD void operator()(Index a) const {
    surface_normal[a] = Vec<D>::zero();
    if (!v.is_fluid(a) || (cls[a] != SurfaceClass::surface && !(alpha[a] < 1))) return;
    const OperatorView<D>& op = v.op;
    Vec<D> s = Vec<D>::zero();
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      s += (v.surface_weight(a, b) * op.volume[b]) * op.kernel.gradient(op.r(a, b));
    }
    const Vec<D> grad_psi = L[a] * s;
    const Real len = sqrt(norm2(grad_psi));
    if (len > 0) surface_normal[a] = (-1.0 / len) * grad_psi;
  }
};

// Pass 2: the shifting displacement of Eqs. 21-24, capped at max_shift.
template <int D>
struct ShiftDisplacement {
  FluidView<D> v;
  const SurfaceClass* cls;
  const Vec<D>* surface_normal;  // from SurfaceNormal (ops only)
  ShiftingType type;
  Real coefficient;              // C
  Real zeta;                     // |u|_max dt
  Real max_shift;                // max_fraction h
  Vec<D>* shift;
  ISPH_HD void operator()(Index a) const {
    shift[a] = Vec<D>::zero();
    if (!v.is_fluid(a) || cls[a] == SurfaceClass::splash || type == ShiftingType::none) return;
    const OperatorView<D>& op = v.op;
    const Index begin = op.nbr_offset[a], end = op.nbr_offset[a + 1];
    Real rbar = 0;
    int count = 0;
    Real nearest_surface2 = 1e300;
    Vec<D> normal = surface_normal[a];
    for (Index k = begin; k < end; ++k) {
      const Index b = op.nbr[k];
      const Real r2 = norm2(op.r(a, b));
      if (!(r2 > 0)) continue;
      rbar += sqrt(r2);
      ++count;
      if (cls[a] == SurfaceClass::near_surface && cls[b] == SurfaceClass::surface && r2 < nearest_surface2) {
        nearest_surface2 = r2;
        normal = surface_normal[b];
      }
    }
    if (count == 0) return;
    rbar /= count;
    Vec<D> R = Vec<D>::zero();
    for (Index k = begin; k < end; ++k) {
      const Index b = op.nbr[k];
      const Vec<D> r_ab = op.r(a, b);
      const Real r2 = norm2(r_ab);
      if (!(r2 > 0)) continue;
      R += (rbar * rbar / (r2 * sqrt(r2))) * r_ab;
    }
    Vec<D> dr = (coefficient * zeta) * R;
    if (type == ShiftingType::ops && (cls[a] == SurfaceClass::surface || cls[a] == SurfaceClass::near_surface))
      dr = dr - dot(dr, normal) * normal;
    const Real len = sqrt(norm2(dr));
    if (len > max_shift) dr = (max_shift / len) * dr;
    shift[a] = dr;
  }
};

// Pass 3: move by the shift and correct u and p by Taylor series (Eqs. 20, 31-32). Free-surface
// particles are moved but not corrected: their gradients come from half a kernel support (and from
// thin sheets and jets at that), and a first-order Taylor step with such a gradient can throw a
// particle off as spray; OPS moves them only along the surface, where u and p vary least.
template <int D>
struct ApplyShift {
  const SurfaceClass* cls;
  const Vec<D>* shift;
  const Mat<D>* grad_u;
  const Vec<D>* grad_p;
  bool taylor_correction;
  Periodicity<D> period;
  Vec<D>* x;
  Vec<D>* u;
  Real* p;
  ISPH_HD void operator()(Index a) const {
    const Vec<D> dr = shift[a];
    if (norm2(dr) == 0) return;
    x[a] = period.wrap(x[a] + dr);
    if (!taylor_correction || cls[a] == SurfaceClass::surface) return;
    u[a] += grad_u[a] * dr;
    p[a] += dot(grad_p[a], dr);
  }
};

}  // namespace isph
