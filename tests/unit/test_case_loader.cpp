// The case loader: defaults, every class of problem, overrides, the resolved configuration.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/case_loader.hpp"

namespace isph {
namespace {

namespace fs = std::filesystem;

// A small valid 2D case: a clamped beam with a tip load and a probe.
const std::string kBeam = R"(
dx = 0.01
end_time = 1

[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3

[[bodies]]
name = "beam"
material = "steel"
shape = { type = "rectangle", min = [0, 0], max = [1, 0.1] }
clamps = [{ type = "rectangle", min = [0, 0], max = [0.05, 0.1] }]

[[loads]]
type = "point"
body = "beam"
point = [1, 0.05]
force = [0, -1000]

[[probes]]
name = "tip"
point = [1, 0.05]
)";

class CaseLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("isph_case_loader_" + std::string(test->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `text` to `name` in the test's directory and returns its path.
  std::string write(const std::string& name, const std::string& text) {
    const auto path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  // The problems load_case reports (none if it succeeds).
  static std::vector<std::string> problems(const std::string& path,
                                           const std::vector<std::string>& overrides = {}) {
    try {
      load_case(path, overrides);
    } catch (const CaseError& e) {
      return e.problems();
    }
    return {};
  }

  fs::path dir_;
};

// Whether `expected` is one of `problems`; the list is printed when it is not.
::testing::AssertionResult reports(const std::vector<std::string>& problems, const std::string& expected) {
  if (std::find(problems.begin(), problems.end(), expected) != problems.end())
    return ::testing::AssertionSuccess();
  auto failure = ::testing::AssertionFailure()
                 << "\"" << expected << "\" not among the " << problems.size() << " problems:";
  for (const auto& p : problems) failure << "\n  " << p;
  return failure;
}

TEST_F(CaseLoaderTest, MinimalCaseLoadsWithDefaults) {
  const auto path = write("minimal.toml", kBeam);
  const CaseSpec c = load_case(path);
  EXPECT_EQ(c.name, "minimal");
  EXPECT_EQ(c.source_path, path);
  EXPECT_EQ(c.dimension, 2);
  EXPECT_DOUBLE_EQ(c.dx, 0.01);
  EXPECT_DOUBLE_EQ(c.end_time, 1.0);  // an integer where a float is expected
  EXPECT_EQ(c.gravity, (std::array<double, 3>{0, 0, 0}));
  EXPECT_EQ(c.kernel.type, "cubic_spline");
  EXPECT_DOUBLE_EQ(c.kernel.h_factor, 1.2);
  EXPECT_TRUE(c.kernel.correction);
  EXPECT_EQ(c.structure.integrator, "rk4");
  EXPECT_DOUBLE_EQ(c.structure.courant, 0.5);
  EXPECT_TRUE(c.output.snapshots);
  EXPECT_TRUE(c.stages.structure);
  EXPECT_FALSE(c.stages.fluid);

  ASSERT_EQ(c.materials.size(), 1u);
  EXPECT_EQ(c.materials[0].model, "saint_venant_kirchhoff");
  EXPECT_EQ(c.materials[0].plane, "strain");
  EXPECT_DOUBLE_EQ(c.materials[0].youngs_modulus, 2e11);

  ASSERT_EQ(c.bodies.size(), 1u);
  const BodySpec& beam = c.bodies[0];
  EXPECT_EQ(beam.kind, ParticleKind::structure);
  EXPECT_EQ(beam.shape.type, "rectangle");
  EXPECT_EQ(beam.shape.max, (std::array<double, 3>{1, 0.1, 0}));
  ASSERT_EQ(beam.clamps.size(), 1u);
  EXPECT_EQ(beam.lattice_origin, beam.shape.min);
  EXPECT_EQ(beam.initial_velocity.type, "none");

  ASSERT_EQ(c.loads.size(), 1u);
  EXPECT_EQ(c.loads[0].region.type, "point");
  EXPECT_EQ(c.loads[0].region.center, (std::array<double, 3>{1, 0.05, 0}));
  EXPECT_DOUBLE_EQ(c.loads[0].ramp_time, 0.0);

  ASSERT_EQ(c.probes.size(), 1u);
  EXPECT_EQ(c.probes[0].type, "displacement");
}

TEST_F(CaseLoaderTest, CircleLatticeOriginAndInitialVelocity) {
  const auto path = write("disc.toml", kBeam + R"(
[[bodies]]
name = "disc"
material = "steel"
shape = { type = "circle", center = [2, 1], radius = 0.5 }
initial_velocity = { type = "cantilever_mode", tip_velocity = 0.1, length = 1, axis = [2, 0] }
)");
  const CaseSpec c = load_case(path);
  ASSERT_EQ(c.bodies.size(), 2u);
  EXPECT_EQ(c.bodies[1].lattice_origin, (std::array<double, 3>{1.5, 0.5, 0}));
  const auto& v = c.bodies[1].initial_velocity;
  EXPECT_EQ(v.type, "cantilever_mode");
  EXPECT_DOUBLE_EQ(v.kL, 1.875);
  EXPECT_EQ(v.axis, (std::array<double, 3>{1, 0, 0}));  // normalized
}

TEST_F(CaseLoaderTest, UnknownKeysAtEveryLevel) {
  const auto path = write("unknown.toml", "colour = \"red\"\n" + kBeam + "[kernel]\nhfactor = 1.3\n");
  auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": colour: unknown key"));
  EXPECT_TRUE(reports(p, path + ": kernel.hfactor: unknown key"));

  const auto nested = write("nested.toml", R"(
dx = 0.01
end_time = 1
[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3
colour = "grey"
[[bodies]]
name = "beam"
material = "steel"
shape = { type = "rectangle", min = [0, 0], max = [1, 0.1], radius = 1 }
)");
  p = problems(nested);
  EXPECT_TRUE(reports(p, nested + ": materials[0].colour: unknown key"));
  EXPECT_TRUE(reports(p, nested + ": bodies[0].shape.radius: unknown key"));
  EXPECT_EQ(p.size(), 2u);
}

TEST_F(CaseLoaderTest, WrongTypesAndMissingKeys) {
  const auto path = write("types.toml", R"(
dx = "fine"
gravity = [0, "down"]
[kernel]
correction = 1
[[probes]]
point = [0, 0, 0]
)");
  const auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": dx: expected a number, got a string"));
  EXPECT_TRUE(reports(p, path + ": end_time: missing required key"));
  EXPECT_TRUE(reports(p, path + ": gravity[1]: expected a number, got a string"));
  EXPECT_TRUE(reports(p, path + ": kernel.correction: expected a boolean, got an integer"));
  EXPECT_TRUE(reports(p, path + ": probes[0].name: missing required key"));
  EXPECT_TRUE(reports(p, path + ": probes[0].point: expected 2 numbers (dimension = 2), got 3"));
}

TEST_F(CaseLoaderTest, OutOfRangeNumbers) {
  std::string text = kBeam;
  text.replace(text.find("dx = 0.01"), 9, "dx = -0.01");
  text.replace(text.find("youngs_modulus = 2e11"), 21, "youngs_modulus = 0");
  text.replace(text.find("poisson_ratio = 0.3"), 19, "poisson_ratio = 0.5");
  const auto path = write("range.toml", text);
  const auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": dx: must be > 0 (got -0.01)"));
  EXPECT_TRUE(reports(p, path + ": materials[0].youngs_modulus: must be > 0 (got 0)"));
  EXPECT_TRUE(reports(p, path + ": materials[0].poisson_ratio: must be < 0.5 (got 0.5)"));
  EXPECT_EQ(p.size(), 3u);
}

