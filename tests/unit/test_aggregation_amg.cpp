// The smoothed-aggregation AMG preconditioner (poisson/aggregation_amg.hpp) on the host: its hierarchy
// (Galerkin coarse matrices, R = P^T, constants interpolated exactly, geometric coarsening with bounded
// complexity), iteration counts that barely grow with the size where Jacobi's do, and results that do
// not depend on the thread count (the property that lets the device run the same loops).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "poisson/aggregation_amg.hpp"
#include "poisson/host_ops.hpp"
#include "poisson/linear_solver.hpp"
#include "poisson/manufactured_system.hpp"

using namespace isph;

namespace {

CsrView view(const CsrMatrix& A) { return {A.rows, A.row_offset.data(), A.col.data(), A.val.data()}; }

std::vector<double> product(const CsrView& A, const std::vector<double>& x) {
  std::vector<double> y(A.rows);
  parallel_for(Exec{}, A.rows, CsrRowProduct{A.row_offset, A.col, A.val, x.data(), y.data()});
  return y;
}

std::map<std::pair<int, int>, double> entries(const CsrView& A) {
  std::map<std::pair<int, int>, double> e;
  for (int i = 0; i < A.rows; ++i)
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) e[{i, A.col[k]}] += A.val[k];
  return e;
}

int solve_iterations(const ManufacturedSystem& m, const std::string& preconditioner) {
  SolverSettings s;
  s.backend = SolverBackend::native;
  s.preconditioner = *enum_from_name<PreconditionerType>(preconditioner);
  s.max_iterations = 3000;
  std::vector<double> x;
  const SolveReport r = make_linear_solver(s)->solve(m.A, m.b, x);
  EXPECT_TRUE(r.converged) << preconditioner << ": " << r.message;
  EXPECT_LT(relative_difference(x, m.x_star), 1e-6) << preconditioner;
  return r.iterations;
}

// The native AMG and, where the build has it, hypre's BoomerAMG, each solving to 1e-8.
std::vector<SolverSettings> amg_solvers() {
  std::vector<SolverSettings> out;
  for (const auto& [backend, preconditioner] : {std::pair{SolverBackend::native, PreconditionerType::amg},
                                                std::pair{SolverBackend::hypre, PreconditionerType::boomeramg}}) {
    if (backend == SolverBackend::hypre && !hypre_available()) continue;
    SolverSettings s;
    s.backend = backend;
    s.preconditioner = preconditioner;
    s.tolerance = 1e-8;
    out.push_back(s);
  }
  return out;
}

}  // namespace

TEST(AggregationAmg, HierarchyIsGalerkinWithRestrictionThePrologationsTranspose) {
  const auto m = manufactured_ppe_system(60, 21);
  HostOps ops;
  AggregationAmg<HostOps> amg(ops);
  ASSERT_EQ(amg.setup(view(m.A)), "");
  ASSERT_GE(amg.levels(), 3);
  long long total = 0;
  for (int l = 0; l < amg.levels(); ++l) total += amg.nonzeros(l);
  EXPECT_LT(double(total) / amg.nonzeros(0), 2.0) << "operator complexity";
  for (int l = 0; l + 1 < amg.levels(); ++l) {
    const CsrView A = amg.matrix(l), P = amg.prolongation(l), R = amg.restriction(l), Ac = amg.matrix(l + 1);
    EXPECT_GT(A.rows, 4 * Ac.rows) << "level " << l << " coarsens by " << double(A.rows) / Ac.rows;
    // A_c v = R (A (P v))
    std::vector<double> v(Ac.rows);
    for (int i = 0; i < Ac.rows; ++i) v[i] = std::sin(1.3 * i) + 0.1 * i;
    const auto direct = product(Ac, v), composed = product(R, product(A, product(P, v)));
    EXPECT_LT(relative_difference(direct, composed), 1e-13) << "level " << l;
    // R = P^T, entry by entry
    const auto p = entries(P), r = entries(R);
    ASSERT_EQ(p.size(), r.size()) << "level " << l;
    for (const auto& [ij, value] : p) EXPECT_EQ(r.at({ij.second, ij.first}), value);
  }
  // Constants are interpolated exactly where a row sums to zero and all its columns are aggregated
  // ((I - omega D^-1 A) P_tent 1 = 1 there); an identity row (free surface) has an empty row of P.
  const CsrView A = amg.matrix(0), P = amg.prolongation(0);
  const auto p1 = product(P, std::vector<double>(amg.rows(1), 1.0));
  int checked = 0, identity_rows = 0;
  for (int i = 0; i < A.rows; ++i) {
    double row_sum = 0;
    bool all_aggregated = true;
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) {
      row_sum += A.val[k];
      const int j = A.col[k];
      all_aggregated = all_aggregated && P.row_offset[j + 1] > P.row_offset[j];
    }
    if (A.row_offset[i + 1] - A.row_offset[i] == 1) {
      ++identity_rows;
      EXPECT_EQ(P.row_offset[i + 1], P.row_offset[i]) << "identity row " << i;
    } else if (all_aggregated && std::abs(row_sum) < 1e-12) {
      ++checked;
      EXPECT_NEAR(p1[i], 1.0, 1e-12) << "row " << i;
    }
  }
  EXPECT_GT(checked, A.rows / 2);
  EXPECT_GT(identity_rows, 0);
}

