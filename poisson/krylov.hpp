// The project's own Krylov solver, written once over a handful of vector primitives and run by two
// backends (docs/SOLVERS.md):
//   native : the primitives on the host (OpenMP), poisson/native_solver.cpp;
//   cuda   : cuSPARSE generic SpMV and cuBLAS dot products on the GPU, the other primitives as launcher
//            functors, poisson/cuda_solver.cu.
// Both backends run the same BiCGSTAB and the same preconditioners, so the host backend is the test
// bed of the algorithm and the reference of the device one (the shape of AMGCL's backends).
//
// An Ops type supplies:
//   using Vector;                               // a vector in the backend's memory
//   static constexpr Device device;             // where the functors below run, and
//   Exec exec() const;                          // the same as an Exec
//   Vector vector(int n);                       // uninitialised
//   static double* data(Vector&); static const double* data(const Vector&);
//   void upload(std::span<const double>, Vector&); void download(const Vector&, std::span<double>);
//                                               // the caller's b and x (host or managed memory), n entries
//   void set_matrix(const CsrMatrix&);          // keeps a copy of A in the backend (reusing its storage)
//   CsrView matrix() const;                     // that copy, as pointers in the backend's memory
//   void spmv(const Vector& x, Vector& y);      // y = A x
//   double dot(const Vector& x, const Vector& y);
//   void release();                             // done with the copy of A
//   template <class T> using Array;             // typed arrays in the backend's memory (the AMG's levels)
//   template <class T> Array<T> array(std::size_t n);
//   template <class T> std::vector<T> to_host(const T* p, std::size_t n);   // n entries from p
//   template <class T> Array<T> from_host(const std::vector<T>&);
#pragma once

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/parallel.hpp"
#include "poisson/aggregation_amg.hpp"
#include "poisson/linear_solver.hpp"
#include "poisson/sparse_functors.hpp"

namespace isph {

// The polynomial preconditioner: kPolynomialSweeps damped-Jacobi sweeps from z = 0,
//   z_0 = ω D⁻¹ r,  z_{k+1} = z_k + ω D⁻¹ (r − A z_k),
// i.e. z = p(D⁻¹A) D⁻¹ r with p(λ) = (1 − (1 − ωλ)^m) / λ (a truncated Neumann series, Saad 2003
// §12.3). For the PPE's weakly diagonally dominant rows D⁻¹A has its eigenvalues in (0, 2], where
// ω = 2/3 keeps |1 − ωλ| ≤ 1/3 at the top of the spectrum; each application costs m − 1 SpMVs.
inline constexpr int kPolynomialSweeps = 3;
inline constexpr double kPolynomialDamping = 2.0 / 3.0;

// BiCGSTAB (van der Vorst 1992) with right preconditioning, over an Ops backend. Holds the work vectors,
// resized for each matrix's size and reallocated only when it outgrows them (one row per particle).
template <class Ops>
class Bicgstab {
 public:
  using Vector = typename Ops::Vector;
  enum class Preconditioner { none, jacobi, polynomial, amg };

  Bicgstab(Ops& ops, int n) : ops_(ops) { resize(n); }

  int size() const { return n_; }
  // Work vectors for systems of n rows, reallocated only when n outgrows them (the PPE's size follows the
  // particles, step by step, with open boundaries); the preconditioner stays (refresh_preconditioner).
  void resize(int n) {
    n_ = n;
    for (Vector* v : {&dinv_, &r_, &rhat_, &p_, &v_, &s_, &t_, &phat_, &shat_, &work_}) Ops::resize(*v, n);
  }
  // The preconditioner of the next runs, for the backend's current matrix (D⁻¹ is taken where the
  // matrix is). Returns an empty string, or why it cannot be built.
  std::string set_preconditioner(Preconditioner m) {
    m_ = m;
    if (m == Preconditioner::none) return "";
    const CsrView A = ops_.matrix();
    if (m == Preconditioner::amg) {
      if (!amg_) amg_.emplace(ops_);
      return amg_->setup(A);
    }
    parallel_for(ops_.exec(), n_, InverseDiagonal{A, Ops::data(dinv_)});
    const Index bad =
        parallel_reduce(ops_.exec(), n_, RowWithoutDiagonal::kNoRow, RowWithoutDiagonal{Ops::data(dinv_)}, MinOf{});
    if (bad != RowWithoutDiagonal::kNoRow)
      return "zero diagonal in row " + std::to_string(bad) + ": the Jacobi scaling cannot be built";
    return "";
  }

