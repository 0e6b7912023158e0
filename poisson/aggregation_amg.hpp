#pragma once
// Smoothed-aggregation algebraic multigrid (Vaněk, Mandel & Brezina 1996, Computing 56:179) as the
// preconditioner "amg" of the project's BiCGSTAB (poisson/krylov.hpp), on the host and on the device.
// Every step of the set-up and of the cycle is a launcher loop that writes only its own row, or a
// collective of core/parallel.hpp (reduction, prefix sum, stable sort), over the arrays of an Ops
// backend: the same code runs with OpenMP and as CUDA kernels, and the host backend ("native") is the
// test bed of the device one ("cuda"). Only a handful of scalars per level (sizes, the MIS rounds' count
// of undecided nodes) and the coarsest matrix (at most kDenseLimit rows) cross to the host, at set-up.
//
// Set-up, level by level, from A (n rows; the PPE's rows have diagonal 1 and negative neighbours):
//  1. Strength: j is a strong neighbour of i when -A_ij >= theta max_{k != i} (-A_ik), theta = 0.25
//     (on the PPE's kernel-weighted rows: the eight nearest neighbours in 2D). A row without a negative
//     off-diagonal entry (Dirichlet rows: free surface, splash, dry walls) has none; it is left out of
//     the coarse levels (its row of P is zero) and the smoother solves it exactly.
//  2. Aggregates: a maximal distance-2 independent set of the strong graph by random priorities
//     (Luby 1986; Bell, Dalton & Olson 2012, SIAM J. Sci. Comput. 34:C123). In each round an undecided
//     node becomes a root when its priority beats every undecided node's within two strong links, and
//     drops out when a root lies within two. Each root starts an aggregate; its strong neighbours join
//     it (the root they are most strongly coupled to), and the nodes two links away join the aggregate
//     of the neighbour they are most strongly coupled to. In 2D about nine nodes form an aggregate.
//  3. Prolongation: the tentative P (1 from each node to its aggregate) smoothed by a damped Jacobi
//     step, P = (I - omega D^-1 A) P_tent with omega = 4 / (3 rho), rho = max_i sum_j |A_ij| / |A_ii|
//     (Gershgorin's bound on the spectral radius of D^-1 A).
//  4. Restriction R = P^T (a transpose by stable sort), coarse matrix A_c = R (A P) (Galerkin).
// Coarsening stops at kCoarsest unknowns or fewer, or when a level keeps more than kStall of its rows.
// The coarsest matrix is inverted densely on the host (kDenseLimit rows at most), or else smoothed.
//
// Apply: one V-cycle from z = 0 (a fixed linear operator, as BiCGSTAB needs): kSweeps l1-Jacobi sweeps
// z += D_l1^-1 (r - A z), D_l1 = diag(sum_j |A_ij|) (convergent without a weight to choose; Baker, Falgout,
// Kolev & Yang 2011, SIAM J. Sci. Comput. 33:2864), the residual restricted, the coarse correction,
// prolongation and kSweeps sweeps again.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/parallel.hpp"
#include "poisson/aggregation_functors.hpp"
#include "poisson/sparse_functors.hpp"

namespace isph {

// The hierarchy over an Ops backend (poisson/krylov.hpp lists what an Ops supplies; the AMG also uses
// its typed arrays: Array<T>, array<T>(n), to_host(pointer, n) and from_host(vector)).
template <class Ops>
class AggregationAmg {
 public:
  template <class T>
  using Array = typename Ops::template Array<T>;

  explicit AggregationAmg(Ops& ops) : ops_(ops) {}

