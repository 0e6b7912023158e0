// The energy books (src/sim/energy_books.hpp): the releasable potential energy of a known set, and
// when the books stop a run.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sim/energy_books.hpp"

namespace isph {
namespace {

TEST(EnergyBooks, ReleasablePotentialOfAColumnIsHalfItsWeightTimesItsHeight) {
  // 11 particles of 2 kg at heights 0..1 m under g = 9.81 downwards, the lowest at 0.3 m in a raised set:
  // sum m g (y - y_min) = 2 * 9.81 * (0 + 0.1 + ... + 1.0) = 2 * 9.81 * 5.5.
  std::vector<Vec<2>> x;
  for (int k = 0; k <= 10; ++k) x.push_back(Vec<2>{0.5, 0.3 + 0.1 * k});
  const Vec<2> g{0, -9.81};
  const Real e = releasable_potential_energy<2>(
      std::span<const Vec<2>>(x), [](std::size_t) { return 2.0; }, g);
  EXPECT_NEAR(e, 2 * 9.81 * 5.5, 1e-9);
  // Particles of no mass (walls in the fluid's set) neither count nor lower the datum.
  x.push_back(Vec<2>{0, -5});
  const Real with_wall = releasable_potential_energy<2>(
      std::span<const Vec<2>>(x), [&](std::size_t a) { return a < 11 ? 2.0 : 0.0; }, g);
  EXPECT_NEAR(with_wall, e, 1e-9);
  // Without gravity nothing is releasable.
  EXPECT_EQ(releasable_potential_energy<2>(
                std::span<const Vec<2>>(x), [](std::size_t) { return 1.0; }, Vec<2>{0, 0}),
            0);
}

TEST(EnergyBooks, LostEnergyNeverStopsARun) {
  EnergyBooks books(/*initial_total=*/-50.0, /*initial_energy=*/100.0);
  for (int k = 0; k < 100; ++k) EXPECT_FALSE(books.post(0.01 * k, -50.0 - k, 0.0)) << k;
  EXPECT_EQ(books.peak_created_fraction(), 0.0);
}

TEST(EnergyBooks, CreatedEnergyBeyondTheBoundStopsTheRunAndSaysWhen) {
  EnergyBooks books(10.0, 100.0);
  // 0.24 of the scale created: still within the bound.
  EXPECT_FALSE(books.post(0.1, 10.0 + 24.0, 0.0));
  EXPECT_NEAR(books.peak_created_fraction(), 0.24, 1e-12);
  const auto broken = books.post(0.2, 10.0 + 26.0, 0.0);
  ASSERT_TRUE(broken);
  EXPECT_NE(broken->find("t = 0.2 s"), std::string::npos) << *broken;
  EXPECT_NE(broken->find("0.26 times"), std::string::npos) << *broken;
  // A non-finite total breaks the books too.
  EnergyBooks nan_books(10.0, 100.0);
  EXPECT_TRUE(nan_books.post(0.1, std::numeric_limits<Real>::quiet_NaN(), 0.0));
}

TEST(EnergyBooks, TheWorkOfMovingBoundariesWidensTheScale) {
  // A tank whose walls have done 400 J of work (either way) may hold 0.25 * (100 + 400) J more than it
  // started with before the books break.
  EnergyBooks books(0.0, 100.0);
  EXPECT_FALSE(books.post(1.0, 0.0, -400.0));
  EXPECT_NEAR(books.scale(), 500.0, 1e-12);
  EXPECT_FALSE(books.post(2.0, 120.0, 10.0));  // the largest work so far is kept
  EXPECT_TRUE(books.post(3.0, 130.0, 10.0));
  // A restart continues the books with the work seen before it, and the largest fraction created so
  // far (0.24 = 120 J of 500 J), which a later, lower total does not lower.
  EnergyBooks continued = EnergyBooks::continued(0.0, 100.0, 400.0, 0.24);
  EXPECT_FALSE(continued.post(2.0, 20.0, 0.0));
  EXPECT_NEAR(continued.peak_created_fraction(), 0.24, 1e-12);
  EXPECT_TRUE(continued.post(3.0, 130.0, 0.0));
}

}  // namespace
}  // namespace isph