// 1,600 to 25,600 unknowns: AMG's iterations stay within a few of each other (Jacobi's grow with the
// grid's width), and at the largest size AMG needs a fifth of Jacobi's or fewer.
TEST(AggregationAmg, IterationsBarelyGrowWithTheSize) {
  std::vector<int> amg, jacobi;
  for (int n : {40, 80, 160}) {
    const auto m = manufactured_ppe_system(n, 21);
    amg.push_back(solve_iterations(m, "amg"));
    jacobi.push_back(solve_iterations(m, "jacobi"));
  }
  EXPECT_LE(amg.back(), amg.front() + 8) << amg[0] << " " << amg[1] << " " << amg[2];
  EXPECT_LE(amg.back(), 30);
  EXPECT_GT(jacobi.back(), 2 * jacobi.front()) << jacobi[0] << " " << jacobi[2];
  EXPECT_LT(5 * amg.back(), jacobi.back()) << amg.back() << " against " << jacobi.back();
}

// The set-up's loops gather, its reductions are exact, and the sort is stable, so the hierarchy and
// the solution are the same bits for any number of threads.
TEST(AggregationAmg, SameSolutionForAnyThreadCount) {
  const auto m = manufactured_ppe_system(120, 21);
  SolverSettings s;
  s.backend = SolverBackend::native;
  s.preconditioner = PreconditionerType::amg;
  const int threads = omp_get_max_threads();
  std::vector<std::vector<double>> x(2);
  std::vector<int> iterations;
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    iterations.push_back(make_linear_solver(s)->solve(m.A, m.b, x[t - 1]).iterations);
  }
  omp_set_num_threads(threads);
  EXPECT_EQ(iterations[0], iterations[1]);
  EXPECT_EQ(x[0], x[1]);
}

// A solver keeps the hierarchy's arrays from one matrix to the next (a set-up on the device then
// allocates only when a size grows): a larger, a smaller and a larger system again give the bits a
// fresh solver gives.
TEST(AggregationAmg, ReusedArraysGiveAFreshHierarchysAnswer) {
  SolverSettings s;
  s.backend = SolverBackend::native;
  s.preconditioner = PreconditionerType::amg;
  auto kept = make_linear_solver(s);
  for (int n : {80, 40, 80, 60}) {
    auto m = manufactured_ppe_system(n, 21);
    for (double& v : m.A.val) v *= 1.0 + 1e-3 * n;  // another matrix each time, even at the same size
    std::vector<double> x_kept, x_fresh;
    const SolveReport a = kept->solve(m.A, m.b, x_kept), b = make_linear_solver(s)->solve(m.A, m.b, x_fresh);
    ASSERT_TRUE(a.converged) << n << ": " << a.message;
    EXPECT_EQ(a.iterations, b.iterations) << n;
    EXPECT_EQ(x_kept, x_fresh) << n;
  }
}

