// The solver factory, option checking, and the frame shared by every backend (see linear_solver.hpp).
#include "poisson/linear_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/ordered_sum.hpp"
#include "poisson/sparse_functors.hpp"

namespace isph {

namespace detail {
// Defined in eigen_solver.cpp, hypre_solver.cpp, native_solver.cpp and cuda_solver.cu.
std::unique_ptr<LinearSolver> make_eigen_solver(const SolverSettings&);
std::unique_ptr<LinearSolver> make_hypre_solver(const SolverSettings&);
std::unique_ptr<LinearSolver> make_native_solver(const SolverSettings&);
std::unique_ptr<LinearSolver> make_cuda_solver(const SolverSettings&);
std::unique_ptr<LinearSolver> make_debug_device_solver(const SolverSettings&);  // cuda on the debug device
}  // namespace detail

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : ", ") + e;
  return s;
}

template <class E>
void require_one_of(const std::string& option, E value, const std::vector<E>& allowed, const std::string& context) {
  if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return;
  std::vector<std::string> names;
  for (E e : allowed) names.push_back(name_of(e));
  throw std::invalid_argument("linear solver: " + option + " '" + name_of(value) + "'" + context +
                              " is not offered (allowed: " + join(names) + ")");
}

constexpr Index kNone = 0x7fffffff;  // "no such row": the identity of MinOf over row indices

// The first row whose offsets decrease (or row 0 when its offset is not 0).
struct BadOffset {
  const int* row_offset;
  ISPH_HD Index operator()(Index i) const {
    return (i == 0 && row_offset[0] != 0) || row_offset[i + 1] < row_offset[i] ? i : kNone;
  }
};
struct ColumnOutOfRange {
  const int* col;
  int rows;
  ISPH_HD Index operator()(Index k) const { return col[k] < 0 || col[k] >= rows ? k : kNone; }
};
struct NonFiniteEntry {
  const double* v;
  ISPH_HD Index operator()(Index i) const { return finite_value(v[i]) ? kNone : i; }
};
// A row whose columns do not increase strictly (unsorted or duplicated).
struct UnsortedRow {
  const int* row_offset;
  const int* col;
  ISPH_HD Index operator()(Index i) const {
    for (int k = row_offset[i] + 1; k < row_offset[i + 1]; ++k)
      if (col[k] <= col[k - 1]) return i;
    return kNone;
  }
};
struct Magnitude {
  const double* v;
  ISPH_HD double operator()(Index i) const { return fabs(v[i]); }
};
// r_i^2 and b_i^2 of the residual r = b - A x.
struct ResidualSquares {
  const int* row_offset;
  const int* col;
  const double* val;
  const double* b;
  const double* x;
  double* r2;
  double* b2;
  ISPH_HD void operator()(Index i) const {
    const double r = row_residual(row_offset, col, val, b, x, i);
    r2[i] = r * r;
    b2[i] = b[i] * b[i];
  }
};
template <class F>
Index first(const Exec& exec, Index n, const F& f) {
  return parallel_reduce(exec, n, kNone, f, MinOf{});
}

StateVector<double> work_array(const Exec& exec) {
  return StateVector<double>(StateAllocator<double>(exec.device == Device::cuda));
}

double relative_residual_on(const Exec& exec, const CsrMatrix& A, std::span<const double> b, std::span<const double> x,
                            StateVector<double>& r2, StateVector<double>& b2, StateVector<double>& partial) {
  r2.resize(A.rows);
  b2.resize(A.rows);
  parallel_for(exec, A.rows,
               ResidualSquares{.row_offset = A.row_offset.data(),
                               .col = A.col.data(),
                               .val = A.val.data(),
                               .b = b.data(),
                               .x = x.data(),
                               .r2 = r2.data(),
                               .b2 = b2.data()});
  const double r = ordered_sum(exec, A.rows, ScalarAt{r2.data()}, partial);
  const double bb = ordered_sum(exec, A.rows, ScalarAt{b2.data()}, partial);
  return bb > 0 ? std::sqrt(r / bb) : std::sqrt(r);
}

bool all_finite(const Exec& exec, std::span<const double> v) {
  return first(exec, static_cast<Index>(v.size()), NonFiniteEntry{v.data()}) == kNone;
}

