// The native backend: the project's BiCGSTAB (poisson/krylov.hpp) on the host, its loops run by the
// launcher with OpenMP. It is the host reference of the cuda backend, which runs the same code.
#include <memory>

#include "poisson/host_ops.hpp"
#include "poisson/krylov.hpp"

namespace isph::detail {

std::unique_ptr<LinearSolver> make_native_solver(const SolverSettings& s) {
  return std::make_unique<OwnKrylovSolver<HostOps>>(s);
}

}  // namespace isph::detail