  // Builds the levels below A (the fine matrix, in the backend's memory; it must outlive the hierarchy's
  // use). Returns an empty string, or why the hierarchy cannot be built. The arrays of the last set-up
  // are reused where they are large enough (a run's matrices change little from step to step), so that
  // a set-up on the device allocates, and synchronises, only when a size grows.
  std::string setup(const CsrView& A) {
    levels_used_ = 0;
    rows_followed_ = false;
    dense_n_ = 0;
    Level& fine = next_level(A.rows);
    fine.A_view = A;
    fine.nonzeros = entries(A);
    while (true) {
      Level& level = levels_[levels_used_ - 1];
      const Exec exec = ops_.exec();
      parallel_for(exec, level.n, InverseDiagonal{level.A_view, level.dinv.data()});
      const Index bad =
          parallel_reduce(exec, level.n, RowWithoutDiagonal::kNoRow, RowWithoutDiagonal{level.dinv.data()}, MinOf{});
      if (bad != RowWithoutDiagonal::kNoRow)
        return "zero diagonal in row " + std::to_string(bad) + ": the AMG level " + std::to_string(levels_used_ - 1) +
               " cannot be smoothed";
      parallel_for(exec, level.n, amg::InverseAbsoluteRowSum{level.A_view, level.l1inv.data()});
      level.P.rows = level.R.rows = 0;
      if (level.n <= amg::kCoarsest || levels_used_ == amg::kMaxLevels) break;
      int coarse_n = 0;
      if (std::string why = coarsen(level, coarse_n); !why.empty()) return why;
      if (coarse_n == 0 || coarse_n > amg::kStall * level.n) {  // stalled: this level is the coarsest
        level.P.rows = 0;
        break;
      }
      const std::size_t at = levels_used_ - 1;
      Level& coarse = next_level(coarse_n);  // may move the levels: `level` is levels_[at] again
      if (std::string why = galerkin(levels_[at], coarse); !why.empty()) return why;
    }
    const Level& last = levels_[levels_used_ - 1];
    if (last.n <= amg::kDenseLimit) {
      const CsrView A_last = last.A_view;
      const std::size_t m = static_cast<std::size_t>(last.nonzeros);
      dense_inverse_ = ops_.from_host(amg::dense_inverse(last.n, ops_.to_host(A_last.row_offset, last.n + 1),
                                                         ops_.to_host(A_last.col, m), ops_.to_host(A_last.val, m)));
      dense_n_ = last.n;
    }
    return "";
  }

  // Takes A (in the backend's memory) as the fine matrix and keeps the levels below it: the next PPE,
  // whose particles moved a little, is smoothed with its own rows and corrected on the coarse levels of
  // the last set-up. origin (A.rows entries in the backend's memory, or null when A's rows are the last
  // fine matrix's): the last fine row each of A's rows continues, -1 for a new one (particles re-sorted,
  // created or removed); P's rows follow it and a new row is left out of the coarse levels, like a
  // Dirichlet row. False when there is no set-up to keep, or the size differs and no origin is given, or
  // the fine level is the coarsest (its dense inverse is of the old rows). The origin always refers to
  // the rows of the set-up's fine matrix, however many refreshes came between.
  bool refresh_fine(const CsrView& A, const Index* origin = nullptr) {
    if (levels_used_ == 0) return false;
    if (origin) {
      if (levels_used_ < 2) return false;
      follow_rows(A.rows, origin);
    } else if (rows_followed_ || A.rows != levels_[0].n) {
      return false;
    }
    Level& fine = levels_[0];
    fine.A_view = A;
    fine.nonzeros = entries(A);
    parallel_for(ops_.exec(), fine.n, InverseDiagonal{A, fine.dinv.data()});
    if (parallel_reduce(ops_.exec(), fine.n, RowWithoutDiagonal::kNoRow, RowWithoutDiagonal{fine.dinv.data()},
                        MinOf{}) != RowWithoutDiagonal::kNoRow)
      return false;
    parallel_for(ops_.exec(), fine.n, amg::InverseAbsoluteRowSum{A, fine.l1inv.data()});
    return true;
  }

  // z = M^-1 r: one V-cycle (r and z in the backend's memory, the fine matrix's size).
  void apply(const double* r, double* z) { cycle(0, r, z); }

