#pragma once
// IQN-ILS for the interface iterations of the coupled step (Degroote, Bathe & Vierendeels 2009; the
// scheme and its safeguards are described in sim/coupling.hpp). Compiled by the host compiler even when
// the CUDA backend is built: Eigen turns its SIMD off under nvcc, and its sums would then round
// differently from a build without CUDA.
#include <Eigen/Dense>
#include <deque>
#include <vector>

#include "core/types.hpp"

namespace isph {

// IQN-ILS for a fixed point x = H(x), with the columns of earlier steps reused.
class InterfaceQuasiNewton {
 public:
  struct Column {
    Eigen::VectorXd dr, dh;  // differences of the residual and of H between two iterations
  };
  explicit InterfaceQuasiNewton(int reuse_steps) : reuse_steps_(reuse_steps) {}
  // Starts the iterations of a new step; the columns of the step that ended are kept for reuse.
  void begin_step();
  // The next iterate from x and H(x).
  Eigen::VectorXd next(const Eigen::VectorXd& x, const Eigen::VectorXd& hx);
  // The columns a next step would reuse, per step, newest first: what a restart must carry, since a
  // capped iteration count (coupling.max_iterations = 2) takes its second iterate from them.
  std::vector<std::vector<Column>> history() const;
  // Continues with `steps` (as history() gives them) as the earlier steps' columns.
  void set_history(std::vector<std::vector<Column>> steps);

 private:
  int reuse_steps_;
  std::vector<Column> current_;
  std::deque<std::vector<Column>> earlier_;  // newest first
  Eigen::VectorXd last_r_, last_h_;
  bool has_last_ = false;
};

}  // namespace isph
