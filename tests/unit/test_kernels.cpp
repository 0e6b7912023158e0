// Smoothing kernels and the corrected gradient.
#include <gtest/gtest.h>

#include <random>

#include "core/neighbour_search.hpp"
#include "kernels/gradient_correction.hpp"
#include "kernels/smoothing_kernel.hpp"

using namespace isph;

namespace {

template <int D>
std::vector<Vec<D>> lattice(int per_side, Real dx, Real jitter, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-jitter, jitter);
  std::vector<Vec<D>> x;
  const int total = D == 2 ? per_side * per_side : per_side * per_side * per_side;
  for (int k = 0; k < total; ++k) {
    Vec<D> p;
    int r = k;
    for (int d = 0; d < D; ++d) {
      p[d] = ((r % per_side) + 0.5 + u(rng)) * dx;
      r /= per_side;
    }
    x.push_back(p);
  }
  return x;
}

// Integral of W over a fine lattice: must be 1 (normalisation), and the gradient must be -dW/dr direction.
template <int D>
Real kernel_integral(KernelType type) {
  const Real h = 1.0, dx = 0.02;
  const auto k = SmoothingKernel<D>::make(type, h);
  const int n = static_cast<int>(2 * k.support() / dx);
  Real sum = 0;
  const int total = D == 2 ? n * n : n * n * n;
  for (int c = 0; c < total; ++c) {
    Vec<D> p;
    int r = c;
    for (int d = 0; d < D; ++d) {
      p[d] = -k.support() + ((r % n) + 0.5) * dx;
      r /= n;
    }
    sum += k.value(std::sqrt(norm2(p))) * (D == 2 ? dx * dx : dx * dx * dx);
  }
  return sum;
}

}  // namespace

TEST(Kernels, IntegrateToOne) {
  EXPECT_NEAR(kernel_integral<2>(KernelType::cubic_spline), 1.0, 2e-4);
  EXPECT_NEAR(kernel_integral<2>(KernelType::wendland_c2), 1.0, 2e-4);
  EXPECT_NEAR(kernel_integral<3>(KernelType::cubic_spline), 1.0, 2e-4);
  EXPECT_NEAR(kernel_integral<3>(KernelType::wendland_c2), 1.0, 2e-4);
}

TEST(Kernels, DerivativeMatchesFiniteDifferenceAndVanishesAtSupport) {
  for (auto type : {KernelType::cubic_spline, KernelType::wendland_c2}) {
    const auto k = SmoothingKernel<2>::make(type, 0.3);
    for (Real r = 0.01; r < 0.6; r += 0.037) {
      const Real e = 1e-6;
      const Real fd = (k.value(r + e) - k.value(r - e)) / (2 * e);
      EXPECT_NEAR(k.derivative(r), fd, 1e-6 * std::abs(k.norm));
    }
    EXPECT_EQ(k.value(0.6), 0.0);
    EXPECT_EQ(k.derivative(0.6), 0.0);
    EXPECT_NEAR(k.value(0.6 - 1e-9), 0.0, 1e-6);
  }
}

// The corrected gradient sum_b (f_b - f_a) L_a g_ab reproduces a linear field exactly, on an
// irregular particle set and at its edges (where the plain SPH gradient is badly wrong).
template <int D>
void check_corrected_gradient_exact_on_linear_fields(KernelType type) {
  const Real dx = 0.1;
  const auto x = lattice<D>(8, dx, 0.2, 7);
  const auto k = SmoothingKernel<D>::make(type, 1.3 * dx);
  const NeighbourList nl = build_neighbour_list<D>(x, k.support());
  Vec<D> grad_f;
  for (int d = 0; d < D; ++d) grad_f[d] = 0.7 + 1.1 * d;
  auto f = [&](const Vec<D>& p) { return 2.0 + dot(grad_f, p); };
  const Real V = D == 2 ? dx * dx : dx * dx * dx;
  Real worst_plain = 0;
  for (Index a = 0; a < static_cast<Index>(x.size()); ++a) {
    Mat<D> moment = Mat<D>::zero();
    Vec<D> plain = Vec<D>::zero();
    for (Index j = nl.offset[a]; j < nl.offset[a + 1]; ++j) {
      const Index b = nl.index[j];
      const Vec<D> g = V * k.gradient(x[a] - x[b]);
      moment = moment + outer(x[b] - x[a], g);
      plain += (f(x[b]) - f(x[a])) * g;
    }
    const Mat<D> L = correction_from_moment(moment);
    const Vec<D> corrected = L * plain;  // L applied to sum of (f_b - f_a) g_ab
    for (int d = 0; d < D; ++d) {
      EXPECT_NEAR(corrected[d], grad_f[d], 1e-10) << "particle " << a;
      worst_plain = std::max(worst_plain, std::abs(plain[d] - grad_f[d]));
    }
  }
  EXPECT_GT(worst_plain, 0.1);  // the uncorrected gradient is not exact: the test can fail
}