// The checks of check_linear_system, on exec.
void check_system(const Exec& exec, const CsrMatrix& A, std::span<const double> b, std::span<const double> x) {
  const auto fail = [](const std::string& why) { throw std::invalid_argument("linear solver: " + why); };
  if (A.rows < 0) fail("matrix has a negative number of rows");
  const auto n = static_cast<std::size_t>(A.rows);
  if (n == 0 && A.row_offset.empty() && A.col.empty() && A.val.empty()) {  // a default-constructed matrix
    if (!b.empty() || !x.empty()) fail("b and x must be empty for an empty matrix");
    return;
  }
  if (A.row_offset.size() != n + 1)
    fail("row_offset has " + std::to_string(A.row_offset.size()) +
         " entries, expected rows + 1 = " + std::to_string(n + 1));
  if (n == 0 && read_back(exec, A.row_offset.data()) != 0) fail("row_offset[0] must be 0");
  if (const Index bad = first(exec, A.rows, BadOffset{A.row_offset.data()}); bad != kNone)
    fail(bad == 0 && read_back(exec, A.row_offset.data()) != 0 ? std::string("row_offset[0] must be 0")
                                                               : "row_offset decreases at row " + std::to_string(bad));
  const auto nnz = static_cast<std::size_t>(read_back(exec, A.row_offset.data() + n));
  if (A.col.size() != nnz || A.val.size() != nnz)
    fail("col and val must have row_offset[rows] = " + std::to_string(nnz) + " entries (have " +
         std::to_string(A.col.size()) + " and " + std::to_string(A.val.size()) + ")");
  if (const Index bad = first(exec, static_cast<Index>(nnz), ColumnOutOfRange{A.col.data(), A.rows}); bad != kNone)
    fail("column index " + std::to_string(read_back(exec, A.col.data() + bad)) + " out of range [0, " +
         std::to_string(A.rows) + ")");
  if (b.size() != n) fail("b has " + std::to_string(b.size()) + " entries, matrix has " + std::to_string(n) + " rows");
  if (x.size() != n) fail("x has " + std::to_string(x.size()) + " entries, matrix has " + std::to_string(n) + " rows");
}

// Sorts the columns of every row and sums duplicates.
CsrMatrix canonical(const CsrMatrix& A) {
  CsrMatrix C;
  C.rows = A.rows;
  C.row_offset.assign(A.rows + 1, 0);
  C.col.reserve(A.col.size());
  C.val.reserve(A.val.size());
  std::vector<std::pair<int, double>> row;
  for (int i = 0; i < A.rows; ++i) {
    row.clear();
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) row.emplace_back(A.col[k], A.val[k]);
    std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [c, v] : row) {
      if (static_cast<int>(C.col.size()) > C.row_offset[i] && C.col.back() == c) {
        C.val.back() += v;
      } else {
        C.col.push_back(c);
        C.val.push_back(v);
      }
    }
    C.row_offset[i + 1] = static_cast<int>(C.col.size());
  }
  return C;
}

std::string sci(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

}  // namespace

const std::vector<KrylovMethod>& solver_methods(SolverBackend backend) {
  static const std::vector<KrylovMethod> library{KrylovMethod::bicgstab, KrylovMethod::gmres},
      own{KrylovMethod::bicgstab};
  return backend == SolverBackend::eigen || backend == SolverBackend::hypre ? library : own;
}

const std::vector<PreconditionerType>& solver_preconditioners(SolverBackend backend) {
  using P = PreconditionerType;
  static const std::vector<P> eigen{P::ilu, P::jacobi, P::none}, hypre{P::boomeramg, P::jacobi, P::none},
      own{P::jacobi, P::polynomial, P::amg, P::none};
  return backend == SolverBackend::eigen ? eigen : backend == SolverBackend::hypre ? hypre : own;
}

bool hypre_available() {
#ifdef ISPH_HAVE_HYPRE
  return true;
#else
  return false;
#endif
}

std::unique_ptr<LinearSolver> make_linear_solver(const SolverSettings& s) {
  const std::string for_backend = " for backend '" + name_of(s.backend) + "'";
  require_one_of("method", s.method, solver_methods(s.backend), for_backend);
  require_one_of("preconditioner", s.preconditioner, solver_preconditioners(s.backend), for_backend);
  if (!(s.tolerance > 0 && s.tolerance < 1))
    throw std::invalid_argument("linear solver: tolerance must be in (0, 1), got " + sci(s.tolerance));
  if (s.max_iterations < 1)
    throw std::invalid_argument("linear solver: max_iterations must be at least 1, got " +
                                std::to_string(s.max_iterations));
  if (s.gmres_restart < 1)
    throw std::invalid_argument("linear solver: gmres_restart must be at least 1, got " +
                                std::to_string(s.gmres_restart));
  if (s.backend == SolverBackend::hypre) {
    if (!hypre_available())
      throw std::invalid_argument(
          "linear solver: backend 'hypre' was requested but this build has no hypre (ISPH_HAVE_HYPRE is not "
          "defined; install libhypre-dev and libopenmpi-dev and reconfigure, or use backend 'eigen')");
    return detail::make_hypre_solver(s);
  }
  if (s.backend == SolverBackend::native) return detail::make_native_solver(s);
  if (s.backend == SolverBackend::cuda)
    return device_emulated() ? detail::make_debug_device_solver(s) : detail::make_cuda_solver(s);
  return detail::make_eigen_solver(s);
}