TEST_F(CaseLoaderTest, UnknownMaterialReference) {
  std::string text = kBeam;
  text.replace(text.find("material = \"steel\""), 18, "material = \"stell\"");
  const auto path = write("reference.toml", text);
  EXPECT_TRUE(
      reports(problems(path), path + ": bodies[0].material: no material named \"stell\" (known: \"steel\")"));
}

TEST_F(CaseLoaderTest, ShapeTypeMustMatchTheDimension) {
  const auto path = write("shape.toml", kBeam + R"(
[[bodies]]
name = "ball"
material = "steel"
shape = { type = "sphere", center = [0, 0], radius = 1 }
clamps = [{ type = "triangle" }]
)");
  const auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": bodies[1].shape.type: \"sphere\" is a 3D shape, but dimension = 2; "
                                "must be one of \"rectangle\", \"circle\""));
  EXPECT_TRUE(reports(p, path + ": bodies[1].clamps[0].type: must be one of \"rectangle\", \"circle\" "
                                "(got \"triangle\")"));
  EXPECT_EQ(p.size(), 2u);  // the other keys of a shape with a bad type are not judged
}

TEST_F(CaseLoaderTest, EmptyBoxIsAnError) {
  std::string text = kBeam;
  text.replace(text.find("max = [1, 0.1]"), 14, "max = [1, 0]");
  const auto path = write("flat.toml", text);
  EXPECT_TRUE(
      reports(problems(path),
              path + ": bodies[0].shape.max: must be > min in every component (component 1: min 0, max 0)"));
}