  // The hierarchy, for tests and diagnostics (pointers into the backend's memory): level 0 is the fine
  // matrix; P and R of the coarsest level are empty.
  int levels() const { return static_cast<int>(levels_used_); }
  int rows(int level) const { return levels_[level].n; }
  Index nonzeros(int level) const { return levels_[level].nonzeros; }
  CsrView matrix(int level) const { return levels_[level].A_view; }
  CsrView prolongation(int level) const { return levels_[level].P.view(); }
  CsrView restriction(int level) const { return levels_[level].R.view(); }

 private:
  struct Csr {  // rows = 0: empty (its arrays may hold an earlier set-up's entries)
    int rows = 0;
    Array<int> row_offset, col;
    Array<double> val;
    CsrView view() const { return rows == 0 ? CsrView{} : CsrView{rows, row_offset.data(), col.data(), val.data()}; }
  };
  struct Level {
    int n = 0;
    Index nonzeros = 0;
    Csr A;  // levels below the finest; the finest uses A_view only
    CsrView A_view;
    Array<double> dinv, l1inv, res, tmp, rhs, z;  // rhs, z: a coarse level's right-hand side and correction
    Csr P, R;                                     // to and from the next level
  };

  // The next level of n rows, its vectors at least n long.
  Level& next_level(int n) {
    if (levels_used_ == levels_.size()) levels_.emplace_back();
    Level& l = levels_[levels_used_++];
    l.n = n;
    for (Array<double>* v : {&l.dinv, &l.l1inv, &l.res, &l.tmp, &l.rhs, &l.z}) ensure(*v, n);
    return l;
  }

  // a holds at least n elements (its contents are not kept when it grows).
  template <class T>
  void ensure(Array<T>& a, std::size_t n) {
    if (a.size() < n) a = ops_.template array<T>(n);
  }

  // Aggregates level's rows and builds its P; coarse_n: the number of aggregates.
  std::string coarsen(Level& level, int& coarse_n) {
    const Exec exec = ops_.exec();
    const int n = level.n;
    const CsrView A = level.A_view;
    Scratch& w = scratch_;
    for (Array<amg::State>* v : {&w.state, &w.near, &w.within_two}) ensure(*v, n);
    for (Array<Index>* v : {&w.rank, &w.first, &w.aggregate}) ensure(*v, n);
    ensure(w.cut, n);
    ensure(w.jacobi, entries(A));
    Array<double>& cut = w.cut;
    Array<amg::State>&state = w.state, &near = w.near, &within_two = w.within_two;
    Array<Index>&rank = w.rank, &first = w.first, &aggregate = w.aggregate;
    parallel_for(exec, n, amg::StrengthCut{A, amg::kStrengthThreshold, cut.data()});
    parallel_for(exec, n, amg::MisStart{cut.data(), state.data()});
    // At least the largest undecided state is decided in each round.
    while (parallel_reduce(exec, n, Index{0}, amg::IsUndecided{state.data()}, IntegerSum{}) > 0) {
      parallel_for(exec, n, amg::HighestNearby{A, cut.data(), state.data(), near.data()});
      parallel_for(exec, n, amg::HighestNearby{A, cut.data(), near.data(), within_two.data()});
      parallel_for(exec, n, amg::MisDecide{within_two.data(), state.data()});
    }
    parallel_for(exec, n, amg::IsRoot{state.data(), rank.data()});
    inclusive_scan(exec, rank.data(), n);
    coarse_n = n > 0 ? read(rank.data() + n - 1) : 0;
    if (coarse_n == 0) return "";
    parallel_for(
        exec, n,
        amg::JoinRoot{
            .A = A, .cut = cut.data(), .state = state.data(), .root_rank = rank.data(), .aggregate = first.data()});
    parallel_for(exec, n, amg::JoinNeighbour{A, cut.data(), first.data(), aggregate.data()});

    Csr& tentative = w.tentative;
    start_csr(tentative, n);
    parallel_for(exec, n, amg::CountAggregated{aggregate.data(), tentative.row_offset.data() + 1});
    inclusive_scan(exec, tentative.row_offset.data() + 1, n);
    allocate_entries(tentative);
    parallel_for(
        exec, n,
        amg::TentativeEntry{aggregate.data(), tentative.row_offset.data(), tentative.col.data(), tentative.val.data()});
    // P = (I - omega D^-1 A) P_tent, omega = 4 / (3 rho)
    const double rho = parallel_reduce(exec, n, 0.0, amg::ScaledRowSum{A, level.dinv.data()}, MaxOf{});
    parallel_for(exec, n, amg::JacobiOperator{A, level.dinv.data(), 4.0 / (3.0 * rho), w.jacobi.data()});
    const CsrView smoothing{n, A.row_offset, A.col, w.jacobi.data()};
    return multiply(smoothing, tentative.view(), level.P);
  }

