// hypre backend (built only with ISPH_HAVE_HYPRE): the CSR matrix goes through the IJ interface into
// a ParCSR matrix on MPI_COMM_WORLD (one rank), solved by ParCSR GMRES or BiCGSTAB preconditioned by
// one BoomerAMG V-cycle, by Jacobi (diagonal scaling) or by nothing. MPI and hypre are initialised on
// first use and finalised at exit (MPI only when this file initialised it). Every hypre object made for
// a solve is destroyed when the solve ends.
#include <stdexcept>

#include "poisson/linear_solver.hpp"

#ifdef ISPH_HAVE_HYPRE

// The build links MPI's C library only: keep the deprecated C++ bindings out of mpi.h.
#ifndef OMPI_SKIP_MPICXX
#define OMPI_SKIP_MPICXX 1
#endif
#ifndef MPICH_SKIP_MPICXX
#define MPICH_SKIP_MPICXX 1
#endif
#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
#include <HYPRE_parcsr_mv.h>
#include <mpi.h>

#include <mutex>
#include <numeric>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

static_assert(std::is_same_v<HYPRE_Complex, double> && std::is_same_v<HYPRE_Real, double>,
              "the hypre backend needs a real double-precision hypre build");

namespace isph::detail {
namespace {

// MPI (when nobody else started it) and hypre, initialised once on first use and finalised at exit by
// the destructor of this function-local static.
class HypreRuntime {
 public:
  static void ensure() {
    static HypreRuntime runtime;
    (void)runtime;
  }
  HypreRuntime(const HypreRuntime&) = delete;
  HypreRuntime& operator=(const HypreRuntime&) = delete;

 private:
  HypreRuntime() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      if (MPI_Init(nullptr, nullptr) != MPI_SUCCESS) throw std::runtime_error("linear solver: MPI_Init failed");
      owns_mpi_ = true;
    }
    HYPRE_Init();
  }
  ~HypreRuntime() {
    HYPRE_Finalize();
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (owns_mpi_ && !finalized) MPI_Finalize();
  }
  bool owns_mpi_ = false;
};

std::string describe(HYPRE_Int code) {
  char text[256] = {0};
  HYPRE_DescribeError(code, text);
  return "hypre error " + std::to_string(code) + " (" + text + ")";
}

class HypreSolver final : public KrylovSolverFrame {
 public:
  explicit HypreSolver(const SolverSettings& s) : KrylovSolverFrame(s) {}
  ~HypreSolver() override { release(); }

