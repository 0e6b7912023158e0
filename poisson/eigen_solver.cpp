// Eigen 3.4 backend: BiCGSTAB (Eigen/IterativeLinearSolvers) or restarted GMRES
// (unsupported/Eigen/IterativeSolvers), preconditioned by Jacobi (DiagonalPreconditioner), ILUT
// (IncompleteLUT) or nothing (IdentityPreconditioner). The CSR matrix is copied into a row-major
// Eigen::SparseMatrix, whose matrix-vector product Eigen runs with OpenMP.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <memory>
#include <span>
#include <string>
#include <unsupported/Eigen/IterativeSolvers>

#include "poisson/linear_solver.hpp"

namespace isph::detail {
namespace {

using SpMat = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Vec = Eigen::VectorXd;

// ILUT parameters: entries below droptol * (2-norm of their row) are dropped, and each row of L and of
// U keeps at most fillfactor * (mean nonzeros per row of A) / 2 entries. Eigen's defaults (1e-12, 10)
// keep almost everything: on the 21-point benchmark at 1e5 unknowns they take 7.7 s for 5 iterations,
// these 2.1 s for 15 (the set-up dominates, and the PPE matrix changes every step).
constexpr double kIlutDropTol = 1e-3;
constexpr int kIlutFillFactor = 4;

// One Eigen iterative solver type, held between the refinement passes of a solve.
struct Engine {
  virtual ~Engine() = default;
  virtual std::string compute(const SpMat& A) = 0;  // preconditioner set-up: "" or why it failed
  virtual int iterate(const Vec& b, Vec& x, double tol, int max_iterations, Eigen::ComputationInfo& info) = 0;
};

template <class Solver>
struct EngineOf final : Engine {
  Solver solver;
  std::string compute(const SpMat& A) override {
    solver.compute(A);
    return solver.info() == Eigen::Success ? "" : "the preconditioner could not be built (zero row or pivot)";
  }
  int iterate(const Vec& b, Vec& x, double tol, int max_iterations, Eigen::ComputationInfo& info) override {
    solver.setTolerance(tol);
    solver.setMaxIterations(max_iterations);
    x = solver.solveWithGuess(b, x);
    info = solver.info();
    return static_cast<int>(solver.iterations());
  }
};

template <template <class, class> class Krylov, class Precond>
std::unique_ptr<Engine> make_engine(const SolverSettings& s) {
  auto e = std::make_unique<EngineOf<Krylov<SpMat, Precond>>>();
  if constexpr (std::is_same_v<Precond, Eigen::IncompleteLUT<double, int>>) {
    e->solver.preconditioner().setDroptol(kIlutDropTol);
    e->solver.preconditioner().setFillfactor(kIlutFillFactor);
  }
  if constexpr (std::is_same_v<Krylov<SpMat, Precond>, Eigen::GMRES<SpMat, Precond>>)
    e->solver.set_restart(s.gmres_restart);
  return e;
}

template <template <class, class> class Krylov>
std::unique_ptr<Engine> make_engine_for(const SolverSettings& s) {
  if (s.preconditioner == PreconditionerType::jacobi)
    return make_engine<Krylov, Eigen::DiagonalPreconditioner<double>>(s);
  if (s.preconditioner == PreconditionerType::ilu) return make_engine<Krylov, Eigen::IncompleteLUT<double, int>>(s);
  return make_engine<Krylov, Eigen::IdentityPreconditioner>(s);
}

class EigenSolver final : public KrylovSolverFrame {
 public:
  explicit EigenSolver(const SolverSettings& s) : KrylovSolverFrame(s) {}

 protected:
  std::string setup(const CsrMatrix& A, std::span<const double> b) override {
    // Copy the (sorted, duplicate-free) CSR arrays straight into a compressed row-major matrix.
    A_.resize(A.rows, A.rows);
    A_.resizeNonZeros(static_cast<Eigen::Index>(A.col.size()));
    std::copy(A.row_offset.begin(), A.row_offset.end(), A_.outerIndexPtr());
    std::copy(A.col.begin(), A.col.end(), A_.innerIndexPtr());
    std::copy(A.val.begin(), A.val.end(), A_.valuePtr());
    b_ = Eigen::Map<const Vec>(b.data(), static_cast<Eigen::Index>(b.size()));
    engine_ = settings_.method == KrylovMethod::gmres ? make_engine_for<Eigen::GMRES>(settings_)
                                                      : make_engine_for<Eigen::BiCGSTAB>(settings_);
    return engine_->compute(A_);
  }

  void update_rhs(std::span<const double> b) override {
    b_ = Eigen::Map<const Vec>(b.data(), static_cast<Eigen::Index>(b.size()));
  }

  Pass iterate(std::span<double> x, double tol, int max_iterations) override {
    Vec xe = Eigen::Map<const Vec>(x.data(), static_cast<Eigen::Index>(x.size()));
    Eigen::ComputationInfo info = Eigen::Success;
    Pass p;
    p.iterations = engine_->iterate(b_, xe, tol, max_iterations, info);
    p.claimed_converged = info == Eigen::Success;
    if (info == Eigen::NumericalIssue) p.note = "Eigen reported a numerical issue";
    Eigen::Map<Vec>(x.data(), static_cast<Eigen::Index>(x.size())) = xe;
    return p;
  }

  void release() override {
    engine_.reset();
    A_ = SpMat();
    b_ = Vec();
  }

  // Eigen's BiCGSTAB stops on ||r|| <= tol ||b||; its GMRES on ||M^-1 r|| <= tol ||M^-1 r_0|| of the pass.
  bool tolerance_relative_to_initial_residual() const override { return settings_.method == KrylovMethod::gmres; }

 private:
  SpMat A_;
  Vec b_;
  std::unique_ptr<Engine> engine_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_eigen_solver(const SolverSettings& s) { return std::make_unique<EigenSolver>(s); }

}  // namespace isph::detail
