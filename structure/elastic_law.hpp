#pragma once
// The elastic laws of TLSPH: from the deformation gradient F, the second Piola-Kirchhoff stress S and the
// stored energy per unit reference volume psi. Every law has the small-strain moduli lambda and mu of
// the case's youngs_modulus and poisson_ratio, so that all agree with linear elasticity at small strain.
//
//  St. Venant-Kirchhoff (seed 001 Eq. 41): with the Green strain E = (C - I)/2, C = F^T F,
//    psi = lambda/2 tr(E)^2 + mu E:E,   S = lambda tr(E) I + 2 mu E.
//  Compressible Neo-Hookean (Bonet & Wood 2008, Nonlinear Continuum Mechanics for Finite Element
//  Analysis, 2nd ed., Eqs. 6.27-6.28), J = det F:
//    psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,   S = mu (I - C^-1) + lambda ln J C^-1.
//  Compressible Mooney-Rivlin (Holzapfel 2000, Nonlinear Solid Mechanics, §6.4-6.5, Eqs. 6.91 and 6.146
//  with the volumetric energy kappa/2 (J - 1)^2), with the isochoric C' = J^(-2/3) C and its invariants
//  I1' = tr C', I2' = (I1'^2 - tr C'^2)/2:
//    psi = c10 (I1' - 3) + c01 (I2' - 3) + kappa/2 (J - 1)^2,
//    S = J^(-2/3) [S' - (S':C)/3 C^-1] + kappa J (J - 1) C^-1,   S' = 2 (c10 + c01 I1') I - 2 c01 C';
//    small strain: mu = 2 (c10 + c01) and kappa = lambda + 2 mu / 3.
// In 2D the hyperelastic laws are plane strain (F_33 = 1: C_33 = 1, and the in-plane block of S);
// St. Venant-Kirchhoff also has plane stress, through its lambda (scene.cpp).
#include <cmath>

#include "core/types.hpp"

namespace isph {

enum class ElasticLaw : int { saint_venant_kirchhoff = 0, neo_hookean = 1, mooney_rivlin = 2 };

// A structure's material. In 2D plane stress (St. Venant-Kirchhoff only), lambda is already the
// plane-stress value 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2).
struct ElasticMaterial {
  Real density;
  Real lambda;
  Real mu;
  Real youngs_modulus;
  ElasticLaw law = ElasticLaw::saint_venant_kirchhoff;
  Real c10 = 0, c01 = 0, kappa = 0;  // Mooney-Rivlin
};

// The linear elastic law C:E = lambda tr(E) I + 2 mu E (also applied to strain gradients: tlsph_functors.hpp).
template <int D>
ISPH_HD inline Mat<D> elastic_stress(const Mat<D>& E, const ElasticMaterial& m) {
  Mat<D> S = (2 * m.mu) * E;
  const Real trE = trace(E);
  for (int i = 0; i < D; ++i) S(i, i) += m.lambda * trE;
  return S;
}

template <int D>
ISPH_HD inline Mat<D> green_strain(const Mat<D>& F) {
  return 0.5 * (transpose(F) * F - Mat<D>::identity());
}

// St. Venant-Kirchhoff, from the Green strain.
template <int D>
ISPH_HD inline Mat<D> svk_stress(const Mat<D>& E, const ElasticMaterial& m, Real* psi = nullptr) {
  if (psi) {
    const Real trE = trace(E);
    *psi = 0.5 * m.lambda * trE * trE + m.mu * ddot(E, E);
  }
  return elastic_stress(E, m);
}

// The right Cauchy-Green tensor in 3D (plane strain in 2D: C_33 = 1) and the in-plane block of a 3D stress.
template <int D>
ISPH_HD inline Mat<3> cauchy_green_3d(const Mat<D>& F) {
  const Mat<D> C = transpose(F) * F;
  Mat<3> C3 = Mat<3>::identity();
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) C3(i, j) = C(i, j);
  return C3;
}
template <int D>
ISPH_HD inline Mat<D> leading_block(const Mat<3>& S3) {
  Mat<D> S;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) S(i, j) = S3(i, j);
  return S;
}

ISPH_HD inline Mat<3> neo_hookean_stress(const Mat<3>& C, const ElasticMaterial& m, Real* psi) {
  const Real J = sqrt(determinant(C));
  const Real lnJ = log(J);
  const Mat<3> Cinv = inverse(C);
  if (psi) *psi = 0.5 * m.mu * (trace(C) - 3) - m.mu * lnJ + 0.5 * m.lambda * lnJ * lnJ;
  return m.mu * (Mat<3>::identity() - Cinv) + (m.lambda * lnJ) * Cinv;
}

ISPH_HD inline Mat<3> mooney_rivlin_stress(const Mat<3>& C, const ElasticMaterial& m, Real* psi) {
  const Real J = sqrt(determinant(C));
  const Real cube_root = cbrt(J), scale = 1 / (cube_root * cube_root);  // J^(-2/3)
  const Mat<3> Ciso = scale * C;
  const Real I1 = trace(Ciso), I2 = 0.5 * (I1 * I1 - ddot(Ciso, transpose(Ciso)));
  const Mat<3> Cinv = inverse(C);
  if (psi) *psi = m.c10 * (I1 - 3) + m.c01 * (I2 - 3) + 0.5 * m.kappa * (J - 1) * (J - 1);
  const Mat<3> Sbar = (2 * (m.c10 + m.c01 * I1)) * Mat<3>::identity() - (2 * m.c01) * Ciso;
  return scale * (Sbar - (ddot(Sbar, C) / 3) * Cinv) + (m.kappa * J * (J - 1)) * Cinv;
}

// S and psi of F under the material's law (E: F's Green strain, which St. Venant-Kirchhoff takes).
template <int D>
ISPH_HD inline Mat<D> second_piola_stress(const Mat<D>& F, const Mat<D>& E, const ElasticMaterial& m,
                                          Real* psi = nullptr) {
  switch (m.law) {
    case ElasticLaw::neo_hookean:
      return leading_block<D>(neo_hookean_stress(cauchy_green_3d(F), m, psi));
    case ElasticLaw::mooney_rivlin:
      return leading_block<D>(mooney_rivlin_stress(cauchy_green_3d(F), m, psi));
    default:
      return svk_stress(E, m, psi);
  }
}

}  // namespace isph
