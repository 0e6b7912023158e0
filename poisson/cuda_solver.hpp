// GPU measurements beside the cuda solver backend (poisson/cuda_solver.cu): the cuSPARSE product and
// the device's copy bandwidth, for the SpMV benchmark and the device tests. Without a CUDA build or a
// visible device each call throws std::runtime_error saying which.
#pragma once

#include <vector>

#include "poisson/linear_solver.hpp"

namespace isph {

// cuSPARSE's CSR products: CSR_ALG2, bit-wise reproducible (the solver's), or CSR_ALG1, the default.
enum class SpmvAlgorithm { reproducible, default_csr };

struct SpmvMeasurement {
  std::vector<double> y;             // A x from cuSPARSE
  double seconds_per_product = 0;    // mean of `repeats` products, timed with CUDA events
  double bytes_per_product = 0;      // least traffic: 12 bytes per nonzero, 4 per row offset, x read and y written once
  double copy_bandwidth = 0;         // bytes/s of device-to-device copies of 512 MiB (read + write counted)
};

SpmvMeasurement measure_cuda_spmv(const CsrMatrix& A, const std::vector<double>& x, int repeats,
                                  SpmvAlgorithm algorithm = SpmvAlgorithm::reproducible);

}  // namespace isph