  // Keeps the AMG hierarchy of the last set_preconditioner for the backend's new matrix, of the same
  // rows or of rows that continue the old ones as origin says (AggregationAmg::refresh_fine); the other
  // preconditioners are rebuilt, which costs one pass. False when there is nothing to keep.
  bool refresh_preconditioner(const Index* origin = nullptr) {
    if (m_ != Preconditioner::amg) return set_preconditioner(m_).empty();
    return amg_ && amg_->refresh_fine(ops_.matrix(), origin);
  }

  // Iterates from x until ||r|| <= tol_abs or max_iterations; x is in the backend's memory. Returns the
  // iterations done, whether the recursive residual met tol_abs, and why it stopped otherwise.
  struct Result {
    int iterations = 0;
    bool converged = false;
    std::string note;
  };
  Result run(const Vector& b, Vector& x, double tol_abs, int max_iterations) {
    Result res;
    ops_.spmv(x, r_);
    axpby(1, b, -1, r_);  // r = b − A x
    axpby(1, r_, 0, rhat_);
    if (norm(r_) <= tol_abs) {
      res.converged = true;
      return res;
    }
    double rho_old = 1, alpha = 1, omega = 1;
    for (int it = 0; it < max_iterations; ++it) {
      const double rho = ops_.dot(rhat_, r_);
      if (rho == 0 || !std::isfinite(rho)) {
        res.note = "BiCGSTAB breakdown (rho = 0)";
        return res;
      }
      if (it == 0) {
        axpby(1, r_, 0, p_);
      } else {  // p = r + β (p − ω v)
        const double beta = (rho / rho_old) * (alpha / omega);
        axpby(-omega, v_, 1, p_);
        axpby(1, r_, beta, p_);
      }
      precondition(p_, phat_);
      ops_.spmv(phat_, v_);
      const double rhat_v = ops_.dot(rhat_, v_);
      if (rhat_v == 0 || !std::isfinite(rhat_v)) {
        res.note = "BiCGSTAB breakdown (r̂·v = 0)";
        return res;
      }
      alpha = rho / rhat_v;
      axpby(1, r_, 0, s_);
      axpby(-alpha, v_, 1, s_);  // s = r − α v
      res.iterations = it + 1;
      if (norm(s_) <= tol_abs) {
        axpby(alpha, phat_, 1, x);
        res.converged = true;
        return res;
      }
      precondition(s_, shat_);
      ops_.spmv(shat_, t_);
      const double tt = ops_.dot(t_, t_);
      omega = tt > 0 ? ops_.dot(t_, s_) / tt : 0;
      axpby(alpha, phat_, 1, x);
      axpby(omega, shat_, 1, x);  // x += α p̂ + ω ŝ
      axpby(1, s_, 0, r_);
      axpby(-omega, t_, 1, r_);  // r = s − ω t
      if (norm(r_) <= tol_abs) {
        res.converged = true;
        return res;
      }
      if (omega == 0 || !std::isfinite(omega)) {
        res.note = "BiCGSTAB breakdown (omega = 0)";
        return res;
      }
      rho_old = rho;
    }
    return res;
  }

  double norm(const Vector& x) { return std::sqrt(ops_.dot(x, x)); }

 private:
  void axpby(double a, const Vector& x, double b, Vector& y) { scaled_axpby(a, nullptr, x, b, y); }
  void scaled_axpby(double a, const Vector* d, const Vector& x, double b, Vector& y) {
    parallel_for(ops_.exec(), n_,
                 ScaledAxpby{.a = a, .b = b, .d = d ? Ops::data(*d) : nullptr, .x = Ops::data(x), .y = Ops::data(y)});
  }