void check_linear_system(const CsrMatrix& A, std::span<const double> b, std::span<const double> x) {
  check_system(Exec{}, A, b, x);
}

double relative_residual(const CsrMatrix& A, std::span<const double> b, std::span<const double> x) {
  StateVector<double> r2, b2, partial;
  return relative_residual_on(Exec{}, A, b, x, r2, b2, partial);
}

SolveReport LinearSolver::solve(const CsrMatrix& A, const std::vector<double>& b, std::vector<double>& x,
                                MatrixReuse reuse, std::span<const Index> origin) {
  if (!x.empty()) return solve(A, std::span<const double>(b), std::span<double>(x), reuse, origin);
  std::vector<double> zero_guess(static_cast<std::size_t>(std::max(A.rows, 0)), 0.0);  // x stays empty if this throws
  const SolveReport report = solve(A, std::span<const double>(b), std::span<double>(zero_guess), reuse, origin);
  x.swap(zero_guess);
  return report;
}

namespace detail {

KrylovSolverFrame::KrylovSolverFrame(const SolverSettings& settings, Exec exec)
    : settings_(settings),
      exec_device_(exec),
      x0_(work_array(exec)),
      squares_(work_array(exec)),
      b_squares_(work_array(exec)),
      partial_(work_array(exec)) {}

std::string KrylovSolverFrame::name() const {
  return name_of(settings_.backend) + "-" + name_of(settings_.method) + "-" + name_of(settings_.preconditioner);
}

double KrylovSolverFrame::relative_residual(const Exec& exec, const CsrMatrix& A, std::span<const double> b,
                                            std::span<const double> x) {
  return relative_residual_on(exec, A, b, x, squares_, b_squares_, partial_);
}

std::optional<std::string> KrylovSolverFrame::screen(const Exec& exec, const CsrMatrix& A, std::span<const double> b,
                                                     std::span<double> x, SolveReport& report, std::string& notes) {
  const int n = A.rows;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (n == 0) {
    report.converged = true;
    return "empty system";
  }
  if (!all_finite(exec, A.val)) {
    report.relative_residual = nan;
    return "the matrix has NaN or Inf entries: not solved, x unchanged";
  }
  if (!all_finite(exec, b)) {
    report.relative_residual = nan;
    return "the right-hand side has NaN or Inf entries: not solved, x unchanged";
  }
  if (parallel_reduce(exec, n, 0.0, Magnitude{b.data()}, MaxOf{}) == 0) {
    parallel_for(exec, n, SetElements<double>{x.data(), 0.0});
    report.converged = true;
    return "b = 0: x = 0";
  }
  if (!all_finite(exec, x)) {
    parallel_for(exec, n, SetElements<double>{x.data(), 0.0});
    notes = "NaN/Inf initial guess replaced by zero; ";
  }
  return std::nullopt;
}

std::string KrylovSolverFrame::prepare(const CsrMatrix& A, std::span<const double> b, MatrixReuse reuse,
                                       std::span<const Index> origin) {
  if (prepared_ && reuse == MatrixReuse::all && !matrix_stale_) {
    update_rhs(b);
    return "";
  }
  matrix_stale_ = false;
  if (prepared_ && reuse != MatrixReuse::none && refresh_matrix(A, b, origin)) {
    kept_preconditioner_ = true;
    return "";
  }
  if (prepared_) {
    release();
    prepared_ = false;
  }
  struct ReleaseOnThrow {
    KrylovSolverFrame* self;
    bool armed = true;
    ~ReleaseOnThrow() {
      if (armed) self->release();
    }
  } guard{this};
  if (std::string why = setup(A, b); !why.empty()) return why;
  guard.armed = false;
  prepared_ = built_preconditioner_ = true;
  return "";
}

std::string KrylovSolverFrame::iterate_to_tolerance(const Exec& exec, const CsrMatrix& A, std::span<const double> b,
                                                    std::span<double> x, double rel, SolveReport& report) {
  const int n = A.rows;
  const double tol = settings_.tolerance;
  x0_.resize(n);
  parallel_for(exec, n, CopyElements<double>{x.data(), x0_.data()});
  const double eps = std::numeric_limits<double>::epsilon();
  int remaining = settings_.max_iterations;
  std::string last_note;
  constexpr int max_passes = 6;
  int pass = 0;
  for (; pass < max_passes && remaining > 0; ++pass) {
    // Internal tolerance that should bring the true residual below tol: relative to ||b|| it is tol
    // (tightened on later passes, against the drift of recursively updated residuals); relative to the
    // initial residual of the pass it is tol * ||b|| / ||r||.
    double inner =
        tolerance_relative_to_initial_residual() ? tol / rel * (pass == 0 ? 1.0 : 0.5) : tol * std::pow(0.3, pass);
    inner = std::clamp(inner, eps, 0.5);
    const Pass p = iterate(x, inner, remaining);
    report.iterations += p.iterations;
    remaining -= std::max(p.iterations, 1);
    if (!p.note.empty()) last_note = p.note;
    if (!all_finite(exec, x)) {
      parallel_for(exec, n, CopyElements<double>{x0_.data(), x.data()});
      report.converged = false;
      report.relative_residual = relative_residual(exec, A, b, x);
      return "the solver produced NaN/Inf (breakdown or a singular preconditioner" +
             (last_note.empty() ? "" : ": " + last_note) + "); x restored to the initial guess";
    }
    const double previous = rel;
    rel = relative_residual(exec, A, b, x);
    report.relative_residual = rel;
    if (rel <= tol) {
      report.converged = true;
      break;
    }
    // Another pass only while it helps: the first refinement always, later ones on real progress.
    if (pass > 0 && !(rel < 0.5 * previous)) break;
  }
  if (report.converged)
    return "converged in " + std::to_string(report.iterations) + " iterations" +
           (pass > 0 ? " (" + std::to_string(pass + 1) + " passes)" : "");
  std::string why =
      remaining <= 0 ? "iteration limit " + std::to_string(settings_.max_iterations) + " reached" : "stagnated";
  return "not converged: " + why + ", relative residual " + sci(rel) + " > tolerance " + sci(tol) +
         (last_note.empty() ? "" : " (" + last_note + ")");
}

SolveReport KrylovSolverFrame::solve(const CsrMatrix& A_in, std::span<const double> b, std::span<double> x,
                                     MatrixReuse reuse, std::span<const Index> origin) {
  const auto start = std::chrono::steady_clock::now();
  // The frame's loops run on the backend's device when the caller's arrays live there (the fluid's, in
  // managed memory), else on the host (a test's or a benchmark's std::vectors).
  const Exec exec = exec_device_.device == Device::cuda && device_accessible(A_in.row_offset.data()) &&
                            device_accessible(A_in.col.data()) && device_accessible(A_in.val.data()) &&
                            device_accessible(b.data()) && device_accessible(x.data())
                        ? exec_device_
                        : Exec{};
  check_system(exec, A_in, b, x);
  if (!origin.empty() && origin.size() != static_cast<std::size_t>(A_in.rows))
    throw std::invalid_argument("linear solver: the row origin has " + std::to_string(origin.size()) +
                                " entries for a matrix of " + std::to_string(A_in.rows) + " rows");
  kept_preconditioner_ = built_preconditioner_ = false;
  if (reuse != MatrixReuse::all) matrix_stale_ = true;  // until prepare() takes this A
  if (reuse == MatrixReuse::none && prepared_) {
    release();
    prepared_ = false;
  }
  SolveReport report;
  const auto done = [&](std::string message) {
    report.message = std::move(message);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
  };
  std::string notes;
  if (const auto ended = screen(exec, A_in, b, x, report, notes)) return done(*ended);

  CsrMatrix sorted;  // on the host: the project's own matrices come sorted
  const bool needs_copy = first(exec, A_in.rows, UnsortedRow{A_in.row_offset.data(), A_in.col.data()}) != kNone;
  if (needs_copy) {
    sorted = canonical(A_in);
    if (exec.device == Device::cuda) {
      make_device_visible(sorted.row_offset);
      make_device_visible(sorted.col);
      make_device_visible(sorted.val);
    }
  }
  const CsrMatrix& A = needs_copy ? sorted : A_in;

  const double rel = relative_residual(exec, A, b, x);
  report.relative_residual = rel;
  if (rel <= settings_.tolerance) {
    report.converged = true;
    return done(notes + "the initial guess meets the tolerance");
  }
  const auto setup_start = std::chrono::steady_clock::now();
  if (std::string why = prepare(A, b, reuse, origin); !why.empty()) return done(notes + "setup failed: " + why);
  report.setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
  return done(notes + iterate_to_tolerance(exec, A, b, x, rel, report));
}

}  // namespace detail
}  // namespace isph