 protected:
  std::string setup(const CsrMatrix& A, std::span<const double> b) override {
    HypreRuntime::ensure();
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    if (ranks != 1) return "the hypre backend runs on one MPI rank, MPI_COMM_WORLD has " + std::to_string(ranks);
    n_ = A.rows;
    HYPRE_ClearAllErrors();
    build_matrix(A);

    // Vectors.
    make_vector(ij_b_, b_, b.data());
    make_vector(ij_x_, x_, nullptr);
    if (HYPRE_Int e = HYPRE_GetError(); e) return "building the ParCSR system: " + describe(e);

    // Preconditioner.
    HYPRE_PtrToParSolverFcn precond = nullptr, precond_setup = nullptr;
    precond_ = nullptr;
    if (settings_.preconditioner == PreconditionerType::boomeramg) {
      HYPRE_BoomerAMGCreate(&amg_);
      HYPRE_BoomerAMGSetCoarsenType(amg_, 10);  // HMIS
      HYPRE_BoomerAMGSetInterpType(amg_, 6);    // extended+i
      HYPRE_BoomerAMGSetPMaxElmts(amg_, 4);     // interpolation truncated to 4 entries per row
      if (settings_.dimension == 3) {
        // 3D stencils (about 60 neighbours) make the hierarchy dense: a stricter strength of connection
        // and one level of aggressive coarsening (multipass interpolation) halve the 1e6-unknown
        // dam-break PPE's set-up and solve (docs/SOLVERS.md, "Captured PPEs").
        HYPRE_BoomerAMGSetStrongThreshold(amg_, 0.5);
        HYPRE_BoomerAMGSetAggNumLevels(amg_, 1);
        HYPRE_BoomerAMGSetAggInterpType(amg_, 4);
      } else {
        HYPRE_BoomerAMGSetStrongThreshold(amg_, 0.25);
      }
      HYPRE_BoomerAMGSetCycleRelaxType(amg_, 13, 1);  // l1 Gauss-Seidel forward on the way down,
      HYPRE_BoomerAMGSetCycleRelaxType(amg_, 14, 2);  // backward on the way up,
      HYPRE_BoomerAMGSetCycleRelaxType(amg_, 9, 3);   // Gaussian elimination on the coarsest level
      HYPRE_BoomerAMGSetNumSweeps(amg_, 1);
      HYPRE_BoomerAMGSetMaxIter(amg_, 1);  // one V-cycle per application
      HYPRE_BoomerAMGSetTol(amg_, 0.0);
      HYPRE_BoomerAMGSetPrintLevel(amg_, 0);
      precond = HYPRE_BoomerAMGSolve;
      precond_setup = HYPRE_BoomerAMGSetup;
      precond_ = precond;
    } else if (settings_.preconditioner == PreconditionerType::jacobi) {
      precond = HYPRE_ParCSRDiagScale;
      precond_setup = HYPRE_ParCSRDiagScaleSetup;
    }

    // Krylov method; its Setup also sets up the preconditioner.
    make_krylov(precond, precond_setup);
    const HYPRE_Int e = HYPRE_GetError();
    HYPRE_ClearAllErrors();
    if (e) return "setting up " + name_of(settings_.preconditioner) + ": " + describe(e);
    return "";
  }

  // A new matrix of the same size under the BoomerAMG hierarchy of the last setup: the matrix that
  // hierarchy was built from is kept alive beside the new one, and the new Krylov solver takes the
  // hierarchy as it is (a set-up function that does nothing). Only for BoomerAMG, whose set-up is most
  // of a small system's solve (docs/SOLVERS.md). Rows that moved (an origin) need a new hierarchy.
  bool refresh_matrix(const CsrMatrix& A, std::span<const double> b, std::span<const Index> origin) override {
    if (!amg_ || A.rows != n_ || !origin.empty()) return false;
    (gmres() ? HYPRE_ParCSRGMRESDestroy : HYPRE_ParCSRBiCGSTABDestroy)(krylov_);
    krylov_ = nullptr;
    if (setup_ij_A_)
      HYPRE_IJMatrixDestroy(ij_A_);  // a refreshed matrix: the setup's stays
    else
      setup_ij_A_ = ij_A_;
    ij_A_ = nullptr;
    HYPRE_ClearAllErrors();
    build_matrix(A);
    update_rhs(b);
    make_krylov(precond_, keep_hierarchy);
    const HYPRE_Int e = HYPRE_GetError();
    HYPRE_ClearAllErrors();
    return e == 0;
  }

  Pass iterate(std::span<double> x, double tol, int max_iterations) override {
    HYPRE_IJVectorSetValues(ij_x_, n_, rows_.data(), x.data());
    HYPRE_IJVectorAssemble(ij_x_);
    HYPRE_Int iterations = 0, code = 0;
    if (gmres()) {
      HYPRE_ParCSRGMRESSetTol(krylov_, tol);
      HYPRE_ParCSRGMRESSetMaxIter(krylov_, max_iterations);
      code = HYPRE_ParCSRGMRESSolve(krylov_, A_, b_, x_);
      HYPRE_ParCSRGMRESGetNumIterations(krylov_, &iterations);
    } else {
      HYPRE_ParCSRBiCGSTABSetTol(krylov_, tol);
      HYPRE_ParCSRBiCGSTABSetMaxIter(krylov_, max_iterations);
      code = HYPRE_ParCSRBiCGSTABSolve(krylov_, A_, b_, x_);
      HYPRE_ParCSRBiCGSTABGetNumIterations(krylov_, &iterations);
    }
    HYPRE_ClearAllErrors();
    HYPRE_IJVectorGetValues(ij_x_, n_, rows_.data(), x.data());
    Pass p;
    p.iterations = iterations;
    p.claimed_converged = code == 0;
    if (code && !HYPRE_CheckError(code, HYPRE_ERROR_CONV)) p.note = describe(code);
    return p;
  }

