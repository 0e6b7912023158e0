#pragma once
// The particle-free loops of the smoothed-aggregation AMG (poisson/aggregation_amg.hpp): its set-up
// (strength, the distance-2 independent set, aggregates, the smoothed prolongation, sparse products and
// the transpose) and its cycle, each a functor that writes only its own row, for the common launcher.
// The algorithm and its sources are described at the head of aggregation_amg.hpp.
#include <cstdint>

#include "core/parallel.hpp"
#include "poisson/sparse_functors.hpp"

namespace isph {

namespace amg {

inline constexpr double kStrengthThreshold = 0.25;
inline constexpr int kSweeps = 1;         // before and after the coarse correction
inline constexpr int kCoarsest = 64;      // coarsening stops at this many unknowns or fewer
inline constexpr double kStall = 0.85;    // ... or when a level keeps more than this share of its rows
inline constexpr int kDenseLimit = 512;   // the coarsest level is inverted densely up to this size
inline constexpr int kCoarseSweeps = 20;  // else smoothed by this many sweeps
inline constexpr int kMaxLevels = 25;
inline constexpr int kProductCapacity = 256;  // entries of one row of a sparse product, at most

using State = std::uint64_t;  // MIS state: code (2 bits), priority (30 bits), node (32 bits)
inline constexpr State kOut = 0, kUndecided = 1, kRoot = 2;

ISPH_HD inline std::uint32_t mix(std::uint32_t x) {  // an integer hash (the priorities; hash slots)
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
ISPH_HD inline State make_state(State code, Index i) {
  return (code << 62) | (State{mix(static_cast<std::uint32_t>(i)) & 0x3fffffffU} << 32) | static_cast<std::uint32_t>(i);
}
ISPH_HD inline State code_of(State s) { return s >> 62; }

// cut_i = theta max_{k != i} (-A_ik), or 0 when row i has no negative off-diagonal entry.
struct StrengthCut {
  CsrView A;
  double theta;
  double* cut;
  ISPH_HD void operator()(Index i) const {
    double largest = 0;
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k)
      if (A.col[k] != i && -A.val[k] > largest) largest = -A.val[k];
    cut[i] = theta * largest;
  }
};

ISPH_HD inline bool is_strong(const CsrView& A, const double* cut, Index i, int k) {
  return A.col[k] != i && cut[i] > 0 && -A.val[k] >= cut[i];
}

// Undecided where row i has strong neighbours, out (for good) where it has none. An out node's state is
// below every undecided or root state, so that the maxima below pass over it.
struct MisStart {
  const double* cut;
  State* state;
  ISPH_HD void operator()(Index i) const { state[i] = make_state(cut[i] > 0 ? kUndecided : kOut, i); }
};

// highest_i = the largest state over i and its strong neighbours (applied twice: within two links).
struct HighestNearby {
  CsrView A;
  const double* cut;
  const State* in;
  State* highest;
  ISPH_HD void operator()(Index i) const {
    State h = in[i];
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k)
      if (is_strong(A, cut, i, k) && in[A.col[k]] > h) h = in[A.col[k]];
    highest[i] = h;
  }
};
// One round's decision from the largest state within two links: root when it is the node's own, out
// when it is a root's.
struct MisDecide {
  const State* highest;
  State* state;
  ISPH_HD void operator()(Index i) const {
    if (code_of(state[i]) != kUndecided) return;
    if (highest[i] == state[i])
      state[i] = make_state(kRoot, i);
    else if (code_of(highest[i]) == kRoot)
      state[i] = make_state(kOut, i);
  }
};

struct IsUndecided {
  const State* state;
  ISPH_HD Index operator()(Index i) const { return code_of(state[i]) == kUndecided ? 1 : 0; }
};

struct IsRoot {
  const State* state;
  Index* flag;
  ISPH_HD void operator()(Index i) const { flag[i] = code_of(state[i]) == kRoot ? 1 : 0; }
};

// Pass 1: a root's aggregate is its coarse index (root_rank: inclusive prefix sum of the root flags);
// a node beside roots joins the most strongly coupled one; others get -1 for now.
struct JoinRoot {
  CsrView A;
  const double* cut;
  const State* state;
  const Index* root_rank;
  Index* aggregate;
  ISPH_HD void operator()(Index i) const {
    if (code_of(state[i]) == kRoot) {
      aggregate[i] = root_rank[i] - 1;
      return;
    }
    Index best = -1;
    double coupling = 0;
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) {
      const Index j = A.col[k];
      if (is_strong(A, cut, i, k) && code_of(state[j]) == kRoot && -A.val[k] > coupling) {
        best = j;
        coupling = -A.val[k];
      }
    }
    aggregate[i] = best >= 0 ? root_rank[best] - 1 : -1;
  }
};
// Pass 2: a node two links from a root joins the aggregate of its most strongly coupled strong
// neighbour that has one; a node without strong neighbours stays at -1 (no coarse unknown).
struct JoinNeighbour {
  CsrView A;
  const double* cut;
  const Index* first;  // pass 1's result
  Index* aggregate;
  ISPH_HD void operator()(Index i) const {
    Index best = first[i];
    double coupling = 0;
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1] && first[i] < 0; ++k) {
      if (is_strong(A, cut, i, k) && first[A.col[k]] >= 0 && -A.val[k] > coupling) {
        best = first[A.col[k]];
        coupling = -A.val[k];
      }
    }
    aggregate[i] = best;
  }
};

