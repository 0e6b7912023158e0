#pragma once
// Floating-point sums that do not depend on the thread count or the device (parallel_reduce offers only
// exact combinations): value(i) summed over fixed blocks of 256 by a particle loop, and the block sums
// added in order on the host. On the device only the block sums come back.
#include "core/device_memory.hpp"

namespace isph {

template <class F>
struct BlockSum {
  F value;  // Index -> double
  Index n, block;
  double* partial;
  ISPH_HD void operator()(Index k) const {
    double s = 0;
    for (Index i = k * block; i < n && i < (k + 1) * block; ++i) s += value(i);
    partial[k] = s;
  }
};

// The sum of value(i) over [0, n); partial is the block sums' scratch (in the memory of exec's device).
template <class F>
double ordered_sum(const Exec& exec, Index n, const F& value, StateVector<double>& partial) {
  constexpr Index block = 256;
  const Index blocks = (n + block - 1) / block;
  partial.resize(blocks);
  parallel_for(exec, blocks, BlockSum<F>{value, n, block, partial.data()});
  double s = 0;
  for (Index k = 0; k < blocks; ++k) s += partial[k];
  return s;
}

}  // namespace isph