  // The fine level's P, R and vectors for n fine rows that continue the set-up's as origin says.
  void follow_rows(int n, const Index* origin) {
    const Exec exec = ops_.exec();
    Level& fine = levels_[0];
    if (!rows_followed_) std::swap(fine.P, setup_p_);  // the set-up's P, kept as the rows' source
    rows_followed_ = true;
    Csr& p = fine.P;
    const CsrView old_p = setup_p_.view();
    start_csr(p, n);
    parallel_for(exec, n, amg::CountOriginEntries{old_p.row_offset, origin, p.row_offset.data() + 1});
    inclusive_scan(exec, p.row_offset.data() + 1, n);
    allocate_entries(p);
    parallel_for(exec, n, amg::GatherOriginRow{old_p, origin, p.row_offset.data(), p.col.data(), p.val.data()});
    transpose(p.view(), levels_[1].n, fine.R);
    fine.n = n;
    for (Array<double>* v : {&fine.dinv, &fine.l1inv, &fine.res, &fine.tmp, &fine.rhs, &fine.z}) ensure(*v, n);
  }

  // R = P^T and the coarse matrix R (A P).
  std::string galerkin(Level& level, Level& coarse) {
    transpose(level.P.view(), coarse.n, level.R);
    Csr& ap = scratch_.ap;
    if (std::string why = multiply(level.A_view, level.P.view(), ap); !why.empty()) return why;
    if (std::string why = multiply(level.R.view(), ap.view(), coarse.A); !why.empty()) return why;
    coarse.A_view = coarse.A.view();
    coarse.nonzeros = entries(coarse.A_view);
    return "";
  }

  // C = X Y (C has X's rows)
  std::string multiply(const CsrView& X, const CsrView& Y, Csr& C) {
    const Exec exec = ops_.exec();
    start_csr(C, X.rows);
    parallel_for(
        exec, X.rows,
        amg::SparseProductRow{
            .X = X, .Y = Y, .row_end = C.row_offset.data() + 1, .row_offset = nullptr, .col = nullptr, .val = nullptr});
    const int widest = parallel_reduce(exec, X.rows, 0, amg::IntAt{C.row_offset.data() + 1}, MaxOf{});
    if (widest >= amg::kProductCapacity - 1)
      return "AMG: a row of a level's product has more than " + std::to_string(amg::kProductCapacity - 2) + " entries";
    inclusive_scan(exec, C.row_offset.data() + 1, X.rows);
    allocate_entries(C);
    parallel_for(exec, X.rows,
                 amg::SparseProductRow{.X = X,
                                       .Y = Y,
                                       .row_end = nullptr,
                                       .row_offset = C.row_offset.data(),
                                       .col = C.col.data(),
                                       .val = C.val.data()});
    return "";
  }

  // T = A^T, A with `columns` columns
  void transpose(const CsrView& A, int columns, Csr& T) {
    const Exec exec = ops_.exec();
    const Index m = entries(A);
    Scratch& w = scratch_;
    for (Array<Index>* v : {&w.entry_row, &w.column, &w.entry}) ensure(*v, m);
    parallel_for(exec, A.rows, amg::EntryRows{A, w.entry_row.data(), w.column.data(), w.entry.data()});
    stable_sort_by_key(exec, w.column.data(), w.entry.data(), m, columns);
    T.rows = columns;
    ensure(T.row_offset, static_cast<std::size_t>(columns) + 1);
    parallel_for(exec, columns + 1, KeyStarts{w.column.data(), m, T.row_offset.data()});  // row offsets
    ensure(T.col, m);
    ensure(T.val, m);
    parallel_for(exec, m,
                 amg::GatherTransposed{.entry = w.entry.data(),
                                       .entry_row = w.entry_row.data(),
                                       .val = A.val,
                                       .t_col = T.col.data(),
                                       .t_val = T.val.data()});
  }