  // z = M⁻¹ r
  void precondition(const Vector& r, Vector& z) {
    switch (m_) {
      case Preconditioner::none:
        axpby(1, r, 0, z);
        return;
      case Preconditioner::jacobi:
        scaled_axpby(1, &dinv_, r, 0, z);
        return;
      case Preconditioner::polynomial:
        scaled_axpby(kPolynomialDamping, &dinv_, r, 0, z);
        for (int k = 1; k < kPolynomialSweeps; ++k) {
          ops_.spmv(z, work_);
          axpby(1, r, -1, work_);
          scaled_axpby(kPolynomialDamping, &dinv_, work_, 1, z);
        }
        return;
      case Preconditioner::amg:
        amg_->apply(Ops::data(r), Ops::data(z));
        return;
    }
  }

  Ops& ops_;
  int n_ = 0;
  Preconditioner m_ = Preconditioner::none;
  std::optional<AggregationAmg<Ops>> amg_;
  Vector dinv_, r_, rhat_, p_, v_, s_, t_, phat_, shat_, work_;
};

namespace detail {

// A LinearSolver over an Ops backend: the shared frame (linear_solver.hpp) around Bicgstab<Ops>.
template <class Ops>
class OwnKrylovSolver final : public KrylovSolverFrame {
 public:
  explicit OwnKrylovSolver(const SolverSettings& s) : KrylovSolverFrame(s, Exec{Ops::device}) {}
  ~OwnKrylovSolver() override { release(); }

 protected:
  std::string setup(const CsrMatrix& A, std::span<const double> b) override {
    using P = typename Bicgstab<Ops>::Preconditioner;
    const P m = settings_.preconditioner == PreconditionerType::jacobi       ? P::jacobi
                : settings_.preconditioner == PreconditionerType::polynomial ? P::polynomial
                : settings_.preconditioner == PreconditionerType::amg        ? P::amg
                                                                             : P::none;
    ops_.set_matrix(A);
    fit(A.rows);
    if (std::string why = krylov_->set_preconditioner(m); !why.empty()) return why;
    update_rhs(b);
    return "";
  }

  bool refresh_matrix(const CsrMatrix& A, std::span<const double> b, std::span<const Index> origin) override {
    if (!krylov_ || (origin.empty() && krylov_->size() != A.rows)) return false;
    ops_.set_matrix(A);
    fit(A.rows);
    if (!origin.empty()) ops_.assign(origin_, origin);
    if (!krylov_->refresh_preconditioner(origin.empty() ? nullptr : origin_.data())) return false;
    update_rhs(b);
    return true;
  }

  void update_rhs(std::span<const double> b) override {
    ops_.upload(b, b_);
    b_norm_ = krylov_->norm(b_);
  }

  Pass iterate(std::span<double> x, double tol, int max_iterations) override {
    ops_.upload(x, x_);
    const auto r = krylov_->run(b_, x_, tol * b_norm_, max_iterations);
    ops_.download(x_, x);
    return Pass{r.iterations, r.converged, r.note};
  }

  // Lets go of the matrix; the work vectors stay for the next matrix of the same size.
  void release() override { ops_.release(); }

  // The work vectors (and the AMG's arrays, kept in krylov_) for n rows.
  void fit(int n) {
    if (!krylov_) krylov_.emplace(ops_, 0);
    if (krylov_->size() == n) return;
    krylov_->resize(n);
    Ops::resize(b_, n);
    Ops::resize(x_, n);
  }

  bool tolerance_relative_to_initial_residual() const override { return false; }

 private:
  Ops ops_;
  std::optional<Bicgstab<Ops>> krylov_;  // the work vectors and the preconditioner
  typename Ops::Vector b_, x_;
  typename Ops::template Array<Index> origin_;  // refresh_matrix's origin, in the backend's memory
  double b_norm_ = 0;
};

}  // namespace detail
}  // namespace isph