TEST_F(CaseLoaderTest, FluidStageIsNotAvailable) {
  const auto path = write("fluid.toml", kBeam + "[stages]\nfluid = true\n");
  EXPECT_TRUE(reports(problems(path), path + ": stages.fluid: the fluid stage is not available yet"));
}

TEST_F(CaseLoaderTest, MissingFile) {
  const auto path = (dir_ / "absent.toml").string();
  EXPECT_EQ(problems(path), std::vector<std::string>{path + ": cannot open file"});
}

TEST_F(CaseLoaderTest, ParseError) {
  const auto path = write("broken.toml", "dx = [0.1,\n");
  const auto p = problems(path);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].rfind(path + ": parse error: ", 0), 0u) << p[0];
}

TEST_F(CaseLoaderTest, DuplicateNames) {
  const auto path = write("duplicates.toml", kBeam + R"(
[[materials]]
name = "steel"
density = 2700
youngs_modulus = 7e10
poisson_ratio = 0.33

[[probes]]
name = "tip"
point = [0.5, 0]

[[probes]]
name = "mid point"
point = [0.5, 0]
)");
  const auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": materials[1].name: duplicate name \"steel\" (also materials[0])"));
  EXPECT_TRUE(reports(p, path + ": probes[1].name: duplicate name \"tip\" (also probes[0])"));
  EXPECT_TRUE(reports(p, path + ": probes[2].name: must match [A-Za-z0-9_]+ (got \"mid point\")"));
}

TEST_F(CaseLoaderTest, AllProblemsAreReportedAtOnce) {
  const auto path = write("many.toml", R"(
dimension = 3
dx = 0
end_time = 1
[structure]
integrator = "euler"
[[materials]]
name = "steel"
density = -1
bulk_modulus = 1e9
youngs_modulus = 1e9
poisson_ratio = 0.3
plane = "stress"
[[loads]]
type = "body"
body = "nothing"
acceleration = [0, 0, -9.81]
)");
  try {
    load_case(path);
    FAIL() << "expected a CaseError";
  } catch (const CaseError& e) {
    const std::vector<std::string> expected = {
        path + ": dx: must be > 0 (got 0)",
        path + ": structure.integrator: must be one of \"rk4\", \"verlet\" (got \"euler\")",
        path + ": materials[0].density: must be > 0 (got -1)",
        path + ": materials[0].youngs_modulus: give youngs_modulus or bulk_modulus, not both",
        path + ": materials[0].plane: only used in 2D (dimension = 3)",
        path + ": loads[0].body: no body named \"nothing\" (none defined)",
    };
    for (const auto& problem : expected) EXPECT_TRUE(reports(e.problems(), problem));
    EXPECT_EQ(e.problems().size(), expected.size());
    EXPECT_NE(std::string(e.what()).find(expected[0] + "\n" + expected[1]), std::string::npos);
  }
}

TEST_F(CaseLoaderTest, BulkModulusDerivesYoungsModulus) {
  std::string text = kBeam;
  text.replace(text.find("youngs_modulus = 2e11"), 21, "bulk_modulus = 1e9");
  const CaseSpec c = load_case(write("bulk.toml", text));
  EXPECT_DOUBLE_EQ(c.materials[0].youngs_modulus, 3.0 * 1e9 * (1.0 - 2.0 * 0.3));
}

