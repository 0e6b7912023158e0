#pragma once
// Particle shifting (seed 001 §2.1, Eqs. 20-26, 31-32), applied after the position update.
//
//  xu   Xu, Stansby & Laurence (2009), generalised by Lind et al. (2012) with the cap |dr| <= 0.2 h:
//         dr_a = C zeta R_a,  R_a = sum_b (rbar_a / r_ab)^2 n_ab,  rbar_a = (1/N_a) sum_b r_ab,   (21-23)
//       zeta = |u|_max dt, n_ab = r_ab / |r_ab|, b over fluid and wall neighbours. Each neighbour counts
//       with its volume relative to a's, w_b = V_b / V_a, in R_a, rbar_a and N_a = sum_b w_b: the sums then
//       approximate integrals over the neighbourhood whatever its resolution, so that the finer (and
//       closer, denser) particles of a structure finer than the water do not push the fluid off it
//       (w_b = 1 on one resolution: Eqs. 21-23 as printed).
//  ops  xu, and at free-surface and near-surface particles only the tangential part (Khayyer et al.
//       2017):  dr_a <- (I - n_a ⊗ n_a) dr_a,                                                   (24)
//       n_a = -grad Psi_a / |grad Psi_a|,  grad Psi_a = L_a sum_b V_b grad W_ab                  (25-26)
//       (wall particles weighted by their wetness, as in the free-surface detection)
//       (near-surface particles take the normal of their nearest surface neighbour).
//  fsi  the intermediate layer beside a structure (fluid particles with a structure particle within
//       the kernel support; n_s the normal of the nearest structure particle). Eq. 27 relocates a
//       displacement x along n_s by  x -> x + |d| [exp(-x / |d|) - 1] = x phi(x / |d|),
//       phi(y) = 1 - (1 - e^-y) / y, with |d| from Eq. 29: zeta / |d| = q = 2 C |R_n|, R_n = R_a · n_s
//       (Eq. 30 then holds for every C in [0.01, 0.1]). What x is, the seed says two ways:
//       literal  x = Xu's normal shift dr_n (Eq. 27's text): dr_n <- dr_n phi(|dr_n| / |d|), which keeps
//                about C^2 R_n^2 of it: the layer all but stops the normal shift;
//       derived  x = zeta, the convection distance (Eq. 28, from which Eq. 29 follows):
//                dr_n <- sign(dr_n) zeta phi(q) = dr_n (2 / q) phi(q), Xu's shift to second order
//                (q small) and never more than zeta where the particles crowd against the structure.
//       relative x = |u_a - u_s| dt, the particle's own convection distance past the nearest structure
//                particle s (not the seed's): dr_n <- sign(dr_n) x phi(x / |d|), about Xu's shift
//                times (x / zeta)^2: Xu's where the water flows past the structure at the step's
//                largest speed, none where it moves with it (docs/VALIDATION.md section 26).
//       (The sign of d is not printed in the seed; taken along dr_n, neither law pushes particles
//       into the structure.)
//  Splash particles and walls are not shifted. After the shift, velocity and pressure of the
//  particles with a full support (not surface particles, see TaylorCorrection) are carried to the new
//  position by first-order Taylor series (Eqs. 20, 31-32), limited to the neighbours' range:
//       u_a <- u_a + G_a dr_a,   p_a <- p_a + <grad p>_a · dr_a,
//  with G_a from the free-slip extension of the velocity into walls (FluidView::velocity_mirrored):
//  the no-slip jump across an unresolved boundary layer is not a field a Taylor series may extend.
#include "kernels/fluid_view.hpp"
#include "shifting/shifting_type.hpp"

namespace isph {

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
      s += (v.surface_weight(a, b) * op.volume[b]) * op.gradient(a, b, op.r(a, b));
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
  const Real* volume;  // the particles' own volumes (v's may leave out dry walls)
  const SurfaceClass* cls;
  const Vec<D>* surface_normal;  // from SurfaceNormal (ops only)
  ShiftingType type;
  Real coefficient;        // C
  Real zeta;               // |u|_max dt
  Real max_shift;          // max_fraction h
  bool fsi_layer;          // Eqs. 27-30 beside structures
  FsiLayerLaw fsi_law;     // what Eq. 27 relocates
  const Vec<D>* velocity;  // the fluid's (relative law)
  Real dt;                 // the step (relative law)
  Vec<D>* shift;
  ISPH_HD void operator()(Index a) const {
    shift[a] = Vec<D>::zero();
    if (!v.is_fluid(a) || cls[a] == SurfaceClass::splash || type == ShiftingType::none) return;
    const OperatorView<D>& op = v.op;
    const Index begin = op.nbr_offset[a], end = op.nbr_offset[a + 1];
    Real rbar = 0, count = 0;
    Real nearest_surface2 = 1e300, nearest_structure2 = 1e300;
    Vec<D> normal = surface_normal[a];
    Index nearest_structure = -1;
    for (Index k = begin; k < end; ++k) {
      const Index b = op.nbr[k];
      const Real r2 = norm2(op.r(a, b));
      if (!(r2 > 0)) continue;
      const Real w = volume[b] / volume[a];
      rbar += w * sqrt(r2);
      count += w;
      if (cls[a] == SurfaceClass::near_surface && cls[b] == SurfaceClass::surface && r2 < nearest_surface2) {
        nearest_surface2 = r2;
        normal = surface_normal[b];
      }
      if (fsi_layer && v.is_structure(b) && r2 < nearest_structure2) {
        nearest_structure2 = r2;
        nearest_structure = b;
      }
    }
    if (!(count > 0)) return;
    rbar /= count;
    Vec<D> R = Vec<D>::zero();
    for (Index k = begin; k < end; ++k) {
      const Index b = op.nbr[k];
      const Vec<D> r_ab = op.r(a, b);
      const Real r2 = norm2(r_ab);
      if (!(r2 > 0)) continue;
      R += (volume[b] / volume[a]) * ((rbar * rbar / (r2 * sqrt(r2))) * r_ab);
    }
    Vec<D> dr = (coefficient * zeta) * R;
    if (type == ShiftingType::ops && (cls[a] == SurfaceClass::surface || cls[a] == SurfaceClass::near_surface))
      dr = dr - dot(dr, normal) * normal;
    if (nearest_structure >= 0 && norm2(v.wall_normal[nearest_structure]) > 0) {
      const Vec<D> n_s = v.wall_normal[nearest_structure];
      const Real dr_n = dot(dr, n_s);
      const Real relative_distance =
          fsi_law == FsiLayerLaw::relative ? sqrt(norm2(velocity[a] - v.wall_velocity[nearest_structure])) * dt : 0;
      dr = dr + ((fsi_layer_factor(dr_n, dot(R, n_s), relative_distance) - 1) * dr_n) * n_s;
    }
    const Real len = sqrt(norm2(dr));
    if (len > max_shift) dr = (max_shift / len) * dr;
    shift[a] = dr;
  }

