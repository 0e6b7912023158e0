// The cuda solver backend's entry points in a build without CUDA: each says so.
#include <memory>
#include <stdexcept>

#include "poisson/cuda_solver.hpp"

#if !defined(ISPH_HAVE_CUDA)
namespace isph {
namespace detail {
std::unique_ptr<LinearSolver> make_cuda_solver(const SolverSettings&) {
  throw std::invalid_argument(
      "linear solver: backend 'cuda' was requested but this build has no CUDA backend (nvcc was not found at "
      "configure time; use backend 'native', 'eigen' or 'hypre')");
}
}  // namespace detail

SpmvMeasurement measure_cuda_spmv(const CsrMatrix&, const std::vector<double>&, int, SpmvAlgorithm, int) {
  throw std::runtime_error("measure_cuda_spmv: this build has no CUDA backend");
}
}  // namespace isph
#endif
