// The launcher's collective primitives on the host: parallel_reduce with its exact combinations, the
// ordered floating-point sum, and the inclusive scan that turns counts into the ends of CSR rows.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "core/ordered_sum.hpp"
#include "core/parallel.hpp"

using namespace isph;

namespace {
struct IntAt {
  const Index* v;
  Index operator()(Index i) const { return v[i]; }
};
}  // namespace

// Over more elements than the launcher runs on one thread, with 1 and 2 threads: max and min are the
// sequence's, the integer sum is exact, and an empty range gives the identity.
TEST(Parallel, ReduceIsExactForAnyThreadCount) {
  std::mt19937 rng(20261123);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<Index> small(0, 9);
  const Index n = 10 * kMinParallelLoop + 7;
  std::vector<double> v(n);
  std::vector<Index> k(n);
  for (Index i = 0; i < n; ++i) v[i] = normal(rng), k[i] = small(rng);
  const int threads = omp_get_max_threads();
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    EXPECT_EQ(parallel_reduce(Exec{}, n, -1e300, ScalarAt{v.data()}, MaxOf{}), *std::max_element(v.begin(), v.end()));
    EXPECT_EQ(parallel_reduce(Exec{}, n, 1e300, ScalarAt{v.data()}, MinOf{}), *std::min_element(v.begin(), v.end()));
    EXPECT_EQ(parallel_reduce(Exec{}, n, Index{0}, IntAt{k.data()}, IntegerSum{}),
              std::accumulate(k.begin(), k.end(), 0));
    EXPECT_EQ(parallel_reduce(Exec{}, 0, -7.0, ScalarAt{v.data()}, MaxOf{}), -7.0);
  }
  omp_set_num_threads(threads);
}

// ordered_sum over enough blocks of 256 for the launcher to run them on two threads: the same bits on
// 1 and 2 threads, those of the block sums added in order, and the exact sum to rounding.
TEST(Parallel, OrderedSumIsTheSameForAnyThreadCount) {
  std::mt19937 rng(20261202);
  std::normal_distribution<double> normal;
  const Index n = 256 * (kMinParallelLoop + 3) + 17;
  std::vector<double> v(n);
  for (double& e : v) e = normal(rng);
  double blocked = 0;
  long double exact = 0;
  for (Index k = 0; k < n; k += 256) {
    double s = 0;
    for (Index i = k; i < std::min(n, k + 256); ++i) s += v[i];
    blocked += s;
  }
  for (double e : v) exact += e;
  StateVector<double> partial;
  const int threads = omp_get_max_threads();
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    const double sum = ordered_sum(Exec{}, n, ScalarAt{v.data()}, partial);
    EXPECT_EQ(sum, blocked) << t << " threads";
    EXPECT_NEAR(sum, static_cast<double>(exact), 1e-12 * n);
  }
  omp_set_num_threads(threads);
  EXPECT_EQ(ordered_sum(Exec{}, 0, ScalarAt{v.data()}, partial), 0.0);
}

TEST(Parallel, InclusiveScanGivesRowEnds) {
  std::vector<Index> counts{3, 0, 2, 5, 1}, ends = counts;
  inclusive_scan(Exec{}, ends.data(), static_cast<Index>(ends.size()));
  EXPECT_EQ(ends, (std::vector<Index>{3, 3, 5, 10, 11}));
  inclusive_scan(Exec{}, ends.data(), 0);  // an empty range is left alone
  EXPECT_EQ(ends[0], 3);
}

// The stable sort by key: keys come out sorted, and values with equal keys keep their order (the AMG's
// transpose relies on it for columns in increasing order within each transposed row).
TEST(Parallel, StableSortByKeyKeepsTheOrderOfEqualKeys) {
  std::mt19937 rng(20261201);
  std::uniform_int_distribution<Index> key(0, 6);
  const Index n = 1000;
  std::vector<Index> keys(n), values(n);
  for (Index i = 0; i < n; ++i) keys[i] = key(rng), values[i] = i;
  const std::vector<Index> original = keys;
  stable_sort_by_key(Exec{}, keys.data(), values.data(), n, 7);
  EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
  for (Index q = 0; q < n; ++q) {
    EXPECT_EQ(original[values[q]], keys[q]) << q;
    if (q > 0 && keys[q] == keys[q - 1]) {
      EXPECT_LT(values[q - 1], values[q]) << q;
    }
  }
  stable_sort_by_key(Exec{}, keys.data(), values.data(), 0, 7);  // an empty range is left alone
}