  // c gets `rows` rows and row_offset[0] = 0; the entries follow by allocate_entries once the offsets hold.
  void start_csr(Csr& c, int rows) {
    c.rows = rows;
    ensure(c.row_offset, static_cast<std::size_t>(rows) + 1);
    parallel_for(ops_.exec(), 1, amg::ZeroFirst{c.row_offset.data()});
  }
  void allocate_entries(Csr& c) {
    const int m = read(c.row_offset.data() + c.rows);
    ensure(c.col, m);
    ensure(c.val, m);
  }
  Index entries(const CsrView& A) { return read(A.row_offset + A.rows); }
  template <class T>
  T read(const T* p) {
    return ops_.to_host(p, 1)[0];
  }

  void cycle(int l, const double* r, double* z) {
    Level& level = levels_[l];
    const Exec exec = ops_.exec();
    const int n = level.n;
    const CsrView A = level.A_view;
    const bool coarsest = l + 1 == static_cast<int>(levels_used_);
    if (coarsest && dense_n_ == n) {
      parallel_for(exec, n, amg::DenseProduct{n, dense_inverse_.data(), r, z});
      return;
    }
    const int sweeps = coarsest ? amg::kCoarseSweeps : amg::kSweeps;
    double* current = z;
    double* other = level.tmp.data();
    parallel_for(
        exec, n,
        ScaledAxpby{.a = 1, .b = 0, .d = level.l1inv.data(), .x = r, .y = current});  // the first sweep, from 0
    for (int s = 1; s < sweeps; ++s) {
      parallel_for(exec, n,
                   amg::JacobiSweep{.A = A, .l1inv = level.l1inv.data(), .r = r, .z_in = current, .z_out = other});
      std::swap(current, other);
    }
    if (!coarsest) {
      Level& next = levels_[l + 1];
      parallel_for(exec, n, amg::Residual{A, r, current, level.res.data()});
      const CsrView R = level.R.view();
      parallel_for(
          exec, next.n,
          CsrRowProduct{
              .row_offset = R.row_offset, .col = R.col, .val = R.val, .x = level.res.data(), .y = next.rhs.data()});
      cycle(l + 1, next.rhs.data(), next.z.data());
      parallel_for(exec, n, amg::ProlongAdd{level.P.view(), next.z.data(), current});
      for (int s = 0; s < sweeps; ++s) {
        parallel_for(exec, n,
                     amg::JacobiSweep{.A = A, .l1inv = level.l1inv.data(), .r = r, .z_in = current, .z_out = other});
        std::swap(current, other);
      }
    }
    if (current != z) parallel_for(exec, n, ScaledAxpby{.a = 1, .b = 0, .d = nullptr, .x = current, .y = z});
  }

  // Work arrays of the set-up, kept for the next one.
  struct Scratch {
    Array<double> cut, jacobi;
    Array<amg::State> state, near, within_two;
    Array<Index> rank, first, aggregate, entry_row, column, entry;
    Csr tentative, ap;
  };

  Ops& ops_;
  std::vector<Level> levels_;  // the first levels_used_ are the hierarchy; the rest keep arrays for later
  std::size_t levels_used_ = 0;
  Scratch scratch_;
  Csr setup_p_;                 // the set-up's fine P, once a refresh has followed moved rows
  bool rows_followed_ = false;  // the fine level's P and R were rebuilt from setup_p_
  Array<double> dense_inverse_;
  int dense_n_ = 0;
};

}  // namespace isph