// A solve told that its matrix is the next step's (MatrixReuse::preconditioner) keeps the hierarchy
// and smooths with the new matrix's own rows: it still meets the tolerance for the new system, at
// about the iterations of a fresh set-up, while the matrices drift by a few per cent (the PPE of the
// next steps). The same for hypre's BoomerAMG.
TEST(AggregationAmg, KeptHierarchySolvesTheNextMatricesAtAboutTheFreshIterations) {
  for (const SolverSettings& s : amg_solvers()) {
    const SolverBackend backend = s.backend;
    auto kept = make_linear_solver(s);
    const ManufacturedSystem first = manufactured_ppe_system(60, 21);
    std::vector<double> x;
    ASSERT_TRUE(kept->solve(first.A, first.b, x).converged);
    for (int step = 1; step <= 10; ++step) {
      ManufacturedSystem m = manufactured_ppe_system(60, 21);
      for (std::size_t k = 0; k < m.A.val.size(); ++k)  // entries drift by up to 0.5 % per step
        m.A.val[k] *= 1.0 + 0.005 * step * std::sin(0.7 * static_cast<double>(k));
      std::vector<double> x_kept = x, x_fresh = x;
      const SolveReport a = kept->solve(m.A, m.b, x_kept, MatrixReuse::preconditioner);
      const SolveReport b = make_linear_solver(s)->solve(m.A, m.b, x_fresh);
      ASSERT_TRUE(a.converged) << name_of(backend) << " step " << step << ": " << a.message;
      EXPECT_TRUE(kept->kept_preconditioner()) << name_of(backend) << " step " << step;
      EXPECT_LE(a.relative_residual, 1e-8);
      EXPECT_LE(a.iterations, b.iterations + 3) << name_of(backend) << " step " << step;
      x = x_kept;
    }
  }
}

namespace {

// The system with its rows and columns in a new order: new row a is old row old_row[a] (a permutation).
CsrMatrix reordered(const CsrMatrix& A, const std::vector<Index>& old_row) {
  std::vector<int> new_row(A.rows);
  for (int a = 0; a < A.rows; ++a) new_row[old_row[a]] = a;
  CsrMatrix out;
  out.rows = A.rows;
  out.row_offset.push_back(0);
  for (int a = 0; a < A.rows; ++a) {
    std::map<int, double> row;
    for (int k = A.row_offset[old_row[a]]; k < A.row_offset[old_row[a] + 1]; ++k) row[new_row[A.col[k]]] = A.val[k];
    for (const auto& [c, v] : row) {
      out.col.push_back(c);
      out.val.push_back(v);
    }
    out.row_offset.push_back(static_cast<int>(out.col.size()));
  }
  return out;
}

std::vector<Index> shuffled_rows(int n) {  // a fixed, well-mixed permutation of 0..n-1
  std::vector<Index> order(n);
  for (int a = 0; a < n; ++a) order[a] = a;
  for (int a = n - 1; a > 0; --a) std::swap(order[a], order[amg::mix(static_cast<std::uint32_t>(a)) % (a + 1)]);
  return order;
}

// The next step's system after an open boundary's exchange: the manufactured system without its bottom
// grid line (particles removed; the rows that reached them keep zero row sums) and with `created` rows
// appended (particles created: rows the kept hierarchy has not seen, coupled to the line above them),
// shuffled. origin: each row's row in m, or -1; b = A x* for the old x* and 1 on the new rows.
struct NextSystem {
  CsrMatrix A;
  std::vector<double> b;
  std::vector<Index> origin;
};
NextSystem exchanged(const ManufacturedSystem& m, int n) {
  std::vector<Index> row_of(m.A.rows, -1), origin;  // old row -> unshuffled new row
  for (int r = n; r < m.A.rows; ++r) {
    row_of[r] = static_cast<Index>(origin.size());
    origin.push_back(r);
  }
  CsrMatrix A;
  A.row_offset.push_back(0);
  std::vector<double> x;
  for (const Index r : origin) {
    double off_diagonal = 0;
    for (int k = m.A.row_offset[r]; k < m.A.row_offset[r + 1]; ++k)
      if (m.A.col[k] != r && row_of[m.A.col[k]] >= 0) {
        A.col.push_back(row_of[m.A.col[k]]);
        A.val.push_back(m.A.val[k]);
        off_diagonal += m.A.val[k];
      }
    const bool identity = m.A.row_offset[r + 1] - m.A.row_offset[r] == 1;
    A.col.push_back(row_of[r]);
    A.val.push_back(identity ? 1.0 : -off_diagonal);
    x.push_back(m.x_star[r]);
    A.row_offset.push_back(static_cast<int>(A.col.size()));
  }
  const int kept = static_cast<int>(origin.size());
  for (int c = 0; c < n; ++c) {  // created rows: -1 to the kept row above, +1.5 on the diagonal
    A.col.push_back(row_of[2 * n + c]);
    A.val.push_back(-1.0);
    A.col.push_back(kept + c);
    A.val.push_back(1.5);
    A.row_offset.push_back(static_cast<int>(A.col.size()));
    origin.push_back(-1);
    x.push_back(1.0);
  }
  A.rows = static_cast<int>(origin.size());
  const std::vector<Index> order = shuffled_rows(A.rows);
  NextSystem next{reordered(A, order), {}, {}};
  const std::vector<double> b = product(view(A), x);
  for (int a = 0; a < A.rows; ++a) {
    next.b.push_back(b[order[a]]);
    next.origin.push_back(origin[order[a]]);
  }
  return next;
}

}  // namespace

