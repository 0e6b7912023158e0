// The interface quasi-Newton iterations of the coupled step (sim/coupling.hpp, IQN-ILS).
#include <gtest/gtest.h>

#include "sim/coupling.hpp"

using namespace isph;

namespace {

// Iterates x = H(x), H(x) = A x + b, from x0 until |H(x) - x| <= 1e-10 |H(x)|; returns the iterations
// used (max_iterations + 1 if it did not converge).
int solve(InterfaceQuasiNewton& qn, const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
          int max_iterations) {
  qn.begin_step();
  for (int k = 1; k <= max_iterations; ++k) {
    const Eigen::VectorXd hx = A * x + b;
    if ((hx - x).norm() <= 1e-10 * hx.norm()) return k;
    x = qn.next(x, hx);
  }
  return max_iterations + 1;
}

}  // namespace

// On a linear map IQN-ILS finds the fixed point once its columns span the space (n + 1 iterations),
// even where plain iteration diverges (|eigenvalues| > 1, like heavy water on a light plate).
TEST(InterfaceQuasiNewton, SolvesALinearFixedPointBeyondContraction) {
  const Eigen::Vector4d d(3.0, -2.0, 0.5, -4.0);
  const Eigen::MatrixXd A = d.asDiagonal();
  const Eigen::Vector4d b(1.0, 2.0, -1.0, 0.5);
  InterfaceQuasiNewton qn(0);
  Eigen::VectorXd x = Eigen::Vector4d::Zero();
  EXPECT_LE(solve(qn, A, b, x, 10), 6);
  const Eigen::VectorXd exact = (Eigen::MatrixXd::Identity(4, 4) - A).inverse() * b;
  EXPECT_LT((x - exact).norm(), 1e-8 * exact.norm());
}

// Columns reused from earlier steps speed up a step whose map is the same, and a step whose map has
// changed (an impact) still converges. (On linear maps like these the reused columns do not mislead;
// the safeguard that drops them when the residual grows was needed at the Walhorn impact,
// docs/VALIDATION.md section 12.)
TEST(InterfaceQuasiNewton, ReusedColumnsSpeedUpTheNextStepAndAChangedMapStillConverges) {
  constexpr int n = 12;
  Eigen::VectorXd d1(n), d2(n), b(n);
  for (int i = 0; i < n; ++i) {
    d1[i] = (i % 2 ? -1.0 : 1.0) * (1.5 + 0.25 * i);
    d2[i] = -3.0 * d1[i] + 0.5;
    b[i] = 1.0 + 0.1 * i;
  }
  const Eigen::MatrixXd A1 = d1.asDiagonal(), A2 = d2.asDiagonal();
  InterfaceQuasiNewton qn(8);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  const int first = solve(qn, A1, b, x, 40);
  b *= 1.1;  // the next step: the same map, another load
  const int second = solve(qn, A1, b, x, 40);
  EXPECT_LT(second, first);
  EXPECT_LE(solve(qn, A2, b, x, 40), n + 2);  // another map: converged within n + 2 iterations
  const Eigen::VectorXd exact = (Eigen::MatrixXd::Identity(n, n) - A2).inverse() * b;
  EXPECT_LT((x - exact).norm(), 1e-8 * exact.norm());
}

// A restart carries the columns (history, set_history): the next step's iterates are those of the run
// that kept going, bit for bit, and the step converges in as few iterations; without the columns it
// takes as many as the first step did.
TEST(InterfaceQuasiNewton, HistoryCarriedToANewInstanceGivesTheSameIterates) {
  constexpr int n = 6;
  Eigen::VectorXd d(n), b(n);
  for (int i = 0; i < n; ++i) {
    d[i] = (i % 2 ? -1.0 : 1.0) * (2.0 + 0.5 * i);
    b[i] = 1.0 - 0.2 * i;
  }
  const Eigen::MatrixXd A = d.asDiagonal();
  InterfaceQuasiNewton kept(8);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  const int first = solve(kept, A, b, x, 40);
  InterfaceQuasiNewton restarted(8), fresh(8);
  restarted.set_history(kept.history());
  EXPECT_EQ(kept.history().size(), 1u);
  b *= 0.9;
  Eigen::VectorXd x_kept = x, x_restarted = x, x_fresh = x;
  const int with_columns = solve(kept, A, b, x_kept, 40);
  EXPECT_EQ(solve(restarted, A, b, x_restarted, 40), with_columns);
  EXPECT_EQ(x_restarted, x_kept);
  EXPECT_LT(with_columns, first);
  EXPECT_EQ(solve(fresh, A, b, x_fresh, 40), first);
}