  void update_rhs(std::span<const double> b) override {
    HYPRE_IJVectorSetValues(ij_b_, n_, rows_.data(), b.data());
    HYPRE_IJVectorAssemble(ij_b_);
    HYPRE_IJVectorGetObject(ij_b_, reinterpret_cast<void**>(&b_));
  }

  void release() override {
    if (krylov_) (gmres() ? HYPRE_ParCSRGMRESDestroy : HYPRE_ParCSRBiCGSTABDestroy)(krylov_);
    if (amg_) HYPRE_BoomerAMGDestroy(amg_);
    if (ij_x_) HYPRE_IJVectorDestroy(ij_x_);
    if (ij_b_) HYPRE_IJVectorDestroy(ij_b_);
    if (ij_A_) HYPRE_IJMatrixDestroy(ij_A_);
    if (setup_ij_A_) HYPRE_IJMatrixDestroy(setup_ij_A_);
    krylov_ = amg_ = nullptr;
    ij_x_ = ij_b_ = nullptr;
    ij_A_ = setup_ij_A_ = nullptr;
    A_ = nullptr;
    b_ = x_ = nullptr;
    rows_ = {};
  }

  // hypre's GMRES and BiCGSTAB stop on ||r|| <= tol ||b||.
  bool tolerance_relative_to_initial_residual() const override { return false; }

 private:
  bool gmres() const { return settings_.method == KrylovMethod::gmres; }

  // A set-up that keeps the hierarchy as it is (refresh_matrix).
  static HYPRE_Int keep_hierarchy(HYPRE_Solver, HYPRE_ParCSRMatrix, HYPRE_ParVector, HYPRE_ParVector) { return 0; }

