#pragma once
// The structure solver's options a case file chooses (docs/CASES.md, [structure]).
#include <span>

#include "core/enum_names.hpp"

namespace isph {

enum class StructureIntegrator { rk4, verlet };
constexpr EnumName<StructureIntegrator> kStructureIntegratorNames[] = {{StructureIntegrator::rk4, "rk4"},
                                                                       {StructureIntegrator::verlet, "verlet"}};
constexpr std::span<const EnumName<StructureIntegrator>> enum_names(StructureIntegrator) {
  return kStructureIntegratorNames;
}

// The pair gradients c_ab of the deformation gradient: uncorrected (g_ab), kernel-corrected (L_a g_ab,
// exact for linear fields; Eq. 35-36) or exact for quadratic fields (QuadraticCorrection).
// A case chooses linear or quadratic; uncorrected follows from kernel.correction = false.
enum class StructureGradient { uncorrected, linear, quadratic };
constexpr EnumName<StructureGradient> kStructureGradientNames[] = {{StructureGradient::linear, "linear"},
                                                                   {StructureGradient::quadratic, "quadratic"}};
constexpr std::span<const EnumName<StructureGradient>> enum_names(StructureGradient) { return kStructureGradientNames; }

// The quadrature of the strain energy: at the particle (the midpoint rule of SPH), or over its cell
// with the strain's linear variation across it (TlsphStrainGradient).
enum class StructureQuadrature { point, cell };
constexpr EnumName<StructureQuadrature> kStructureQuadratureNames[] = {{StructureQuadrature::point, "point"},
                                                                       {StructureQuadrature::cell, "cell"}};
constexpr std::span<const EnumName<StructureQuadrature>> enum_names(StructureQuadrature) {
  return kStructureQuadratureNames;
}

}  // namespace isph
