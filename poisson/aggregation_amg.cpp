// The coarsest level of the AMG hierarchy (poisson/aggregation_amg.hpp), inverted densely on the host.
#include "poisson/aggregation_amg.hpp"

#include <Eigen/Dense>

namespace isph::amg {

std::vector<double> dense_inverse(int n, const std::vector<int>& row_offset, const std::vector<int>& col,
                                  const std::vector<double>& val) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int k = row_offset[i]; k < row_offset[i + 1]; ++k) A(i, col[k]) += val[k];
  // A coarse Galerkin matrix can be singular (a closed box's constant pressure): then the
  // pseudo-inverse, which leaves that mode to the Krylov method.
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  const Eigen::MatrixXd inverse = lu.isInvertible()
                                      ? Eigen::MatrixXd(lu.inverse())
                                      : Eigen::MatrixXd(A.completeOrthogonalDecomposition().pseudoInverse());
  std::vector<double> out(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) out[static_cast<std::size_t>(i) * n + j] = inverse(i, j);
  return out;
}

}  // namespace isph::amg
