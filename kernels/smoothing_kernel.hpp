#pragma once
// SPH smoothing kernels with compact support 2h, for 2D and 3D.
//  Cubic B-spline (Monaghan & Lattanzio 1985; the seed paper's choice), q = r/h:
//    W = s [1 - 1.5 q^2 + 0.75 q^3]   for 0 <= q < 1
//    W = s [0.25 (2 - q)^3]           for 1 <= q < 2,   s = 10/(7 pi h^2) in 2D, 1/(pi h^3) in 3D.
//  Wendland C2 (Wendland 1995), q = r/h:
//    W = s (1 - q/2)^4 (2q + 1)       for 0 <= q < 2,   s = 7/(4 pi h^2) in 2D, 21/(16 pi h^3) in 3D.
#include <cmath>
#include <span>

#include "core/enum_names.hpp"
#include "core/types.hpp"

namespace isph {

enum class KernelType : int { cubic_spline = 0, wendland_c2 = 1 };
constexpr EnumName<KernelType> kKernelTypeNames[] = {{KernelType::cubic_spline, "cubic_spline"},
                                                     {KernelType::wendland_c2, "wendland_c2"}};
constexpr std::span<const EnumName<KernelType>> enum_names(KernelType) { return kKernelTypeNames; }

template <int D>
struct SmoothingKernel {
  KernelType type = KernelType::cubic_spline;
  Real h = 1;
  Real norm = 0;  // s above, including the h^-D factor

  static SmoothingKernel make(KernelType type, Real h) {
    constexpr Real pi = 3.14159265358979323846;
    SmoothingKernel k;
    k.type = type;
    k.h = h;
    const Real hd = (D == 2) ? h * h : h * h * h;
    if (type == KernelType::cubic_spline)
      k.norm = ((D == 2) ? 10.0 / (7.0 * pi) : 1.0 / pi) / hd;
    else
      k.norm = ((D == 2) ? 7.0 / (4.0 * pi) : 21.0 / (16.0 * pi)) / hd;
    return k;
  }

  ISPH_HD Real support() const { return 2 * h; }

  ISPH_HD Real value(Real r) const {
    const Real q = r / h;
    if (q >= 2) return 0;
    if (type == KernelType::cubic_spline) {
      if (q < 1) return norm * (1 - 1.5 * q * q + 0.75 * q * q * q);
      const Real t = 2 - q;
      return norm * 0.25 * t * t * t;
    }
    const Real t = 1 - 0.5 * q;
    return norm * t * t * t * t * (2 * q + 1);
  }

  // dW/dr
  ISPH_HD Real derivative(Real r) const {
    const Real q = r / h;
    if (q >= 2) return 0;
    if (type == KernelType::cubic_spline) {
      if (q < 1) return norm / h * (-3 * q + 2.25 * q * q);
      const Real t = 2 - q;
      return norm / h * (-0.75 * t * t);
    }
    const Real t = 1 - 0.5 * q;
    return norm / h * (-5 * q * t * t * t);
  }

  // Gradient of W(|r_a - r_b|) with respect to r_a, given r_ab = r_a - r_b.
  ISPH_HD Vec<D> gradient(const Vec<D>& r_ab) const {
    const Real r = sqrt(norm2(r_ab));
    if (r <= 0) return Vec<D>::zero();
    return (derivative(r) / r) * r_ab;
  }
};

// Sum of W(|r|) over the points r of a full lattice of spacing dx within the kernel's support of the
// origin, the origin included: the kernel sum a particle in a regular interior sees (FluidView::kernel_sum).
template <int D>
Real lattice_kernel_sum(const SmoothingKernel<D>& kernel, Real dx) {
  const int reach = static_cast<int>(std::ceil(kernel.support() / dx));
  int index[D];
  for (int d = 0; d < D; ++d) index[d] = -reach;
  Real sum = 0;
  while (true) {
    Real r2 = 0;
    for (int d = 0; d < D; ++d) r2 += (index[d] * dx) * (index[d] * dx);
    sum += kernel.value(std::sqrt(r2));
    int d = 0;
    while (d < D && ++index[d] > reach) index[d++] = -reach;
    if (d == D) break;
  }
  return sum;
}

}  // namespace isph
