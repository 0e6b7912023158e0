#pragma once
// Free-surface detection and Skillen's coefficient (seed 001 §2.1, Eqs. 16-17, Fig. 2).
//
// The divergence of position, <div r>_a = -sum_b w_ab V_b r_ab · grad_a W_ab over fluid and wall
// neighbours, is D inside the fluid and drops towards D/2 at a free surface; wall particles count with
// their wetness w_ab (FluidView::wall_wetness), so that a dry wall above the water does not hide the
// free surface where it meets the wall. With the threshold chi
// (1.4 in 2D) and the full-support value chi_full (1.6 in 2D):
//   surface      div r <= chi with at least one fluid neighbour,
//   splash       div r <= chi with no fluid neighbour (isolated drops),
//   near_surface div r >  chi and a surface particle closer than h,
//   interior     otherwise.
// Skillen et al. (2013) coefficient, Eq. 17 (with the pi the seed's copy lacks):
//   alpha = 0 (div r <= chi),  0.5 [1 - cos(pi (div r - chi)/(chi_full - chi))] (between),  1 (above).
// alpha = 0 makes the particle a Dirichlet p = 0 row of the PPE.
#include "kernels/fluid_view.hpp"

namespace isph {

struct SurfaceThresholds {
  Real chi = 1.4;       // div r at or below: surface
  Real chi_full = 1.6;  // div r at or above: alpha = 1
};

ISPH_HD inline Real skillen_coefficient(Real div_r, const SurfaceThresholds& t) {
  constexpr Real pi = 3.14159265358979323846;
  if (div_r <= t.chi) return 0;
  if (div_r >= t.chi_full) return 1;
  return 0.5 * (1 - cos(pi * (div_r - t.chi) / (t.chi_full - t.chi)));
}

// Pass 1: div r, the surface/splash/interior class and alpha of every fluid particle. Walls get
// class interior, alpha = 1 and div r = 0.
template <int D>
struct SurfaceDetection {
  FluidView<D> v;
  SurfaceThresholds thresholds;
  bool detect;  // false: no free surface in the scene (every particle interior)
  Real* div_r;
  SurfaceClass* cls;
  Real* alpha;
  ISPH_HD void operator()(Index a) const {
    cls[a] = SurfaceClass::interior;
    alpha[a] = 1;
    div_r[a] = 0;
    if (!v.is_fluid(a)) return;  // a wall's PPE row is the wall condition, not Eq. 16
    const OperatorView<D>& op = v.op;
    Real s = 0;
    int fluid_neighbours = 0;
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      const Vec<D> r_ab = op.r(a, b);
      s -= v.surface_weight(a, b) * op.volume[b] * dot(r_ab, op.gradient(a, b, r_ab));
      fluid_neighbours += v.is_fluid(b) ? 1 : 0;
    }
    div_r[a] = s;
    if (!detect) return;
    alpha[a] = skillen_coefficient(s, thresholds);
    if (s <= thresholds.chi) cls[a] = fluid_neighbours > 0 ? SurfaceClass::surface : SurfaceClass::splash;
  }
};

// Pass 2: fluid particles above the threshold with a surface particle closer than h become
// near_surface; the other classes are copied.
template <int D>
struct NearSurfaceDetection {
  FluidView<D> v;
  const SurfaceClass* detected;  // pass 1 classes
  SurfaceClass* cls;
  ISPH_HD void operator()(Index a) const {
    cls[a] = detected[a];
    if (!v.is_fluid(a) || detected[a] != SurfaceClass::interior) return;
    const OperatorView<D>& op = v.op;
    const Real h2 = op.own_kernel(a).h * op.own_kernel(a).h;
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      if (detected[b] == SurfaceClass::surface && norm2(op.r(a, b)) < h2) {
        cls[a] = SurfaceClass::near_surface;
        return;
      }
    }
  }
};

// Pass 3: the volumes the pressure stages see. A wall particle whose fluid neighbours are all
// free-surface or splash particles (alpha = 0) is dry: it stands beside a jet, a drop or above the
// water line, where there is air, not fluid, on the other side of the wall. It gets p = 0 in the PPE
// (PpeRowFill) and volume 0 here, so that the PPE, the pressure gradient and shifting do not see it
// (every corrected operator weights neighbours by volume).
template <int D>
struct PressureVolume {
  FluidView<D> v;
  const Real* alpha;
  Real* volume;  // out
  ISPH_HD void operator()(Index a) const {
    const OperatorView<D>& op = v.op;
    bool wet = v.is_fluid(a);
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1] && !wet; ++k)
      wet = v.is_fluid(op.nbr[k]) && alpha[op.nbr[k]] > 0;
    volume[a] = wet ? op.volume[a] : 0;
  }
};

}  // namespace isph
