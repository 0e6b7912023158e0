// Coupled ISPH-TLSPH runs at coarse resolution (seconds each), asserting physics: a plate under a
// water column deflects downwards by about the static deflection, no fluid enters it, and the
// staggered scheme (no interface iterations) is the one that fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "run_support.hpp"

namespace {

// The hydrostatic plate with a water column 0.5 m deep (instead of 2 m) at T/dx = 4, for 12 ms.
// Static mid-span deflection (reference README, seed Eq. 53 with H = 0.5 m):
// 12 g (1 - nu^2)(rho_w H + rho_s T) L^4 / (384 E T^3) = 2.04e-5 m.
constexpr double kStatic = 12 * 9.81 * (1 - 0.34 * 0.34) * (1000 * 0.5 + 2700 * 0.05) / (384 * 67.5e9 * 0.05 * 0.05 * 0.05);

CommandResult run_small_plate(const fs::path& out, const std::string& extra) {
  const std::string shallow =
      " --set 'bodies.water.shape={type=\"rectangle\",min=[0.0,0.0],max=[1.0,0.5]}'"
      " --set 'bodies.left_wall.shape={type=\"rectangle\",min=[-0.0375,0.0],max=[0.0,0.6]}'"
      " --set 'bodies.right_wall.shape={type=\"rectangle\",min=[1.0,0.0],max=[1.0375,0.6]}'";
  return isph("run " + kCases + "hydrostatic_plate.toml --quiet --out " + out.string() +
              " --set dx=0.0125 --set end_time=0.012 --set output.interval=0.0005 --set output.snapshots=false" +
              shallow + extra);
}

}  // namespace

TEST(CoupledPlate, DeflectsDownwardsByTheStaticDeflectionWithoutPenetration) {
  const fs::path out = fresh_dir("coupled_plate");
  const auto r = run_small_plate(out, "");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto probes = read_csv(out / "probes.csv");
  const auto& uy = probes.at("midspan.uy");
  const double lowest = *std::min_element(uy.begin(), uy.end());
  const double mean = std::accumulate(uy.begin(), uy.end(), 0.0) / uy.size();
  // A suddenly applied load overshoots to about twice the static deflection; the run holds about one
  // oscillation, whose mean is about the static deflection.
  EXPECT_LT(lowest, -1.2 * kStatic);
  EXPECT_GT(lowest, -3.0 * kStatic);
  EXPECT_LT(mean, -0.5 * kStatic);
  EXPECT_GT(mean, -1.6 * kStatic);
  const std::string s = read_file(out / "summary.json");
  EXPECT_EQ(json_number(s, "fluid_inside_structure_max"), 0) << s;
  EXPECT_GT(json_number(s, "min_fluid_structure_distance"), 0.5 * 0.0125) << s;
  EXPECT_EQ(json_number(s, "unconverged_steps"), 0) << s;
}

// A plate clamped over its whole length carries the weight of the water, 0.5 m deep over the 1 m span,
// through the pairwise pressure force (within 3 %; docs/VALIDATION.md compares the gradient form).
TEST(CoupledPlate, RigidPlateCarriesTheWaterWeight) {
  const fs::path out = fresh_dir("coupled_plate_rigid");
  const auto r = run_small_plate(
      out, " --set end_time=0.005 --set 'bodies.plate.clamps=[{type=\"rectangle\",min=[-0.05,-0.05],max=[1.05,0.0]}]'");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string s = read_file(out / "summary.json");
  const double weight = 1000 * 9.81 * 0.5;
  EXPECT_NEAR(-json_number(s, "fy"), weight, 0.03 * weight) << s;
  EXPECT_NEAR(json_number(s, "fx"), 0.0, 1e-6 * weight) << s;
}

// Without interface iterations the water's added mass (3.7 times the plate's) makes the coupling unstable.
TEST(CoupledPlate, StaggeredCouplingFailsWhereIterationsHold) {
  const fs::path out = fresh_dir("coupled_plate_staggered");
  const auto r = run_small_plate(out, " --set coupling.max_iterations=1");
  const std::string s = read_file(out / "summary.json");
  const auto probes = read_csv(out / "probes.csv");
  const auto& uy = probes.at("midspan.uy");
  const double lowest = *std::min_element(uy.begin(), uy.end());
  const bool diverged = s.find("\"status\": \"diverged\"") != std::string::npos;
  EXPECT_TRUE(diverged || lowest < -10 * kStatic) << s;
}

TEST(BadCoupledInput, ClearErrors) {
  const std::string plate = kCases + "hydrostatic_plate.toml";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"check " + plate + " --set 'bodies.left_wall.shape={type=\"rectangle\",min=[-0.0375,-0.02],max=[0.0,2.1]}'",
       "wall particles lie inside this structure body 'plate'"},
      {"check " + plate + " --set 'bodies.plate.clamps=[{type=\"rectangle\",min=[3.0,3.0],max=[3.1,3.1]}]'",
       "the clamp region holds no particle"},
      {"check " + plate + " --set coupling.substeps=-1", "coupling.substeps"},
      {"check " + plate + " --set coupling.interaction_force=\\\"average\\\"", "interaction_force"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = isph(args);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << "\n" << r.output;
  }
}