TEST(GradientCorrection, ExactOnLinearFields2D) {
  check_corrected_gradient_exact_on_linear_fields<2>(KernelType::cubic_spline);
  check_corrected_gradient_exact_on_linear_fields<2>(KernelType::wendland_c2);
}
TEST(GradientCorrection, ExactOnLinearFields3D) {
  check_corrected_gradient_exact_on_linear_fields<3>(KernelType::cubic_spline);
}

TEST(GradientCorrection, SingularMomentFallsBackToIdentity) {
  Mat<2> m = Mat<2>::zero();
  m(0, 0) = 1.0;  // a particle with neighbours along one line only
  const Mat<2> L = correction_from_moment(m);
  EXPECT_EQ(L(0, 0), 1.0);
  EXPECT_EQ(L(1, 1), 1.0);
  EXPECT_EQ(L(0, 1), 0.0);
}

// Neighbour search against brute force, 2D and 3D, on irregular points with a group filter.
template <int D>
void check_neighbours_against_brute_force(bool groups) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> u(0.0, 1.0);
  std::vector<Vec<D>> x(D == 2 ? 700 : 900);
  std::vector<int> group(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (int d = 0; d < D; ++d) x[i][d] = u(rng) * (d == 0 ? 2.0 : 1.0);
    group[i] = groups ? static_cast<int>(i % 3) : 0;
  }
  const Real radius = 0.13;
  const NeighbourList nl = build_neighbour_list<D>(x, radius, groups ? group.data() : nullptr);
  long long brute_pairs = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::vector<Index> expect;
    for (std::size_t j = 0; j < x.size(); ++j)
      if (i != j && norm2(x[i] - x[j]) < radius * radius && group[i] == group[j])
        expect.push_back(static_cast<Index>(j));
    std::vector<Index> got(nl.index.begin() + nl.offset[i], nl.index.begin() + nl.offset[i + 1]);
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, expect) << "particle " << i;
    brute_pairs += static_cast<long long>(expect.size());
  }
  EXPECT_EQ(nl.pairs(), brute_pairs);
  EXPECT_GT(brute_pairs, static_cast<long long>(x.size()));  // the test is not vacuous
}

TEST(NeighbourSearch, MatchesBruteForce2D) { check_neighbours_against_brute_force<2>(false); }
TEST(NeighbourSearch, MatchesBruteForce3D) { check_neighbours_against_brute_force<3>(false); }
TEST(NeighbourSearch, GroupFilter) { check_neighbours_against_brute_force<2>(true); }

TEST(NeighbourSearch, CellOrderIsAPermutationSortedByCell) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(0.0, 1.0);
  std::vector<Vec<2>> x(500);
  for (auto& p : x) p = {{u(rng), u(rng)}};
  CellList<2> cells;
  cells.build(x, 0.1);
  auto order = cells.order();
  const auto view = cells.view();
  for (std::size_t k = 1; k < order.size(); ++k)
    EXPECT_LE(view.grid.cell_of(x[order[k - 1]]), view.grid.cell_of(x[order[k]]));
  std::sort(order.begin(), order.end());
  for (std::size_t k = 0; k < order.size(); ++k) EXPECT_EQ(order[k], static_cast<Index>(k));
}