// Gershgorin's bound on the spectral radius of D^-1 A from row i: sum_j |A_ij| / |A_ii|.
struct ScaledRowSum {
  CsrView A;
  const double* dinv;
  ISPH_HD double operator()(Index i) const {
    double s = 0;
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) s += A.val[k] < 0 ? -A.val[k] : A.val[k];
    return s * (dinv[i] < 0 ? -dinv[i] : dinv[i]);
  }
};

// The l1 smoother's weights: 1 / sum_j |A_ij|.
struct InverseAbsoluteRowSum {
  CsrView A;
  double* l1inv;
  ISPH_HD void operator()(Index i) const {
    double s = 0;
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) s += A.val[k] < 0 ? -A.val[k] : A.val[k];
    l1inv[i] = s > 0 ? 1.0 / s : 0.0;
  }
};

// The tentative prolongation: row i holds 1 in column aggregate_i, or nothing when aggregate_i < 0.
struct CountAggregated {
  const Index* aggregate;
  int* row_end;  // row_offset + 1
  ISPH_HD void operator()(Index i) const { row_end[i] = aggregate[i] >= 0 ? 1 : 0; }
};
struct TentativeEntry {
  const Index* aggregate;
  const int* row_offset;
  int* col;
  double* val;
  ISPH_HD void operator()(Index i) const {
    if (aggregate[i] < 0) return;
    col[row_offset[i]] = aggregate[i];
    val[row_offset[i]] = 1;
  }
};

// A kept prolongation for a fine matrix whose rows were reordered, created or removed: row i of the new
// P is row origin_i of the old one, or empty when origin_i < 0 (a row the hierarchy has not seen).
struct CountOriginEntries {
  const int* old_offset;
  const Index* origin;
  int* row_end;  // the new row_offset + 1
  ISPH_HD void operator()(Index i) const {
    row_end[i] = origin[i] >= 0 ? old_offset[origin[i] + 1] - old_offset[origin[i]] : 0;
  }
};
struct GatherOriginRow {
  CsrView old_p;
  const Index* origin;
  const int* row_offset;
  int* col;
  double* val;
  ISPH_HD void operator()(Index i) const {
    if (origin[i] < 0) return;
    int out = row_offset[i];
    for (int k = old_p.row_offset[origin[i]]; k < old_p.row_offset[origin[i] + 1]; ++k, ++out) {
      col[out] = old_p.col[k];
      val[out] = old_p.val[k];
    }
  }
};

// The values of I - omega D^-1 A on A's pattern (every row of A holds its diagonal).
struct JacobiOperator {
  CsrView A;
  const double* dinv;
  double omega;
  double* val;
  ISPH_HD void operator()(Index i) const {
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k)
      val[k] = (A.col[k] == i ? 1.0 : 0.0) - omega * dinv[i] * A.val[k];
  }
};

