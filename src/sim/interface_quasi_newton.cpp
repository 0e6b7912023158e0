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

std::vector<std::vector<InterfaceQuasiNewton::Column>> InterfaceQuasiNewton::history() const {
  std::vector<std::vector<Column>> steps;
  if (!current_.empty()) steps.push_back(current_);
  steps.insert(steps.end(), earlier_.begin(), earlier_.end());
  if (static_cast<int>(steps.size()) > reuse_steps_) steps.resize(static_cast<std::size_t>(reuse_steps_));
  return steps;
}

void InterfaceQuasiNewton::set_history(std::vector<std::vector<Column>> steps) {
  current_.clear();
  earlier_.assign(std::make_move_iterator(steps.begin()), std::make_move_iterator(steps.end()));
  while (static_cast<int>(earlier_.size()) > reuse_steps_) earlier_.pop_back();
  has_last_ = false;
}

}  // namespace isph
