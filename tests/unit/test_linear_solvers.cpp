// Linear solver backends (poisson/linear_solver.hpp) on a manufactured PPE-like system: a non-symmetric
// 2D convection-diffusion M-matrix with Dirichlet identity rows (free-surface particles), b = A x*.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "core/device_memory.hpp"
#include "poisson/cuda_solver.hpp"
#include "poisson/linear_solver.hpp"
#include "poisson/manufactured_system.hpp"

using namespace isph;

namespace {

// The 9-point manufactured system (poisson/manufactured_system.hpp).
ManufacturedSystem manufactured(int n) { return manufactured_ppe_system(n, 9); }

// Settings by the names a case file gives them.
SolverSettings settings(const std::string& backend, const std::string& method, const std::string& precond,
                        double tol = 1e-10) {
  SolverSettings s;
  s.backend = *enum_from_name<SolverBackend>(backend);
  s.method = *enum_from_name<KrylovMethod>(method);
  s.preconditioner = *enum_from_name<PreconditionerType>(precond);
  s.tolerance = tol;
  s.max_iterations = 2000;
  return s;
}

struct Combination {
  std::string backend, method, preconditioner;
};

// Names the combination in test output (instead of the parameter's bytes).
void PrintTo(const Combination& c, std::ostream* os) { *os << c.backend << "-" << c.method << "-" << c.preconditioner; }

std::vector<Combination> all_combinations() {
  std::vector<Combination> c;
  for (const SolverBackend backend : {SolverBackend::eigen, SolverBackend::hypre, SolverBackend::native})
    for (const auto method : solver_methods(backend))
      for (const auto p : solver_preconditioners(backend)) c.push_back({name_of(backend), name_of(method), name_of(p)});
  return c;
}

std::string expect_invalid(const SolverSettings& s) {
  try {
    make_linear_solver(s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::invalid_argument for " << name_of(s.backend) << "/" << name_of(s.method) << "/"
                << name_of(s.preconditioner);
  return "";
}

long resident_kib() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Every backend / method / preconditioner (hypre skipped when not built).
class LinearSolverCombination : public ::testing::TestWithParam<Combination> {};

TEST_P(LinearSolverCombination, RecoversTheManufacturedSolution) {
  const auto& c = GetParam();
  if (c.backend == "hypre" && !hypre_available()) GTEST_SKIP() << "hypre not built";
  const auto m = manufactured(40);
  auto solver = make_linear_solver(settings(c.backend, c.method, c.preconditioner));
  EXPECT_EQ(solver->name(), c.backend + "-" + c.method + "-" + c.preconditioner);
  std::vector<double> x(m.b.size(), 0.0);
  const auto r = solver->solve(m.A, m.b, x);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_GT(r.iterations, 0);
  EXPECT_LE(r.relative_residual, 1e-10);
  EXPECT_NEAR(r.relative_residual, relative_residual(m.A, m.b, x), 1e-15);
  EXPECT_LT(relative_difference(x, m.x_star), 1e-7) << r.message;
  EXPECT_GE(r.seconds, 0.0);

  // Starting from the answer costs no iteration; a second solve with the same object works the same.
  std::vector<double> again = m.x_star;
  const auto r2 = solver->solve(m.A, m.b, again);
  EXPECT_TRUE(r2.converged);
  EXPECT_EQ(r2.iterations, 0);
  std::vector<double> guess(m.x_star.size());  // a non-zero initial guess is used
  for (std::size_t i = 0; i < guess.size(); ++i) guess[i] = m.x_star[i] * (1.0 + 0.01 * std::sin(0.1 * i));
  const auto r4 = solver->solve(m.A, m.b, guess);
  EXPECT_TRUE(r4.converged) << r4.message;
  EXPECT_LT(relative_difference(guess, m.x_star), 1e-7);
  EXPECT_LE(r4.iterations, r.iterations + 5);

  std::vector<double> fresh;  // empty: zero initial guess
  const auto r3 = solver->solve(m.A, m.b, fresh);
  EXPECT_TRUE(r3.converged) << r3.message;
  EXPECT_EQ(r3.iterations, r.iterations);
  EXPECT_LT(relative_difference(fresh, x), 1e-12);

  // Same matrix, another right-hand side (the coupled step's interface iterations): the set-up of the
  // last solve is reused and the answer is that of the new b.
  std::vector<double> x2_star(m.x_star.size()), b2(m.b.size(), 0.0);
  for (std::size_t i = 0; i < x2_star.size(); ++i) x2_star[i] = std::cos(0.05 * static_cast<double>(i));
  for (int i = 0; i < m.A.rows; ++i)
    for (int k = m.A.row_offset[i]; k < m.A.row_offset[i + 1]; ++k) b2[i] += m.A.val[k] * x2_star[m.A.col[k]];
  std::vector<double> x2 = x;
  const auto r5 = solver->solve(m.A, b2, x2, MatrixReuse::all);
  EXPECT_TRUE(r5.converged) << r5.message;
  EXPECT_LT(relative_difference(x2, x2_star), 1e-7) << r5.message;
}

INSTANTIATE_TEST_SUITE_P(LinearSolverAll, LinearSolverCombination, ::testing::ValuesIn(all_combinations()),
                         [](const ::testing::TestParamInfo<Combination>& info) {
                           return info.param.backend + "_" + info.param.method + "_" + info.param.preconditioner;
                         });

// The acceptance criterion: Eigen BiCGSTAB and hypre BoomerAMG-GMRES agree to 1e-8.
TEST(LinearSolver, EigenBicgstabAndHypreAmgGmresAgree) {
  if (!hypre_available()) GTEST_SKIP() << "hypre not built";
  const auto m = manufactured(48);
  std::vector<double> xe(m.b.size(), 0.0), xh(m.b.size(), 0.0);
  const auto re = make_linear_solver(settings("eigen", "bicgstab", "ilu", 1e-12))->solve(m.A, m.b, xe);
  const auto rh = make_linear_solver(settings("hypre", "gmres", "boomeramg", 1e-12))->solve(m.A, m.b, xh);
  ASSERT_TRUE(re.converged) << re.message;
  ASSERT_TRUE(rh.converged) << rh.message;
  EXPECT_LT(relative_difference(xh, xe), 1e-8);
  EXPECT_LT(relative_difference(xe, m.x_star), 1e-8);
}

// ---------------------------------------------------------------------------------------------------
TEST(LinearSolverFactory, DefaultsAndNames) {
  EXPECT_EQ(make_linear_solver({})->name(), "eigen-bicgstab-ilu");
  if (hypre_available()) {
    EXPECT_EQ(make_linear_solver(settings("hypre", "gmres", "boomeramg"))->name(), "hypre-gmres-boomeramg");
  }
}

// Unknown names are the case loader's to refuse (CaseLoaderTest); the factory refuses what a backend
// does not offer.
TEST(LinearSolverFactory, BadOptionsThrowNamingTheOption) {
  auto s = SolverSettings{};
  s.preconditioner = PreconditionerType::boomeramg;  // an hypre preconditioner asked of Eigen
  auto msg = expect_invalid(s);
  EXPECT_NE(msg.find("preconditioner 'boomeramg'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("ilu, jacobi, none"), std::string::npos) << msg;

  s = settings("hypre", "gmres", "ilu");
  msg = expect_invalid(s);
  EXPECT_NE(msg.find("preconditioner 'ilu'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("boomeramg, jacobi, none"), std::string::npos) << msg;

  s = {};
  s.tolerance = 0;
  EXPECT_NE(expect_invalid(s).find("tolerance"), std::string::npos);
  s = {};
  s.max_iterations = 0;
  EXPECT_NE(expect_invalid(s).find("max_iterations"), std::string::npos);
  s = {};
  s.gmres_restart = 0;
  EXPECT_NE(expect_invalid(s).find("gmres_restart"), std::string::npos);
}

TEST(LinearSolverFactory, OwnKrylovBackendsOfferBicgstabWithTheirPreconditioners) {
  EXPECT_EQ(make_linear_solver(settings("native", "bicgstab", "polynomial"))->name(), "native-bicgstab-polynomial");
  auto msg = expect_invalid(settings("native", "gmres", "jacobi"));
  EXPECT_NE(msg.find("method 'gmres' for backend 'native'"), std::string::npos) << msg;
  msg = expect_invalid(settings("native", "bicgstab", "ilu"));
  EXPECT_NE(msg.find("jacobi, polynomial, amg, none"), std::string::npos) << msg;
  msg = expect_invalid(settings("cuda", "bicgstab", "boomeramg"));
  EXPECT_NE(msg.find("preconditioner 'boomeramg' for backend 'cuda'"), std::string::npos) << msg;
}

// Without a device (or without the CUDA backend) asking for cuda is an error that says which.
TEST(LinearSolverFactory, CudaWithoutADeviceIsAClearError) {
  if (cuda_devices() > 0) GTEST_SKIP() << "a CUDA device is visible";
  const auto msg = expect_invalid(settings("cuda", "bicgstab", "jacobi"));
  EXPECT_TRUE(msg.find("none is visible") != std::string::npos || msg.find("no CUDA backend") != std::string::npos)
      << msg;
}

// The native backend runs the same BiCGSTAB as Eigen's (van der Vorst's), so with the same Jacobi
// preconditioner it needs about the same iterations; the polynomial preconditioner (three damped
// Jacobi sweeps) needs fewer.
TEST(LinearSolver, NativeBicgstabMatchesEigenAndThePolynomialPreconditionerHelps) {
  const auto m = manufactured_ppe_system(80, 21);
  const auto run = [&](const std::string& backend, const std::string& precond) {
    std::vector<double> x;
    const auto r = make_linear_solver(settings(backend, "bicgstab", precond, 1e-8))->solve(m.A, m.b, x);
    EXPECT_TRUE(r.converged) << backend << "-" << precond << ": " << r.message;
    EXPECT_LT(relative_difference(x, m.x_star), 1e-6) << backend << "-" << precond;
    return r.iterations;
  };
  const int eigen_jacobi = run("eigen", "jacobi"), native_jacobi = run("native", "jacobi"),
            native_polynomial = run("native", "polynomial");
  EXPECT_NEAR(native_jacobi, eigen_jacobi, 0.15 * eigen_jacobi);
  EXPECT_LT(native_polynomial, 0.7 * native_jacobi);
}

// One solver object through systems of changing size and matrices (its work vectors are kept between
// matrices of the same size): every answer is that of its own system.
TEST(LinearSolver, NativeSolverFollowsChangingSystems) {
  for (const auto p : solver_preconditioners(SolverBackend::native)) {
    const std::string preconditioner = name_of(p);
    auto solver = make_linear_solver(settings("native", "bicgstab", preconditioner));
    for (int n : {30, 20, 30, 31}) {
      const auto m = manufactured(n);
      std::vector<double> x;
      const auto r = solver->solve(m.A, m.b, x);
      EXPECT_TRUE(r.converged) << preconditioner << " n = " << n << ": " << r.message;
      EXPECT_LT(relative_difference(x, m.x_star), 1e-7) << preconditioner << " n = " << n;
    }
  }
}

TEST(LinearSolverFactory, HypreWithoutHypreIsAClearError) {
  if (hypre_available()) GTEST_SKIP() << "hypre is built";
  const auto msg = expect_invalid(settings("hypre", "gmres", "boomeramg"));
  EXPECT_NE(msg.find("no hypre"), std::string::npos) << msg;
}

// ---------------------------------------------------------------------------------------------------
TEST(LinearSolver, BadSizesThrow) {
  const auto m = manufactured(8);
  auto solver = make_linear_solver({});
  std::vector<double> x(m.b.size(), 0.0);
  auto short_b = m.b;
  short_b.pop_back();
  EXPECT_THROW(solver->solve(m.A, short_b, x), std::invalid_argument);
  std::vector<double> long_x(m.b.size() + 1, 0.0);
  EXPECT_THROW(solver->solve(m.A, m.b, long_x), std::invalid_argument);
  auto bad = m.A;
  bad.row_offset.pop_back();
  EXPECT_THROW(solver->solve(bad, m.b, x), std::invalid_argument);
  bad = m.A;
  bad.col[3] = bad.rows;
  EXPECT_THROW(solver->solve(bad, m.b, x), std::invalid_argument);
  bad = m.A;
  bad.val.pop_back();
  EXPECT_THROW(solver->solve(bad, m.b, x), std::invalid_argument);
}

// The span interface, called with StateVectors as a solver that keeps its arrays in them does (host
// memory here): the answer of the std::vector overload. A span x must have A.rows entries; an empty
// std::vector x is resized only once the system has passed the checks.
TEST(LinearSolver, SpansOfStateVectorsSolveAsVectorsDo) {
  const auto m = manufactured(20);
  const StateVector<double> b(m.b.begin(), m.b.end());
  for (const auto& c : all_combinations()) {
    if (c.backend == "hypre" && !hypre_available()) continue;
    std::vector<double> x_vector;
    const auto rv = make_linear_solver(settings(c.backend, c.method, c.preconditioner))->solve(m.A, m.b, x_vector);
    StateVector<double> x(b.size(), 0.0);
    const auto rs = make_linear_solver(settings(c.backend, c.method, c.preconditioner))
                        ->solve(m.A, std::span<const double>(b), std::span<double>(x));
    EXPECT_TRUE(rs.converged) << c.backend << c.method << c.preconditioner << ": " << rs.message;
    EXPECT_EQ(rs.iterations, rv.iterations) << c.backend << c.method << c.preconditioner;
    EXPECT_LT(relative_difference(std::vector<double>(x.begin(), x.end()), x_vector), 1e-12)
        << c.backend << c.method << c.preconditioner;
  }
  auto solver = make_linear_solver(settings("native", "bicgstab", "jacobi"));
  StateVector<double> empty_x, short_x(b.size() - 1, 0.0);
  EXPECT_THROW(solver->solve(m.A, std::span<const double>(b), std::span<double>(empty_x)), std::invalid_argument);
  EXPECT_THROW(solver->solve(m.A, std::span<const double>(b), std::span<double>(short_x)), std::invalid_argument);
  auto bad = m.A;
  bad.col[3] = bad.rows;
  std::vector<double> x;
  EXPECT_THROW(solver->solve(bad, m.b, x), std::invalid_argument);
  EXPECT_TRUE(x.empty());
}

TEST(LinearSolver, EmptySystemIsTrivial) {
  std::vector<double> b, x;
  const auto r = make_linear_solver({})->solve(CsrMatrix{}, b, x);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 0);
}

TEST(LinearSolver, ZeroRightHandSideGivesZero) {
  const auto m = manufactured(8);
  std::vector<double> b(m.b.size(), 0.0), x(m.b.size(), 3.0);
  for (const auto& c : all_combinations()) {
    if (c.backend == "hypre" && !hypre_available()) continue;
    std::fill(x.begin(), x.end(), 3.0);
    const auto r = make_linear_solver(settings(c.backend, c.method, c.preconditioner))->solve(m.A, b, x);
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(r.relative_residual, 0.0);
    for (double v : x) ASSERT_EQ(v, 0.0);
  }
}

TEST(LinearSolver, UnsortedAndDuplicateEntriesAreSummed) {
  const auto m = manufactured(12);
  // Same matrix with every row reversed and each off-diagonal entry split into two halves.
  CsrMatrix split;
  split.rows = m.A.rows;
  split.row_offset.assign(1, 0);
  for (int i = 0; i < m.A.rows; ++i) {
    for (int k = m.A.row_offset[i + 1] - 1; k >= m.A.row_offset[i]; --k) {
      const int parts = m.A.col[k] == i ? 1 : 2;
      for (int p = 0; p < parts; ++p) {
        split.col.push_back(m.A.col[k]);
        split.val.push_back(m.A.val[k] / parts);
      }
    }
    split.row_offset.push_back(static_cast<int>(split.col.size()));
  }
  for (const auto& c : all_combinations()) {
    if (c.backend == "hypre" && !hypre_available()) continue;
    std::vector<double> x;
    const auto r = make_linear_solver(settings(c.backend, c.method, c.preconditioner))->solve(split, m.b, x);
    EXPECT_TRUE(r.converged) << c.backend << c.method << c.preconditioner << ": " << r.message;
    EXPECT_LT(relative_difference(x, m.x_star), 1e-7) << c.backend << c.method << c.preconditioner;
  }
}

// A singular, inconsistent system (the pure-Neumann Laplacian: no Dirichlet row, b not in the range) is
// reported as not converged, with its iterations and residual, and never throws.
TEST(LinearSolver, SingularSystemIsReportedNotConverged) {
  const int n = 12;
  CsrMatrix A;
  A.rows = n * n;
  A.row_offset.assign(1, 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int row = j * n + i;
      double diag = 0;
      A.col.push_back(row);
      A.val.push_back(0);
      const std::size_t at = A.val.size() - 1;
      for (const auto& [di, dj] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
        if (i + di < 0 || i + di >= n || j + dj < 0 || j + dj >= n) continue;
        const double a = di > 0 ? -1.3 : -0.7;  // non-symmetric, row sums zero
        A.col.push_back(row + di + n * dj);
        A.val.push_back(a);
        diag -= a;
      }
      A.val[at] = diag;
      A.row_offset.push_back(static_cast<int>(A.col.size()));
    }
  std::vector<double> b(A.rows, 0.0);
  b[0] = 1.0;  // inconsistent: the left null vector is positive everywhere
  for (const auto& c : all_combinations()) {
    if (c.backend == "hypre" && !hypre_available()) continue;
    auto s = settings(c.backend, c.method, c.preconditioner, 1e-10);
    s.max_iterations = 200;
    std::vector<double> x(A.rows, 0.0);
    SolveReport r;
    ASSERT_NO_THROW(r = make_linear_solver(s)->solve(A, b, x)) << c.backend << c.method << c.preconditioner;
    EXPECT_FALSE(r.converged) << c.backend << c.method << c.preconditioner;
    EXPECT_FALSE(r.message.empty());
    EXPECT_GE(r.iterations, 0);
    EXPECT_LE(r.iterations, 200);
    EXPECT_TRUE(std::isfinite(r.relative_residual)) << r.message;
    EXPECT_GT(r.relative_residual, 1e-10) << r.message;
    for (double v : x) ASSERT_TRUE(std::isfinite(v)) << r.message;
  }
}

// A zero row (a particle with no equation) cannot be solved: Eigen's ILUT refuses it at set-up, the others
// run out of iterations or break down; all report it.
TEST(LinearSolver, ZeroRowIsReportedNotConverged) {
  auto m = manufactured(10);
  const int row = 5 * 10 + 5;
  for (int k = m.A.row_offset[row]; k < m.A.row_offset[row + 1]; ++k) m.A.val[k] = 0.0;
  m.b[row] = 1.0;
  for (const auto& c : all_combinations()) {
    if (c.backend == "hypre" && !hypre_available()) continue;
    auto s = settings(c.backend, c.method, c.preconditioner);
    s.max_iterations = 100;
    std::vector<double> x(m.b.size(), 0.0);
    SolveReport r;
    ASSERT_NO_THROW(r = make_linear_solver(s)->solve(m.A, m.b, x));
    EXPECT_FALSE(r.converged) << c.backend << c.method << c.preconditioner;
    EXPECT_FALSE(r.message.empty());
    for (double v : x) ASSERT_TRUE(std::isfinite(v)) << r.message;
  }
}

// The own-Krylov backends take D⁻¹ where their copy of the matrix is: a row whose diagonal entry is
// zero makes the Jacobi scalings (jacobi, polynomial, and the AMG's smoother) fail at set-up, naming
// the first such row.
TEST(LinearSolver, ZeroDiagonalNamesTheRowForTheJacobiScalings) {
  auto m = manufactured(10);
  for (int row : {77, 23})
    for (int k = m.A.row_offset[row]; k < m.A.row_offset[row + 1]; ++k)
      if (m.A.col[k] == row) m.A.val[k] = 0.0;
  for (const char* p : {"jacobi", "polynomial", "amg"}) {
    std::vector<double> x(m.b.size(), 0.0);
    const SolveReport r = make_linear_solver(settings("native", "bicgstab", p))->solve(m.A, m.b, x);
    EXPECT_FALSE(r.converged) << p;
    EXPECT_NE(r.message.find("zero diagonal in row 23:"), std::string::npos) << r.message;
  }
}

TEST(LinearSolver, NanOrInfInputIsReportedNotConverged) {
  const auto m = manufactured(8);
  for (const auto& c : all_combinations()) {
    if (c.backend == "hypre" && !hypre_available()) continue;
    auto solver = make_linear_solver(settings(c.backend, c.method, c.preconditioner));
    auto A = m.A;
    A.val[40] = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> x(m.b.size(), 1.0);
    SolveReport r;
    ASSERT_NO_THROW(r = solver->solve(A, m.b, x));
    EXPECT_FALSE(r.converged);
    EXPECT_NE(r.message.find("NaN"), std::string::npos) << r.message;
    for (double v : x) ASSERT_EQ(v, 1.0);

    auto b = m.b;
    b[7] = std::numeric_limits<double>::infinity();
    ASSERT_NO_THROW(r = solver->solve(m.A, b, x));
    EXPECT_FALSE(r.converged);
    EXPECT_NE(r.message.find("Inf"), std::string::npos) << r.message;

    // A NaN initial guess (a diverged previous step) is replaced by zero and the solve goes on.
    std::fill(x.begin(), x.end(), std::numeric_limits<double>::quiet_NaN());
    r = solver->solve(m.A, m.b, x);
    EXPECT_TRUE(r.converged) << r.message;
    EXPECT_LT(relative_difference(x, m.x_star), 1e-7);
  }
}

// Iteration limit: reported, not thrown, with the iterations used.
TEST(LinearSolver, IterationLimitIsReported) {
  const auto m = manufactured(40);
  for (const auto& c : all_combinations()) {
    if (c.backend == "hypre" && !hypre_available()) continue;
    auto s = settings(c.backend, c.method, c.preconditioner, 1e-12);
    s.max_iterations = 2;
    std::vector<double> x(m.b.size(), 0.0);
    const auto r = make_linear_solver(s)->solve(m.A, m.b, x);
    EXPECT_FALSE(r.converged) << c.backend << c.method << c.preconditioner;
    EXPECT_LE(r.iterations, 2);
    EXPECT_GT(r.relative_residual, 1e-12);
    EXPECT_NE(r.message.find("iteration limit"), std::string::npos) << r.message;
  }
}

// Repeated solves destroy what they create: resident memory stays flat.
TEST(LinearSolver, RepeatedHypreSolvesDoNotLeak) {
  if (!hypre_available()) GTEST_SKIP() << "hypre not built";
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer holds freed memory in quarantine (its leak check covers this build)";
#endif
  const auto m = manufactured(64);
  auto solver = make_linear_solver(settings("hypre", "gmres", "boomeramg"));
  std::vector<double> x;
  for (int k = 0; k < 5; ++k) {  // warm-up: allocator pools reach their steady size
    x.clear();
    solver->solve(m.A, m.b, x);
  }
  const long before = resident_kib();
  for (int k = 0; k < 30; ++k) {
    x.clear();
    ASSERT_TRUE(solver->solve(m.A, m.b, x).converged);
  }
  const long grown = resident_kib() - before;
  EXPECT_LT(grown, 4 * 1024) << "resident memory grew by " << grown << " KiB over 30 solves";
}

// The vector CSR kernel's threads per row: about three entries each, a power of two from 2 to 32 (the
// 2D PPE's 21 entries per row get 8; a 3D PPE's 60-80 get 16 to 32).
TEST(VectorCsr, LanesGiveAboutThreeEntriesEach) {
  EXPECT_EQ(vector_csr_lanes(0.0), 2);
  EXPECT_EQ(vector_csr_lanes(5.0), 2);
  EXPECT_EQ(vector_csr_lanes(12.0), 4);
  EXPECT_EQ(vector_csr_lanes(21.0), 8);
  EXPECT_EQ(vector_csr_lanes(60.0), 16);
  EXPECT_EQ(vector_csr_lanes(80.0), 32);
  EXPECT_EQ(vector_csr_lanes(1000.0), 32);
}
