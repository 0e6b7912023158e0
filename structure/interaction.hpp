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
#include "kernels/operators.hpp"
#include "sim/fluid_view.hpp"

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
        if (v.is_fluid(b)) s += (op.volume[b] * (p[a] + p[b])) * op.kernel.gradient(op.r(a, b));
      }
      force_density[a] = -1.0 * s;
      return;
    }
    GradientCorrection<D>{v.op, L}(a);
    CorrectedGradient<D>{v.op, L, p, grad_p}(a);
    force_density[a] = -1.0 * grad_p[a];
  }
};

// Fluid particles beside a structure: whether the particle lies inside the structure, and its distance
// to the nearest structure particle (or a large value). Inside means that the structure's kernel sum
// (its colour function) at the particle, c_a = sum_s V_s W(x_a - x_s), exceeds 1/2, its value on a flat
// face of the body: the particle has crossed the structure's surface, which lies dx/2 beyond the outer
// particles. The test needs no surface normals. A test by the faces of the nearby surface particles
// (behind every face within 1.5 dx) failed at convex corners: with only the corner particle in reach,
// water running out a full dx below the elastic gate's end was behind the plane of that particle's side
// face and was counted inside (tests/unit/test_structure_contact.cpp). Near a convex corner, where c
// is 1/4 on the surface, a particle is counted once it is about dx/2 in.
template <int D>
struct StructureContact {
  FluidView<D> v;
  unsigned char* inside;
  Real* distance;
  ISPH_HD void operator()(Index a) const {
    inside[a] = 0;
    distance[a] = 1e300;
    if (!v.is_fluid(a)) return;
    Real colour = 0;
    for (Index k = v.op.nbr_offset[a]; k < v.op.nbr_offset[a + 1]; ++k) {
      const Index s = v.op.nbr[k];
      if (!v.is_structure(s)) continue;
      const Real r = sqrt(norm2(v.op.r(a, s)));
      distance[a] = fmin(distance[a], r);
      colour += v.op.volume[s] * v.op.kernel.value(r);
    }
    inside[a] = colour > 0.5;
  }
};

}  // namespace isph