// Particles re-sorted between steps: the hierarchy kept with its fine rows following the new order
// (refresh_fine with an origin) is the same preconditioner, M'^-1 (Q r) = Q (M^-1 r), to rounding.
TEST(AggregationAmg, KeptHierarchyFollowsReorderedRows) {
  const auto m = manufactured_ppe_system(60, 21);
  HostOps ops;
  AggregationAmg<HostOps> amg(ops);
  ASSERT_EQ(amg.setup(view(m.A)), "");
  std::vector<double> r(m.A.rows), z(m.A.rows);
  for (int i = 0; i < m.A.rows; ++i) r[i] = std::cos(0.37 * i) + 0.01 * i;
  amg.apply(r.data(), z.data());

  const std::vector<Index> old_row = shuffled_rows(m.A.rows);
  const CsrMatrix A_moved = reordered(m.A, old_row);
  ASSERT_TRUE(amg.refresh_fine(view(A_moved), old_row.data()));
  std::vector<double> r_moved(m.A.rows), z_moved(m.A.rows), z_expected(m.A.rows);
  for (int a = 0; a < m.A.rows; ++a) {
    r_moved[a] = r[old_row[a]];
    z_expected[a] = z[old_row[a]];
  }
  amg.apply(r_moved.data(), z_moved.data());
  EXPECT_LT(relative_difference(z_moved, z_expected), 1e-12);
  EXPECT_FALSE(amg.refresh_fine(view(A_moved))) << "without an origin, rows that moved need a new set-up";
}

// Particles created and removed as well (an open boundary's exchange, then a re-sort): the solver
// keeps the native AMG's hierarchy, its new rows left to the smoother, and meets the tolerance at about
// a fresh set-up's iterations; hypre's BoomerAMG cannot follow the rows and builds a new hierarchy.
TEST(AggregationAmg, KeptHierarchyFollowsCreatedAndRemovedRows) {
  for (const SolverSettings& s : amg_solvers()) {
    const SolverBackend backend = s.backend;
    auto kept = make_linear_solver(s);
    const ManufacturedSystem first = manufactured_ppe_system(60, 21);
    std::vector<double> x;
    ASSERT_TRUE(kept->solve(first.A, first.b, x).converged);
    ASSERT_TRUE(kept->built_preconditioner());

    const NextSystem next = exchanged(first, 60);
    std::vector<double> x_kept, x_fresh;
    const SolveReport a = kept->solve(next.A, next.b, x_kept, MatrixReuse::preconditioner, next.origin);
    const SolveReport fresh = make_linear_solver(s)->solve(next.A, next.b, x_fresh);
    ASSERT_TRUE(a.converged) << name_of(backend) << ": " << a.message;
    EXPECT_LE(a.relative_residual, 1e-8);
    EXPECT_EQ(kept->kept_preconditioner(), backend == SolverBackend::native) << name_of(backend);
    EXPECT_EQ(kept->built_preconditioner(), backend != SolverBackend::native) << name_of(backend);
    EXPECT_LE(a.iterations, fresh.iterations + 3) << name_of(backend) << ": fresh " << fresh.iterations;
    const std::span<const Index> too_short = std::span<const Index>(next.origin).first(10);
    EXPECT_THROW(kept->solve(next.A, next.b, x_kept, MatrixReuse::preconditioner, too_short), std::invalid_argument);
  }
}
