// GPU measurements beside the cuda solver backend (poisson/cuda_solver.cu): the device's CSR products
// and its copy bandwidth, for the SpMV benchmark and the device tests. Without a CUDA build or a
// visible device each call throws std::runtime_error saying which.
#pragma once

#include <cmath>
#include <vector>

#include "poisson/linear_solver.hpp"

namespace isph {

// The device's CSR products: cuSPARSE's CSR_ALG2, bit-wise reproducible (the solver's), or CSR_ALG1, the
// default; or the project's vector CSR kernel (a few threads per row, reproducible too).
enum class SpmvAlgorithm { reproducible, default_csr, vector_csr };

// Threads per row of the vector CSR kernel for a matrix with `entries_per_row` nonzeros per row on
// average: the power of two nearest a third of it (about three entries per thread), 2 to 32.
inline int vector_csr_lanes(double entries_per_row) {
  int lanes = 2;
  while (lanes < 32 && 3.0 * lanes * std::sqrt(2.0) < entries_per_row) lanes *= 2;
  return lanes;
}

struct SpmvMeasurement {
  std::vector<double> y;           // A x from the device
  double seconds_per_product = 0;  // mean of `repeats` products, timed with CUDA events
  double bytes_per_product = 0;    // least traffic: 12 bytes per nonzero, 4 per row offset, x read and y written once
  double copy_bandwidth = 0;       // bytes/s of device-to-device copies of 512 MiB (read + write counted)
};

// lanes: the vector CSR kernel's threads per row (a power of two, 2 to 32), 0 for vector_csr_lanes.
SpmvMeasurement measure_cuda_spmv(const CsrMatrix& A, const std::vector<double>& x, int repeats,
                                  SpmvAlgorithm algorithm = SpmvAlgorithm::reproducible, int lanes = 0);

}  // namespace isph
