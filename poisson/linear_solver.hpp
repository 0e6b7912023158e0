// Sparse linear solvers for the pressure Poisson equation, behind one small interface.
//
// Backends (docs/SOLVERS.md):
//   eigen : Eigen 3.4 BiCGSTAB or restarted GMRES, preconditioned by Jacobi, ILUT or nothing.
//   hypre : hypre ParCSR BiCGSTAB or GMRES, preconditioned by one BoomerAMG V-cycle, Jacobi or
//           nothing (only when the build found hypre + MPI: ISPH_HAVE_HYPRE).
//   native: the project's BiCGSTAB (poisson/krylov.hpp) on the host, preconditioned by Jacobi, a
//           Jacobi polynomial, smoothed-aggregation AMG (poisson/aggregation_amg.hpp) or nothing.
//   cuda  : the same BiCGSTAB on the GPU: cuSPARSE SpMV, cuBLAS dot products (only in builds with the
//           CUDA backend, and only when a device is visible).
// Every backend reports the TRUE relative residual ||b - A x|| / ||b||, recomputed from the CSR
// matrix after the solve, and calls the solve converged only when that residual meets the tolerance.
// The frame's passes over the matrix and the vectors (checks, residuals) are launcher loops on the
// backend's device, so that the cuda backend's arrays stay where they are; their sums are taken in
// fixed blocks and the block sums in order, so they do not depend on the threads or the device.
// The caller's arrays come as StateVectors and spans, not std::vectors, because the fluid solver may
// keep them in CUDA managed memory (core/device_memory.hpp).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/device_memory.hpp"
#include "core/enum_names.hpp"
#include "core/parallel.hpp"