// One row of a sparse product C = X Y, merged in a small open-addressing table; entries come out in
// the order of their first contribution, so the result does not depend on the device or the threads.
struct RowTable {
  int key[kProductCapacity];
  double value[kProductCapacity];
  int order[kProductCapacity];
  int size = 0;
  bool overflow = false;
  ISPH_HD RowTable() {
    for (int s = 0; s < kProductCapacity; ++s) key[s] = -1;
  }
  ISPH_HD void add(int c, double v) {
    int s = static_cast<int>(mix(static_cast<std::uint32_t>(c)) & (kProductCapacity - 1));
    while (key[s] != -1 && key[s] != c) s = (s + 1) & (kProductCapacity - 1);
    if (key[s] == c) {
      value[s] += v;
      return;
    }
    if (size == kProductCapacity - 1) {  // one slot stays empty, so that a search ends
      overflow = true;
      return;
    }
    key[s] = c;
    value[s] = v;
    order[size++] = s;
  }
};

// Pass 1 (col == nullptr): row_end[i] = the number of entries of row i of X Y (kProductCapacity when it
// does not fit). Pass 2: the entries, at row_offset[i].
struct SparseProductRow {
  CsrView X, Y;
  int* row_end;           // pass 1: C's row_offset + 1
  const int* row_offset;  // pass 2
  int* col;
  double* val;
  ISPH_HD void operator()(Index i) const {
    RowTable t;
    for (int kx = X.row_offset[i]; kx < X.row_offset[i + 1]; ++kx) {
      const int j = X.col[kx];
      for (int ky = Y.row_offset[j]; ky < Y.row_offset[j + 1]; ++ky) t.add(Y.col[ky], X.val[kx] * Y.val[ky]);
    }
    if (!col) {
      row_end[i] = t.overflow ? kProductCapacity : t.size;
      return;
    }
    for (int e = 0; e < t.size; ++e) {
      col[row_offset[i] + e] = t.key[t.order[e]];
      val[row_offset[i] + e] = t.value[t.order[e]];
    }
  }
};

struct ZeroFirst {  // row_offset[0] = 0, launched over one element
  int* v;
  ISPH_HD void operator()(Index) const { v[0] = 0; }
};
struct IntAt {
  const int* v;
  ISPH_HD int operator()(Index i) const { return v[i]; }
};

// Transpose by a stable sort of the entries by column: the row of every entry, the entries' order.
struct EntryRows {
  CsrView A;
  Index* entry_row;
  Index* column_key;
  Index* entry;
  ISPH_HD void operator()(Index i) const {
    for (int k = A.row_offset[i]; k < A.row_offset[i + 1]; ++k) {
      entry_row[k] = i;
      column_key[k] = A.col[k];
      entry[k] = k;
    }
  }
};
struct GatherTransposed {
  const Index* entry;
  const Index* entry_row;
  const double* val;
  int* t_col;
  double* t_val;
  ISPH_HD void operator()(Index q) const {
    t_col[q] = entry_row[entry[q]];
    t_val[q] = val[entry[q]];
  }
};

// The cycle's loops.
// z_out = z_in + D_l1^-1 (r - A z_in)
struct JacobiSweep {
  CsrView A;
  const double* l1inv;
  const double* r;
  const double* z_in;
  double* z_out;
  ISPH_HD void operator()(Index i) const {
    z_out[i] = z_in[i] + l1inv[i] * row_residual(A.row_offset, A.col, A.val, r, z_in, i);
  }
};
// res = r - A z
struct Residual {
  CsrView A;
  const double* r;
  const double* z;
  double* res;
  ISPH_HD void operator()(Index i) const { res[i] = row_residual(A.row_offset, A.col, A.val, r, z, i); }
};
// z += P z_coarse
struct ProlongAdd {
  CsrView P;
  const double* z_coarse;
  double* z;
  ISPH_HD void operator()(Index i) const {
    double s = 0;
    for (int k = P.row_offset[i]; k < P.row_offset[i + 1]; ++k) s += P.val[k] * z_coarse[P.col[k]];
    z[i] += s;
  }
};
// y = M x, M dense n x n by rows
struct DenseProduct {
  int n;
  const double* M;
  const double* x;
  double* y;
  ISPH_HD void operator()(Index i) const {
    double s = 0;
    for (int j = 0; j < n; ++j) s += M[static_cast<std::size_t>(i) * n + j] * x[j];
    y[i] = s;
  }
};

// The inverse of the CSR matrix (n rows, host arrays) as a dense row-major array; its pseudo-inverse
// when it is singular (aggregation_amg.cpp, with Eigen: host code only).
std::vector<double> dense_inverse(int n, const std::vector<int>& row_offset, const std::vector<int>& col,
                                  const std::vector<double>& val);

}  // namespace amg

}  // namespace isph