  // The ParCSR copy of A. BoomerAMG and the Jacobi scaling take the first entry of each ParCSR row as
  // its diagonal, which hypre guarantees only for rows that store one: explicit zeros are added where
  // it is missing.
  void build_matrix(const CsrMatrix& A) {
    const MPI_Comm comm = MPI_COMM_WORLD;
    const int n = A.rows;
    HYPRE_IJMatrixCreate(comm, 0, n - 1, 0, n - 1, &ij_A_);
    HYPRE_IJMatrixSetObjectType(ij_A_, HYPRE_PARCSR);
    std::vector<HYPRE_Int> ncols(n), offd(n, 0);
    bool has_all_diagonals = true;
    for (int i = 0; i < n; ++i) {
      ncols[i] = A.row_offset[i + 1] - A.row_offset[i];
      bool diag = false;
      for (int k = A.row_offset[i]; k < A.row_offset[i + 1] && !diag; ++k) diag = A.col[k] == i;
      if (!diag) {
        has_all_diagonals = false;
        ++ncols[i];
      }
    }
    HYPRE_IJMatrixSetDiagOffdSizes(ij_A_, ncols.data(), offd.data());
    HYPRE_IJMatrixInitialize(ij_A_);
    rows_.resize(n);
    std::iota(rows_.begin(), rows_.end(), HYPRE_BigInt{0});
    if (has_all_diagonals && std::is_same_v<HYPRE_BigInt, int>) {
      HYPRE_IJMatrixSetValues(ij_A_, n, ncols.data(), rows_.data(), reinterpret_cast<const HYPRE_BigInt*>(A.col.data()),
                              A.val.data());
    } else {
      std::vector<HYPRE_BigInt> cols;
      std::vector<double> vals;
      cols.reserve(A.col.size() + n);
      vals.reserve(A.col.size() + n);
      for (int i = 0; i < n; ++i) {
        bool diag = false;
        for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) {
          cols.push_back(A.col[k]);
          vals.push_back(A.val[k]);
          diag = diag || A.col[k] == i;
        }
        if (!diag) {
          cols.push_back(i);
          vals.push_back(0.0);
        }
      }
      HYPRE_IJMatrixSetValues(ij_A_, n, ncols.data(), rows_.data(), cols.data(), vals.data());
    }
    HYPRE_IJMatrixAssemble(ij_A_);
    HYPRE_IJMatrixGetObject(ij_A_, reinterpret_cast<void**>(&A_));
  }

  // The Krylov method over A_, preconditioned by `precond` (none: unpreconditioned); its Setup calls
  // precond_setup.
  void make_krylov(HYPRE_PtrToParSolverFcn precond, HYPRE_PtrToParSolverFcn precond_setup) {
    const MPI_Comm comm = MPI_COMM_WORLD;
    if (gmres()) {
      HYPRE_ParCSRGMRESCreate(comm, &krylov_);
      HYPRE_ParCSRGMRESSetKDim(krylov_, settings_.gmres_restart);
      HYPRE_ParCSRGMRESSetTol(krylov_, settings_.tolerance);
      HYPRE_ParCSRGMRESSetMaxIter(krylov_, settings_.max_iterations);
      HYPRE_ParCSRGMRESSetPrintLevel(krylov_, 0);
      HYPRE_ParCSRGMRESSetLogging(krylov_, 0);
      if (precond) HYPRE_ParCSRGMRESSetPrecond(krylov_, precond, precond_setup, amg_);
      HYPRE_ParCSRGMRESSetup(krylov_, A_, b_, x_);
    } else {
      HYPRE_ParCSRBiCGSTABCreate(comm, &krylov_);
      HYPRE_ParCSRBiCGSTABSetTol(krylov_, settings_.tolerance);
      HYPRE_ParCSRBiCGSTABSetMaxIter(krylov_, settings_.max_iterations);
      HYPRE_ParCSRBiCGSTABSetPrintLevel(krylov_, 0);
      HYPRE_ParCSRBiCGSTABSetLogging(krylov_, 0);
      if (precond) HYPRE_ParCSRBiCGSTABSetPrecond(krylov_, precond, precond_setup, amg_);
      HYPRE_ParCSRBiCGSTABSetup(krylov_, A_, b_, x_);
    }
  }

  void make_vector(HYPRE_IJVector& ij, HYPRE_ParVector& par, const double* values) {
    HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, n_ - 1, &ij);
    HYPRE_IJVectorSetObjectType(ij, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(ij);
    if (values) HYPRE_IJVectorSetValues(ij, n_, rows_.data(), values);
    HYPRE_IJVectorAssemble(ij);
    HYPRE_IJVectorGetObject(ij, reinterpret_cast<void**>(&par));
  }

  int n_ = 0;
  std::vector<HYPRE_BigInt> rows_;
  HYPRE_IJMatrix ij_A_ = nullptr,
                 setup_ij_A_ = nullptr;  // the matrix, and the one BoomerAMG was set up from (when refreshed)
  HYPRE_PtrToParSolverFcn precond_ = nullptr;
  HYPRE_IJVector ij_b_ = nullptr, ij_x_ = nullptr;
  HYPRE_ParCSRMatrix A_ = nullptr;
  HYPRE_ParVector b_ = nullptr, x_ = nullptr;
  HYPRE_Solver amg_ = nullptr, krylov_ = nullptr;
};

}  // namespace

std::unique_ptr<LinearSolver> make_hypre_solver(const SolverSettings& s) { return std::make_unique<HypreSolver>(s); }

}  // namespace isph::detail

#else  // !ISPH_HAVE_HYPRE

namespace isph::detail {
std::unique_ptr<LinearSolver> make_hypre_solver(const SolverSettings&) {
  throw std::invalid_argument(
      "linear solver: backend 'hypre' was requested but this build has no hypre (ISPH_HAVE_HYPRE is not defined)");
}
}  // namespace isph::detail

#endif  // ISPH_HAVE_HYPRE