namespace isph {

// Square sparse matrix in compressed sparse row form: the entries of row i are
// col[row_offset[i] .. row_offset[i+1]) and val[...]. Columns need not be sorted within a row;
// duplicate (row, col) entries are summed. The arrays are in host or managed memory (StateVector).
struct CsrMatrix {
  int rows = 0;
  StateVector<int> row_offset;
  StateVector<int> col;
  StateVector<double> val;
};

// The backends, Krylov methods and preconditioners, by the names a case file gives them.
enum class SolverBackend { eigen, hypre, native, cuda };
constexpr EnumName<SolverBackend> kSolverBackendNames[] = {{SolverBackend::eigen, "eigen"},
                                                           {SolverBackend::hypre, "hypre"},
                                                           {SolverBackend::native, "native"},
                                                           {SolverBackend::cuda, "cuda"}};
constexpr std::span<const EnumName<SolverBackend>> enum_names(SolverBackend) { return kSolverBackendNames; }

enum class KrylovMethod { bicgstab, gmres };
constexpr EnumName<KrylovMethod> kKrylovMethodNames[] = {{KrylovMethod::bicgstab, "bicgstab"},
                                                         {KrylovMethod::gmres, "gmres"}};
constexpr std::span<const EnumName<KrylovMethod>> enum_names(KrylovMethod) { return kKrylovMethodNames; }

enum class PreconditionerType { ilu, jacobi, none, boomeramg, polynomial, amg };
constexpr EnumName<PreconditionerType> kPreconditionerTypeNames[] = {{PreconditionerType::ilu, "ilu"},
                                                                     {PreconditionerType::jacobi, "jacobi"},
                                                                     {PreconditionerType::none, "none"},
                                                                     {PreconditionerType::boomeramg, "boomeramg"},
                                                                     {PreconditionerType::polynomial, "polynomial"},
                                                                     {PreconditionerType::amg, "amg"}};
constexpr std::span<const EnumName<PreconditionerType>> enum_names(PreconditionerType) {
  return kPreconditionerTypeNames;
}

struct SolverSettings {
  SolverBackend backend = SolverBackend::eigen;
  KrylovMethod method = KrylovMethod::bicgstab;                 // gmres: eigen and hypre only
  PreconditionerType preconditioner = PreconditionerType::ilu;  // solver_preconditioners(backend)
  double tolerance = 1e-8;                                      // relative residual ||b - Ax|| / ||b||
  int max_iterations = 1000;  // Krylov iterations in total (over restarts and refinement passes)
  int gmres_restart = 50;     // Krylov subspace dimension of GMRES
  int dimension = 2;          // the PPE's space dimension: BoomerAMG's coarsening (docs/SOLVERS.md)
};

struct SolveReport {
  bool converged = false;
  int iterations = 0;
  double relative_residual = 0;  // true ||b - A x|| / ||b|| of the returned x (||b - A x|| when b = 0)
  double seconds = 0;            // wall time of the whole call: copies, preconditioner setup, solve
  double setup_seconds = 0;      // the part of it spent copying A and b in and building the preconditioner
  std::string message;
};

// What a solve may keep from the solver's previous call (LinearSolver::solve).
//  none:           A is new: a new copy and a new preconditioner.
//  preconditioner: A is new, but close to the matrix the last preconditioner was built for (the next
//                  step's PPE): the backend takes the new A and may keep that preconditioner (hypre's
//                  BoomerAMG hierarchy, the native and cuda AMG's); a backend that cannot builds a new
//                  one. A's rows are that matrix's, or, with a row origin (solve), continue its rows as
//                  the origin says (particles re-sorted, created, removed): only the native and cuda
//                  AMG keep their hierarchy then.
//  all:            A is the matrix of the previous call; only b changed.
enum class MatrixReuse { none, preconditioner, all };

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  // Solves A x = b; x (A.rows entries: a span cannot grow) holds the initial guess on entry. Never
  // throws on non-convergence, breakdown, NaN or Inf: reports it (converged=false, residual,
  // iterations, message). Throws std::invalid_argument on a malformed matrix or mismatched sizes.
  // b = 0 gives x = 0. A non-finite initial guess is replaced by zero. When the solver produces a
  // non-finite x, x is restored to the initial guess and the report says so.
  // reuse: what the call may keep from the previous one (MatrixReuse). origin (with
  // MatrixReuse::preconditioner; empty, or A.rows entries in the caller's memory): for each row of A,
  // the row of the kept preconditioner's matrix it continues, or -1 for a new row.
  virtual SolveReport solve(const CsrMatrix& A, std::span<const double> b, std::span<double> x,
                            MatrixReuse reuse = MatrixReuse::none, std::span<const Index> origin = {}) = 0;
  // The same for std::vectors, where an empty x means a zero guess (x is then resized to A.rows).
  SolveReport solve(const CsrMatrix& A, const std::vector<double>& b, std::vector<double>& x,
                    MatrixReuse reuse = MatrixReuse::none, std::span<const Index> origin = {});
  // Whether the last solve kept an earlier preconditioner for a new matrix (MatrixReuse::preconditioner),
  // and whether it built a new one (neither: it took the last call's set-up, or ended before iterating).
  virtual bool kept_preconditioner() const { return false; }
  virtual bool built_preconditioner() const { return false; }
  // The relative residual the following solves must reach (SolverSettings::tolerance at construction).
  virtual void set_tolerance(double tolerance) = 0;
  virtual double tolerance() const = 0;
  virtual std::string name() const = 0;  // e.g. "eigen-bicgstab-ilu", "hypre-gmres-boomeramg"
};

// Throws std::invalid_argument naming an option the backend does not offer and the ones it does; asking
// for hypre in a build without it (ISPH_HAVE_HYPRE undefined) is also an std::invalid_argument that says
// so, and so is asking for cuda in a build without the CUDA backend or on a machine without a visible
// device.
std::unique_ptr<LinearSolver> make_linear_solver(const SolverSettings&);

// What each backend offers: its Krylov methods and its preconditioners, the first being the default
// (ilu for eigen, boomeramg for hypre, jacobi for native and cuda).
const std::vector<KrylovMethod>& solver_methods(SolverBackend backend);
const std::vector<PreconditionerType>& solver_preconditioners(SolverBackend backend);

// True when this build contains the hypre backend.
bool hypre_available();

// Throws std::invalid_argument unless A is a well-formed square CSR matrix (offsets monotone, columns
// in range) and b and x have A.rows entries.
void check_linear_system(const CsrMatrix& A, std::span<const double> b, std::span<const double> x);

// ||b - A x|| / ||b||, or ||b - A x|| when b = 0 (sizes are assumed checked; host or managed memory).
double relative_residual(const CsrMatrix& A, std::span<const double> b, std::span<const double> x);