TEST_F(CaseLoaderTest, OverridesByIndexAndByName) {
  const auto path = write("beam.toml", kBeam);
  const CaseSpec c = load_case(path, {
                                         "dx=0.002",
                                         "kernel.correction=false",
                                         "gravity=[0,-9.81]",
                                         "structure.integrator=verlet",  // unquoted: taken as a string
                                         "materials.0.density=8000",
                                         "materials.steel.youngs_modulus=1e9",
                                         "probes.tip.point=[0.1,0]",
                                         "name = renamed",
                                     });
  EXPECT_DOUBLE_EQ(c.dx, 0.002);
  EXPECT_FALSE(c.kernel.correction);
  EXPECT_EQ(c.gravity, (std::array<double, 3>{0, -9.81, 0}));
  EXPECT_EQ(c.structure.integrator, "verlet");
  EXPECT_DOUBLE_EQ(c.materials[0].density, 8000.0);
  EXPECT_DOUBLE_EQ(c.materials[0].youngs_modulus, 1e9);
  EXPECT_EQ(c.probes[0].point, (std::array<double, 3>{0.1, 0, 0}));
  EXPECT_EQ(c.name, "renamed");
}

TEST_F(CaseLoaderTest, BadOverrides) {
  const auto path = write("beam.toml", kBeam);
  const auto p = problems(path, {"kernel.hfactor=1.3", "dx", "materials.copper.density=1", "dx.value=1"});
  EXPECT_TRUE(reports(p, path + ": kernel.hfactor: unknown key"));
  EXPECT_TRUE(reports(p, "--set dx: expected key=value"));
  EXPECT_TRUE(
      reports(p, "--set materials.copper.density=1: materials: no element with index or name \"copper\""));
  EXPECT_TRUE(reports(p, "--set dx.value=1: dx: is a float, not a table or an array"));
  EXPECT_EQ(p.size(), 4u);
}

TEST_F(CaseLoaderTest, ResolvedTomlReloadsToTheSameCase) {
  const auto path = write("original.toml", "gravity = [0, -9.81]\n" + kBeam + R"(
[[loads]]
type = "edge"
body = "beam"
region = { type = "circle", center = [1, 0.05], radius = 0.02 }
force = [0, -1]
ramp_time = 0.1
)");
  const auto first = load_case(path, {"materials.steel.poisson_ratio=0.25",
                                      "bodies.beam.initial_velocity={ type = \"uniform\", value = [1, 2] }"});
  const auto second = load_case(write("resolved.toml", first.resolved_toml));
  EXPECT_EQ(second.name, "original");
  EXPECT_EQ(second.gravity, first.gravity);
  EXPECT_EQ(second.kernel.h_factor, first.kernel.h_factor);
  EXPECT_EQ(second.materials[0].poisson_ratio, 0.25);
  EXPECT_EQ(second.materials[0].youngs_modulus, first.materials[0].youngs_modulus);
  EXPECT_EQ(second.bodies[0].initial_velocity.value, (std::array<double, 3>{1, 2, 0}));
  EXPECT_EQ(second.bodies[0].clamps[0].max, first.bodies[0].clamps[0].max);
  EXPECT_EQ(second.loads[1].region.radius, 0.02);
  EXPECT_EQ(second.loads[1].ramp_time, 0.1);
  EXPECT_EQ(second.resolved_toml, first.resolved_toml);  // resolving is idempotent
}

TEST(ShapeTest, RectangleContainsItsFaces) {
  const Shape r{.type = "rectangle", .min = {0, 0, 0}, .max = {0.3, 0.1, 0}};
  EXPECT_TRUE(r.contains({0.15, 0.05, 0}, 2));
  EXPECT_TRUE(r.contains({0.3, 0.1, 0}, 2));
  EXPECT_TRUE(r.contains({3 * 0.1, 0.05, 0}, 2));  // 0.30000000000000004: on the face
  EXPECT_TRUE(r.contains({0.15, 0.05, 7}, 2));     // the third component does not count in 2D
  EXPECT_FALSE(r.contains({0.3 + 1e-9, 0.05, 0}, 2));
  EXPECT_FALSE(r.contains({0.15, -1e-9, 0}, 2));
}

TEST(ShapeTest, SphereContainsItsSurface) {
  const Shape s{.type = "sphere", .center = {1, 1, 1}, .radius = 0.5};
  EXPECT_TRUE(s.contains({1.5, 1, 1}, 3));
  EXPECT_TRUE(s.contains({1, 1, 0.5}, 3));
  EXPECT_FALSE(s.contains({1.4, 1.4, 1}, 3));
  EXPECT_FALSE(s.contains({1, 1, 1.5 + 1e-9}, 3));
  const Shape point{.type = "point", .center = {1, 1, 1}};
  EXPECT_FALSE(point.contains({1, 1, 1}, 3));
}

}  // namespace
}  // namespace isph
