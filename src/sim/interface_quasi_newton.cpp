#include "sim/interface_quasi_newton.hpp"

#include <algorithm>

namespace isph {

void InterfaceQuasiNewton::begin_step() {
  if (!current_.empty()) {
    earlier_.push_front(std::move(current_));
    if (static_cast<int>(earlier_.size()) > reuse_steps_) earlier_.pop_back();
  }
  current_.clear();
  has_last_ = false;
}

Eigen::VectorXd InterfaceQuasiNewton::next(const Eigen::VectorXd& x, const Eigen::VectorXd& hx) {
  const Eigen::VectorXd r = hx - x;
  // A residual that grows means the reused columns describe another state of the interface (an
  // impact changes it within a step): they are dropped, and reuse starts again from this step.
  if (has_last_ && r.norm() > last_r_.norm()) earlier_.clear();
  if (has_last_) current_.push_back({r - last_r_, hx - last_h_});
  last_r_ = r;
  last_h_ = hx;
  has_last_ = true;
  std::vector<const Column*> columns;
  for (auto it = current_.rbegin(); it != current_.rend(); ++it) columns.push_back(&*it);  // newest first
  for (const auto& step : earlier_)
    for (auto it = step.rbegin(); it != step.rend(); ++it) columns.push_back(&*it);
  const Eigen::Index rows = x.size();
  const Eigen::Index cols = std::min<Eigen::Index>(static_cast<Eigen::Index>(columns.size()), rows);
  if (cols == 0) return x + 0.1 * r;
  Eigen::MatrixXd V(rows, cols), W(rows, cols);
  for (Eigen::Index k = 0; k < cols; ++k) {
    V.col(k) = columns[k]->dr;
    W.col(k) = columns[k]->dh;
  }
  const Eigen::VectorXd c = V.colPivHouseholderQr().solve(-r);
  return hx + W * c;
}

bool InterfaceQuasiNewton::converged(const Eigen::VectorXd& x, const Eigen::VectorXd& hx, Real tolerance, Real floor) {
  return (hx - x).norm() <= tolerance * std::max(hx.norm(), floor);
}

}  // namespace isph