  // Eq. 27 as a ratio, phi(y) = 1 - (1 - e^-y) / y (its series below 1e-4, where the difference cancels).
  ISPH_HD static Real relocation_ratio(Real y) { return y < 1e-4 ? y / 2 - y * y / 6 : 1 - (1 - exp(-y)) / y; }

  // Eqs. 27-29: the factor the FSI layer puts on the normal shift dr_n, given R_n (and, for the
  // relative law, the particle's convection distance past the structure).
  ISPH_HD Real fsi_layer_factor(Real dr_n, Real R_n, Real relative_distance = 0) const {
    if (R_n == 0 || !(zeta > 0)) return 1;
    const Real q = 2 * coefficient * fabs(R_n);  // zeta / |d|, Eq. 29
    if (fsi_law == FsiLayerLaw::literal) return relocation_ratio(fabs(dr_n) * q / zeta);
    if (fsi_law == FsiLayerLaw::derived) return 2 * relocation_ratio(q) / q;
    if (dr_n == 0) return 1;
    return relative_distance * relocation_ratio(relative_distance * q / zeta) / fabs(dr_n);
  }
};

// Pass 3: the velocity and pressure each particle will carry to its shifted position, by first-order
// Taylor series (Eqs. 20, 31-32), written to u_out and p_out for every particle (unchanged where there
// is no correction). Free-surface particles are not corrected: their gradients come from half a
// kernel support (and from thin sheets and jets at that); OPS moves them only along the surface,
// where u and p vary least.
// The corrected value is an interpolation among the neighbours, so it is limited, component by
// component, to the range spanned by the particle and its fluid neighbours (the limiter of Barth &
// Jespersen, 1989, AIAA 89-0366, in its simplest form): where two streams collide the velocity
// gradient is steep and poorly resolved, and an unlimited first-order step overshoots and feeds
// energy into the flow (measured: the dam break gains 300 % at the plunging-wave impact).
template <int D>
struct TaylorCorrection {
  FluidView<D> v;
  const SurfaceClass* cls;
  const Vec<D>* shift;
  const Mat<D>* grad_u;
  const Vec<D>* grad_p;
  const Vec<D>* u;
  const Real* p;
  Vec<D>* u_out;
  Real* p_out;
  ISPH_HD void operator()(Index a) const {
    u_out[a] = u[a];
    p_out[a] = p[a];
    const Vec<D> dr = shift[a];
    if (norm2(dr) == 0 || cls[a] == SurfaceClass::surface) return;
    Vec<D> u_lo = u[a], u_hi = u[a];
    Real p_lo = p[a], p_hi = p[a];
    const OperatorView<D>& op = v.op;
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      if (!v.is_fluid(b)) continue;
      for (int i = 0; i < D; ++i) {
        u_lo[i] = fmin(u_lo[i], u[b][i]);
        u_hi[i] = fmax(u_hi[i], u[b][i]);
      }
      p_lo = fmin(p_lo, p[b]);
      p_hi = fmax(p_hi, p[b]);
    }
    const Vec<D> ua = u[a] + grad_u[a] * dr;
    for (int i = 0; i < D; ++i) u_out[a][i] = fmin(fmax(ua[i], u_lo[i]), u_hi[i]);
    p_out[a] = fmin(fmax(p[a] + dot(grad_p[a], dr), p_lo), p_hi);
  }
};

// Pass 4: move by the shift.
template <int D>
struct ApplyShift {
  const Vec<D>* shift;
  Periodicity<D> period;
  Vec<D>* x;
  ISPH_HD void operator()(Index a) const { x[a] = period.wrap(x[a] + shift[a]); }
};

}  // namespace isph
