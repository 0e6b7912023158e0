#pragma once
// Floating-point sums that do not depend on the thread count or the device (parallel_reduce offers only
// exact combinations): value(i) summed over fixed blocks of 256 by a particle loop, and the block sums
// added in order by AddBlockSums, on the host (ordered_sum: only the block sums come back from the
// device) or queued on the device (ordered_sum_into: nothing comes back until the caller reads it).
// Both add in the same order, so they give the same bits.
#include "core/device_memory.hpp"

namespace isph {

inline constexpr Index kSumBlock = 256;

template <class F>
struct BlockSum {
  F value;  // Index -> double
  Index n;
  double* partial;
  ISPH_HD void operator()(Index k) const {
    double s = 0;
    for (Index i = k * kSumBlock; i < n && i < (k + 1) * kSumBlock; ++i) s += value(i);
    partial[k] = s;
  }
};

// *total = partial[0] + partial[1] + ... in that order (one thread).
struct AddBlockSums {
  const double* partial;
  Index blocks;
  double* total;
  ISPH_HD void operator()(Index) const {
    double s = 0;
    for (Index k = 0; k < blocks; ++k) s += partial[k];
    *total = s;
  }
};

// Launches the block sums of value over [0, n) into partial (the scratch, in the memory of exec's
// device); returns their number.
template <class F>
Index launch_block_sums(const Exec& exec, Index n, const F& value, StateVector<double>& partial) {
  const Index blocks = (n + kSumBlock - 1) / kSumBlock;
  resize_for_overwrite(partial, blocks);
  parallel_for(exec, blocks, BlockSum<F>{value, n, partial.data()});
  return blocks;
}

// The sum of value(i) over [0, n); exec must wait for its launches.
template <class F>
double ordered_sum(const Exec& exec, Index n, const F& value, StateVector<double>& partial) {
  const Index blocks = launch_block_sums(exec, n, value, partial);
  double total = 0;
  AddBlockSums{partial.data(), blocks, &total}(0);
  return total;
}

// Queues the same sum into *total (memory of exec's device), for a caller that reads it later; partial
// keeps its size (and address) from call to call while n does not change.
template <class F>
void ordered_sum_into(const Exec& exec, Index n, const F& value, StateVector<double>& partial, double* total) {
  const Index blocks = launch_block_sums(exec, n, value, partial);
  parallel_for(exec, 1, AddBlockSums{partial.data(), blocks, total});
}

}  // namespace isph