namespace detail {

// The frame every backend shares (linear_solver.cpp): argument checks, the trivial cases (empty system,
// b = 0, non-finite input, an initial guess that already meets the tolerance), timing, NaN guards,
// the true residual, and refinement passes: when a backend stops on its own residual estimate but the
// true residual misses the tolerance, the Krylov method is restarted from the current x with a tighter
// internal tolerance, within the remaining iteration budget. A backend supplies setup and one pass.
class KrylovSolverFrame : public LinearSolver {
 public:
  // exec: where the frame's loops run (the backend's device); the caller's arrays must be readable there.
  explicit KrylovSolverFrame(const SolverSettings& settings, Exec exec = {});
  using LinearSolver::solve;  // the std::vector overload
  SolveReport solve(const CsrMatrix& A, std::span<const double> b, std::span<double> x,
                    MatrixReuse reuse = MatrixReuse::none, std::span<const Index> origin = {}) final;
  std::string name() const final;
  bool kept_preconditioner() const final { return kept_preconditioner_; }
  bool built_preconditioner() const final { return built_preconditioner_; }
  void set_tolerance(double tolerance) final { settings_.tolerance = tolerance; }
  double tolerance() const final { return settings_.tolerance; }

 protected:
  struct Pass {
    int iterations = 0;
    bool claimed_converged = false;  // the backend's own stopping test was met
    std::string note;                // why it stopped otherwise (breakdown, ...), or empty
  };
  // Copies A (columns sorted within each row, no duplicates, all values finite) and b into the
  // backend and builds the preconditioner. Returns an empty string, or why the setup failed.
  // b and x below are the caller's (host or managed memory), A.rows entries each.
  virtual std::string setup(const CsrMatrix& A, std::span<const double> b) = 0;
  // Replaces b, keeping A and the preconditioner of the last setup.
  virtual void update_rhs(std::span<const double> b) = 0;
  // Replaces A and b, keeping the preconditioner of the last setup; A's rows are the last matrix's, or
  // continue them as origin says (LinearSolver::solve). False where the backend cannot (the frame then
  // releases and sets up afresh).
  virtual bool refresh_matrix(const CsrMatrix&, std::span<const double>, std::span<const Index>) { return false; }
  // Runs the Krylov method from x (in/out) until its own residual estimate falls below tol (relative
  // to ||b||, or to the initial residual of this pass when tolerance_relative_to_initial_residual())
  // or after max_iterations iterations.
  virtual Pass iterate(std::span<double> x, double tol, int max_iterations) = 0;
  // Frees what setup() made; called before the next setup and when a setup failed or threw (the
  // setup is kept between solves for same_matrix calls).
  virtual void release() = 0;
  virtual bool tolerance_relative_to_initial_residual() const = 0;

  SolverSettings settings_;

 private:
  // The checks before any iteration: a solve that ends there (an empty system, non-finite A or b,
  // b = 0) gets its message; a non-finite initial guess is replaced by zero and noted.
  std::optional<std::string> screen(const Exec& exec, const CsrMatrix& A, std::span<const double> b,
                                    std::span<double> x, SolveReport& report, std::string& notes);
  // The backend's set-up for A and b as `reuse` allows; why it failed, or an empty string.
  std::string prepare(const CsrMatrix& A, std::span<const double> b, MatrixReuse reuse, std::span<const Index> origin);
  // The Krylov passes from x to the tolerance, from the relative residual `rel` of x; the closing message.
  std::string iterate_to_tolerance(const Exec& exec, const CsrMatrix& A, std::span<const double> b, std::span<double> x,
                                   double rel, SolveReport& report);
  double relative_residual(const Exec& exec, const CsrMatrix& A, std::span<const double> b, std::span<const double> x);

  bool prepared_ = false;      // a setup() is in place
  bool matrix_stale_ = false;  // the last solve's A is not the one set up (it ended before prepare())
  bool kept_preconditioner_ = false, built_preconditioner_ = false;
  Exec exec_device_;                                        // the backend's device
  StateVector<double> x0_, squares_, b_squares_, partial_;  // the initial guess; the residual's work arrays
};

}  // namespace detail
}  // namespace isph
