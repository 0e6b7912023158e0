#pragma once
// Periodic axes of the domain. Pair vectors use the minimum image, r_ab = x_a - x_b wrapped into
// [-L/2, L/2) on each periodic axis, and positions are wrapped into [lo, lo + L). With no periodic
// axis both are the identity, so every operator can take a Periodicity unconditionally.
#include "core/types.hpp"

namespace isph {

template <int D>
struct Periodicity {
  bool axis[D] = {};
  Real lo[D] = {};
  Real length[D] = {};

  ISPH_HD bool any() const {
    for (int d = 0; d < D; ++d)
      if (axis[d]) return true;
    return false;
  }

  // Minimum-image difference x_a - x_b.
  ISPH_HD Vec<D> delta(const Vec<D>& xa, const Vec<D>& xb) const {
    Vec<D> r = xa - xb;
    for (int d = 0; d < D; ++d)
      if (axis[d]) r[d] -= length[d] * floor(r[d] / length[d] + 0.5);
    return r;
  }

  // The image of x inside [lo, lo + L) on every periodic axis.
  ISPH_HD Vec<D> wrap(Vec<D> x) const {
    for (int d = 0; d < D; ++d)
      if (axis[d]) {
        x[d] -= length[d] * floor((x[d] - lo[d]) / length[d]);
        if (x[d] >= lo[d] + length[d]) x[d] = lo[d];  // round-off at the upper end
      }
    return x;
  }
};

}  // namespace isph
