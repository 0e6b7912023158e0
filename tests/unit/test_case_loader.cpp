// The case loader: defaults, every class of problem, overrides, the resolved configuration.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "io/case_loader.hpp"
#include "scratch_dir_test.hpp"
#include "sim/scene.hpp"

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

// A small valid 2D fluid case: a dam break (water column in a tank of three walls).
const std::string kDamBreak = R"(
dx = 0.01
end_time = 1
gravity = [0, -9.81]

[stages]
fluid = true

[fluid.shifting]
type = "xu"

[[materials]]
name = "water"
model = "newtonian"
density = 1000
viscosity = 1e-6

[[bodies]]
name = "water"
kind = "fluid"
material = "water"
shape = { type = "rectangle", min = [0, 0], max = [0.2, 0.4] }

[[bodies]]
name = "floor"
kind = "wall"
shape = { type = "rectangle", min = [-0.03, -0.03], max = [1.03, 0] }

[[bodies]]
name = "left"
kind = "wall"
shape = { type = "rectangle", min = [-0.03, 0], max = [0, 0.6] }

[[bodies]]
name = "right"
kind = "wall"
shape = { type = "rectangle", min = [1, 0], max = [1.03, 0.6] }

[[probes]]
name = "p_wall"
type = "pressure"
point = [0.995, 0.02]

[[probes]]
name = "front"
type = "front"
point = [0, 0.01]
)";

class CaseLoaderTest : public ScratchDirTest {
 protected:
  CaseLoaderTest() : ScratchDirTest("isph_case_loader_") {}

  // The problems load_case reports (none if it succeeds).
  static std::vector<std::string> problems(const std::string& path, const std::vector<std::string>& overrides = {}) {
    try {
      load_case(path, overrides);
    } catch (const CaseError& e) {
      return e.problems();
    }
    return {};
  }
};

// Whether `expected` is one of `problems`; the list is printed when it is not.
::testing::AssertionResult reports(const std::vector<std::string>& problems, const std::string& expected) {
  if (std::find(problems.begin(), problems.end(), expected) != problems.end()) return ::testing::AssertionSuccess();
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
  EXPECT_EQ(name_of(c.kernel.type), "cubic_spline");
  EXPECT_DOUBLE_EQ(c.kernel.h_factor, 1.2);
  EXPECT_TRUE(c.kernel.correction);
  EXPECT_EQ(name_of(c.structure.integrator), "rk4");
  EXPECT_DOUBLE_EQ(c.structure.courant, 0.5);
  EXPECT_TRUE(c.output.snapshots);
  EXPECT_TRUE(c.stages.structure);
  EXPECT_FALSE(c.stages.fluid);

  ASSERT_EQ(c.materials.size(), 1u);
  EXPECT_EQ(c.materials[0].model, MaterialModel::saint_venant_kirchhoff);
  EXPECT_EQ(name_of(c.materials[0].plane), "strain");
  EXPECT_DOUBLE_EQ(c.materials[0].youngs_modulus, 2e11);

  ASSERT_EQ(c.bodies.size(), 1u);
  const BodySpec& beam = c.bodies[0];
  EXPECT_EQ(beam.kind, ParticleKind::structure);
  EXPECT_EQ(beam.shape.type, ShapeType::rectangle);
  EXPECT_EQ(beam.shape.max, (std::array<double, 3>{1, 0.1, 0}));
  ASSERT_EQ(beam.clamps.size(), 1u);
  EXPECT_EQ(beam.lattice_origin, beam.shape.min);
  EXPECT_EQ(name_of(beam.initial_velocity.type), "none");

  ASSERT_EQ(c.loads.size(), 1u);
  EXPECT_EQ(c.loads[0].point, (std::array<double, 3>{1, 0.05, 0}));
  EXPECT_DOUBLE_EQ(c.loads[0].ramp_time, 0.0);

  ASSERT_EQ(c.probes.size(), 1u);
  EXPECT_EQ(name_of(c.probes[0].type), "displacement");
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
  EXPECT_EQ(name_of(v.type), "cantilever_mode");
  EXPECT_DOUBLE_EQ(v.kL, 1.875);
  EXPECT_EQ(v.axis, (std::array<double, 3>{1, 0, 0}));  // normalized
}

// lattice_offset = 0 on an axis puts particle columns on the faces through the origin: on the clamp's
// face at x = 0 and on the loaded end at x = 1; 1/2 (the default) centres them in their cells.
TEST_F(CaseLoaderTest, LatticeOffsetPlacesParticleRowsOnTheFaces) {
  const CaseSpec cell = load_case(write("cell.toml", kBeam));
  EXPECT_EQ(cell.bodies[0].lattice_offset, (std::array<double, 3>{0.5, 0.5, 0.5}));
  std::string text = kBeam;
  text.replace(text.find("clamps ="), 0, "lattice_offset = [0.0, 0.5]\n");
  const CaseSpec node = load_case(write("node.toml", text));
  const auto columns = [](const CaseSpec& spec, bool clamped_only) {
    const Scene<2> scene = build_scene<2>(spec);
    std::vector<double> x;
    for (std::size_t a = 0; a < scene.structure.X.size(); ++a)
      if (!clamped_only || scene.structure.fixed[a]) x.push_back(scene.structure.X[a][0]);
    std::sort(x.begin(), x.end());
    x.erase(std::unique(x.begin(), x.end(), [](double p, double q) { return std::abs(p - q) < 1e-9; }), x.end());
    return x;
  };
  const auto all_cell = columns(cell, false), all_node = columns(node, false);
  ASSERT_EQ(all_cell.size(), 100u);
  EXPECT_NEAR(all_cell.front(), 0.005, 1e-12);
  EXPECT_NEAR(all_cell.back(), 0.995, 1e-12);
  ASSERT_EQ(all_node.size(), 101u);
  EXPECT_NEAR(all_node.front(), 0.0, 1e-12);
  EXPECT_NEAR(all_node.back(), 1.0, 1e-12);
  const auto clamped = columns(node, true);  // the clamp [0, 0.05] holds the columns on both its faces
  ASSERT_EQ(clamped.size(), 6u);
  EXPECT_NEAR(clamped.back(), 0.05, 1e-12);

  text = kBeam;
  text.replace(text.find("clamps ="), 0, "lattice_offset = [1.0, 0.5]\n");
  const auto path = write("offset.toml", text);
  EXPECT_TRUE(reports(problems(path), path + ": bodies[0].lattice_offset: every component must be in [0, 1), in units "
                                             "of the body's spacing (got 1 in component 0)"));
}

// A traction load gives each loaded free particle traction * dx^(D-1): along the beam's top face, the
// 95 free particles of the top row carry 1000 Pa * 0.01 m each; the 5 clamped ones carry nothing.
TEST_F(CaseLoaderTest, TractionLoadsEachCellFace) {
  std::string text = kBeam;
  const auto first = text.find("[[loads]]"), last = text.find("[[probes]]");
  text.replace(first, last - first,
               "[[loads]]\ntype = \"traction\"\nbody = \"beam\"\n"
               "region = { type = \"rectangle\", min = [0, 0.099], max = [1, 0.1] }\ntraction = [0, -1000]\n\n");
  const CaseSpec spec = load_case(write("traction.toml", text));
  const Scene<2> scene = build_scene<2>(spec);
  const auto& s = scene.structure;
  ASSERT_EQ(s.loads.size(), 1u);
  int loaded = 0;
  Vec<2> total = Vec<2>::zero();
  for (std::size_t a = 0; a < s.X.size(); ++a) {
    const Vec<2> f = (7800 * s.volume[a]) * s.loads[0].acc[a];
    if (norm2(f) == 0) continue;
    ++loaded;
    EXPECT_NEAR(s.X[a][1], 0.095, 1e-12);
    EXPECT_FALSE(s.fixed[a]);
    EXPECT_NEAR(f[1], -10.0, 1e-9);
    total += f;
  }
  EXPECT_EQ(loaded, 95);
  EXPECT_NEAR(total[1], -950.0, 1e-7);
  EXPECT_NEAR(total[0], 0.0, 1e-12);
}

// A wedge's lattice: 2 x 20 columns 0.005 m apart from the keel, each of round(T / (s cos β)) = 4
// particles stacked along the vertical from the outer face; their cells sum to the panels' area
// 2 (B / cos β) T, every particle lies inside the shape, and the outer row lies on the outer face
// (half a pitch above it along the vertical).
TEST_F(CaseLoaderTest, WedgeIsFilledOnItsShearedLattice) {
  const double B = 0.1, T = 0.02, beta = 20.0 * std::numbers::pi / 180.0, s0 = 0.005;
  const CaseSpec spec = load_case(write("wedge_lattice.toml", R"(
dx = 0.01
end_time = 1
[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3
[[bodies]]
name = "hull"
material = "steel"
refinement = 2
shape = { type = "wedge", apex = [0.5, 0.2], half_breadth = 0.1, deadrise = 20, thickness = 0.02 }
clamps = [{ type = "rectangle", min = [0.4, 0.2], max = [0.405, 0.3] }]
)"));
  const Scene<2> scene = build_scene<2>(spec);
  const auto& st = scene.structure;
  const int layers = static_cast<int>(std::lround(T / (s0 * std::cos(beta))));
  ASSERT_EQ(layers, 4);
  ASSERT_EQ(st.X.size(), 2u * 20u * layers);
  const double pitch = T / std::cos(beta) / layers;
  double area = 0;
  int clamped = 0, outer = 0;
  for (std::size_t a = 0; a < st.X.size(); ++a) {
    area += st.volume[a];
    EXPECT_TRUE(spec.bodies[0].shape.contains({st.X[a][0], st.X[a][1], 0.0}, 2));
    clamped += st.fixed[a];
    const double across = std::abs(st.X[a][0] - 0.5);
    const double above = st.X[a][1] - 0.2 - across * std::tan(beta);
    if (std::abs(above - 0.5 * pitch) < 1e-12) ++outer;
  }
  EXPECT_NEAR(area, 2 * (B / std::cos(beta)) * T, 1e-12);
  EXPECT_EQ(clamped, layers);  // the outermost left column
  EXPECT_EQ(outer, 40);
}

// A structure body `refinement` times finer than the case's dx: its lattice has the spacing
// dx / refinement (four times as many particles in 2D, each a quarter of the volume), its traction
// load acts on the finer cells' faces (the same total), and the TLSPH kernel of its particles is the
// finer one (level 0 of the table, beside the case's dx). Fluid and wall bodies keep the case's dx.
TEST_F(CaseLoaderTest, RefinementMakesAStructureFinerThanTheCase) {
  std::string text = kBeam;
  const auto first = text.find("[[loads]]"), last = text.find("[[probes]]");
  text.replace(first, last - first,
               "[[loads]]\ntype = \"traction\"\nbody = \"beam\"\n"
               "region = { type = \"rectangle\", min = [0, 0.099], max = [1, 0.1] }\ntraction = [0, -1000]\n\n");
  text.replace(text.find("clamps ="), 0, "refinement = 2\n");
  const CaseSpec spec = load_case(write("refined.toml", text));
  EXPECT_EQ(spec.bodies[0].refinement, 2.0);
  const Scene<2> scene = build_scene<2>(spec);
  const auto& s = scene.structure;
  ASSERT_EQ(s.X.size(), 4u * 1000u);
  EXPECT_NEAR(s.volume[0], 0.005 * 0.005, 1e-15);
  ASSERT_EQ(s.kernels.levels, 2);
  EXPECT_NEAR(s.kernels.kernel[0].h, 1.2 * 0.005, 1e-15);
  EXPECT_NEAR(s.kernels.kernel[1].h, 1.2 * 0.01, 1e-15);
  for (unsigned char level : s.level) EXPECT_EQ(level, 0);
  Vec<2> total = Vec<2>::zero();
  int loaded = 0;
  for (std::size_t a = 0; a < s.X.size(); ++a) {
    const Vec<2> f = (7800 * s.volume[a]) * s.loads[0].acc[a];
    if (norm2(f) == 0) continue;
    ++loaded;
    EXPECT_NEAR(s.X[a][1], 0.0975, 1e-12);
    total += f;
  }
  EXPECT_EQ(loaded, 190);
  EXPECT_NEAR(total[1], -950.0, 1e-7);

  // the same body by its own spacing; not both keys; not coarser than the case
  std::string own = text;
  own.replace(own.find("refinement = 2"), 14, "dx = 0.005");
  const Scene<2> by_spacing = build_scene<2>(load_case(write("own_dx.toml", own)));
  ASSERT_EQ(by_spacing.structure.X.size(), s.X.size());
  for (std::size_t a = 0; a < s.X.size(); ++a) EXPECT_EQ(norm2(by_spacing.structure.X[a] - s.X[a]), 0.0);
  std::string both = text;
  both.replace(both.find("refinement = 2"), 0, "dx = 0.005\n");
  const auto both_path = write("both.toml", both);
  EXPECT_TRUE(reports(problems(both_path),
                      both_path + ": bodies[0].dx: give the body's spacing as dx or as refinement, not both"));
  std::string coarse = text;
  coarse.replace(coarse.find("refinement = 2"), 14, "dx = 0.02");
  EXPECT_THROW(build_scene<2>(load_case(write("coarse.toml", coarse))), CaseError);

  std::string water = kDamBreak;
  water.replace(water.find("shape = { type = \"rectangle\", min = [0, 0]"), 0, "refinement = 2\n");
  const auto bad = write("refined_water.toml", water);
  EXPECT_TRUE(reports(problems(bad), bad +
                                         ": bodies[0].refinement: only for kind = \"structure\"; fluid and walls take "
                                         "the case's dx (kind = \"fluid\")"));
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
  EXPECT_TRUE(reports(
      p,
      nested +
          ": bodies[0].shape.radius: only for type = \"circle\", \"sphere\" or \"cylinder\" (type = \"rectangle\")"));
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
  EXPECT_TRUE(reports(p, path + ": materials[0].poisson_ratio: must be > -1 and < 0.5 (got 0.5)"));
  EXPECT_EQ(p.size(), 3u);
}

TEST_F(CaseLoaderTest, UnknownMaterialReference) {
  std::string text = kBeam;
  text.replace(text.find("material = \"steel\""), 18, "material = \"stell\"");
  const auto path = write("reference.toml", text);
  EXPECT_TRUE(reports(problems(path), path + ": bodies[0].material: no material named \"stell\" (known: \"steel\")"));
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
                                "must be one of \"rectangle\", \"circle\", \"wedge\""));
  EXPECT_TRUE(reports(p, path + ": bodies[1].clamps[0].type: must be one of \"rectangle\", \"circle\", \"wedge\" "
                                "(got \"triangle\")"));
  EXPECT_EQ(p.size(), 2u);  // the other keys of a shape with a bad type are not judged
}

// A wedge is a 2D structure's shape, filled on its own lattice; it is no load region.
TEST_F(CaseLoaderTest, WedgeIsATwoDimensionalStructureShape) {
  const std::string wedge =
      R"(shape = { type = "wedge", apex = [0.5, 0.2], half_breadth = 0.1, deadrise = 10, thickness = 0.01 })";
  const auto path = write("wedge.toml", kBeam + R"(
[[bodies]]
name = "hull"
material = "steel"
)" + wedge + R"(
lattice_offset = [0.0, 0.5]
[[bodies]]
name = "rigid_hull"
kind = "wall"
)" + wedge + R"(
[[loads]]
type = "traction"
body = "hull"
region = { type = "wedge", apex = [0.5, 0.2], half_breadth = 0.1, deadrise = 10, thickness = 0.01 }
traction = [0, -1]
[[probes]]
name = "keel"
type = "structure_pressure"
point = [0.5, 0.2]
)");
  const auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": bodies[1].lattice_offset: not for a wedge, which is filled on its own lattice "
                                "(docs/CASES.md, shapes)"));
  EXPECT_TRUE(reports(p, path + ": bodies[2].shape: a wedge is a structure's shape (kind = \"wall\")"));
  EXPECT_TRUE(reports(p, path + ": loads[1].region: a load's region is a rectangle, circle, box, sphere or cylinder"));
  EXPECT_TRUE(reports(p, path + ": probes[1].type: \"structure_pressure\" probes need stages.fluid = true"));
}

// A force probe names a wall or structure body and takes no point; the key is for force probes only.
TEST_F(CaseLoaderTest, ForceProbeNamesAWallOrStructureBody) {
  const auto path = write("forces.toml", kDamBreak + R"(
[[probes]]
name = "on_floor"
type = "force"
body = "floor"
)");
  EXPECT_TRUE(problems(path).empty());
  EXPECT_EQ(load_case(path).probes[2].body, "floor");
  const auto p = problems(path, {"probes.on_floor.body=\"water\""});
  EXPECT_TRUE(reports(p, path + ": probes[2].body: a force probe needs a wall or structure body; \"water\" is of "
                                "kind = \"fluid\""));
  EXPECT_EQ(p.size(), 1u);
  EXPECT_TRUE(
      reports(problems(path, {"probes.on_floor.body=\"roof\""}),
              path + ": probes[2].body: no body named \"roof\" (known: \"water\", \"floor\", \"left\", \"right\")"));
  const auto pressure = problems(path, {"probes.on_floor.type=\"pressure\""});
  EXPECT_TRUE(reports(pressure, path + ": probes[2].point: missing required key"));
  EXPECT_TRUE(reports(pressure, path + ": probes[2].body: only for type = \"force\" (type = \"pressure\")"));
}

TEST_F(CaseLoaderTest, EmptyBoxIsAnError) {
  std::string text = kBeam;
  text.replace(text.find("max = [1, 0.1]"), 14, "max = [1, 0]");
  const auto path = write("flat.toml", text);
  EXPECT_TRUE(reports(problems(path),
                      path + ": bodies[0].shape.max: must be > min in every component (component 1: min 0, max 0)"));
}

TEST_F(CaseLoaderTest, FluidStageNeedsFluidBodies) {
  const auto path = write("fluid.toml", kBeam + "[stages]\nfluid = true\n");
  const auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": stages.fluid: needs at least one body of kind = \"fluid\""));
  EXPECT_EQ(p.size(), 1u);
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
        path +
            ": stages.structure: needs at least one body of kind = \"structure\" (or set stages.fluid = true "
            "for a fluid case)",
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
  EXPECT_EQ(name_of(c.structure.integrator), "verlet");
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
  EXPECT_TRUE(reports(p, "--set materials.copper.density=1: materials: no element with index or name \"copper\""));
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

TEST_F(CaseLoaderTest, FluidCaseLoadsWithDefaults) {
  const std::string path = write("dam_break.toml", kDamBreak);
  const CaseSpec c = load_case(path);
  EXPECT_TRUE(c.stages.fluid);
  EXPECT_FALSE(c.stages.structure);  // no structure bodies: the structure stage does not run

  ASSERT_EQ(c.materials.size(), 1u);
  EXPECT_EQ(c.materials[0].model, MaterialModel::newtonian);
  EXPECT_DOUBLE_EQ(c.materials[0].density, 1000.0);
  EXPECT_DOUBLE_EQ(c.materials[0].viscosity, 1e-6);

  ASSERT_EQ(c.bodies.size(), 4u);
  EXPECT_EQ(c.bodies[0].kind, ParticleKind::fluid);
  EXPECT_EQ(c.bodies[0].material, "water");
  EXPECT_EQ(name_of(c.bodies[0].initial_velocity.type), "none");
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_EQ(c.bodies[i].kind, ParticleKind::wall);
    EXPECT_TRUE(c.bodies[i].material.empty());
    EXPECT_EQ(name_of(c.bodies[i].motion.type), "none");
  }

  ASSERT_EQ(c.probes.size(), 2u);
  EXPECT_EQ(name_of(c.probes[0].type), "pressure");
  EXPECT_EQ(name_of(c.probes[1].type), "front");
  EXPECT_EQ(c.probes[1].point, (std::array<double, 3>{0, 0.01, 0}));

  const FluidSpec& f = c.fluid;
  EXPECT_DOUBLE_EQ(f.courant, 0.1);
  EXPECT_DOUBLE_EQ(f.viscous_number, 0.125);
  EXPECT_DOUBLE_EQ(f.reference_velocity, 0.0);
  EXPECT_DOUBLE_EQ(f.max_dt, 0.0);
  EXPECT_EQ(name_of(f.turbulence), "none");
  EXPECT_DOUBLE_EQ(f.smagorinsky, 0.1);
  EXPECT_TRUE(f.free_surface);
  EXPECT_DOUBLE_EQ(f.surface_threshold, 0.0);
  EXPECT_DOUBLE_EQ(f.surface_full, 0.0);
  EXPECT_EQ(name_of(f.shifting.type), "xu");
  EXPECT_DOUBLE_EQ(f.shifting.coefficient, 0.05);
  EXPECT_DOUBLE_EQ(f.shifting.max_fraction, 0.2);
  EXPECT_TRUE(f.shifting.taylor_correction);
  // BoomerAMG with Eigen behind it where the build has hypre; Eigen's ILUT alone otherwise.
  EXPECT_EQ(name_of(f.ppe.backend), hypre_available() ? "hypre" : "eigen");
  EXPECT_EQ(name_of(f.ppe.method), "bicgstab");
  EXPECT_EQ(name_of(f.ppe.preconditioner), hypre_available() ? "boomeramg" : "ilu");
  EXPECT_DOUBLE_EQ(f.ppe.tolerance, 1e-8);
  EXPECT_EQ(f.ppe.max_iterations, 1000);
  EXPECT_EQ(name_of(f.ppe.fallback), hypre_available() ? "eigen" : "none");
  // Naming a backend drops the default fallback (eigen would otherwise fall back on itself).
  const CaseSpec named = load_case(path, {"fluid.ppe.backend=eigen"});
  EXPECT_EQ(name_of(named.fluid.ppe.preconditioner), "ilu");
  EXPECT_EQ(name_of(named.fluid.ppe.fallback), "none");

  for (int k = 0; k < 3; ++k) EXPECT_FALSE(c.periodic.axis(k));
}

TEST_F(CaseLoaderTest, FluidTablesAndWallMotion) {
  const auto path = write("couette.toml", R"(
dx = 0.01
end_time = 1
[stages]
fluid = true
[fluid]
courant = 0.2
viscous_number = 0.1
reference_velocity = 1
max_dt = 1e-3
turbulence = "sps"
smagorinsky = 0.12
free_surface = false
surface_threshold = 1.3
surface_full = 1.5
[fluid.shifting]
type = "none"
coefficient = 0.1
max_fraction = 0.1
taylor_correction = false
[fluid.ppe]
backend = "hypre"
method = "gmres"
tolerance = 1e-6
max_iterations = 200
fallback = "eigen"
[periodic]
x = [0, 0.1]
[[materials]]
name = "oil"
model = "newtonian"
density = 900
viscosity = 1e-4
[[bodies]]
name = "oil"
kind = "fluid"
material = "oil"
shape = { type = "rectangle", min = [0, 0], max = [0.1, 0.1] }
initial_velocity = { type = "uniform", value = [0.5, 0] }
[[bodies]]
name = "plate"
kind = "wall"
motion = { type = "constant_velocity", velocity = [1, 0] }
shape = { type = "rectangle", min = [0, 0.1], max = [0.1, 0.13] }
[[probes]]
name = "u_mid"
type = "velocity"
point = [0.05, 0.05]
)");
  const CaseSpec c = load_case(path);
  const FluidSpec& f = c.fluid;
  EXPECT_DOUBLE_EQ(f.courant, 0.2);
  EXPECT_DOUBLE_EQ(f.viscous_number, 0.1);
  EXPECT_DOUBLE_EQ(f.reference_velocity, 1.0);
  EXPECT_DOUBLE_EQ(f.max_dt, 1e-3);
  EXPECT_EQ(name_of(f.turbulence), "sps");
  EXPECT_DOUBLE_EQ(f.smagorinsky, 0.12);
  EXPECT_FALSE(f.free_surface);
  EXPECT_DOUBLE_EQ(f.surface_threshold, 1.3);
  EXPECT_DOUBLE_EQ(f.surface_full, 1.5);
  EXPECT_EQ(name_of(f.shifting.type), "none");
  EXPECT_DOUBLE_EQ(f.shifting.coefficient, 0.1);
  EXPECT_DOUBLE_EQ(f.shifting.max_fraction, 0.1);
  EXPECT_FALSE(f.shifting.taylor_correction);
  EXPECT_EQ(name_of(f.ppe.backend), "hypre");
  EXPECT_EQ(name_of(f.ppe.method), "gmres");
  EXPECT_EQ(name_of(f.ppe.preconditioner), "boomeramg");  // the default of hypre
  EXPECT_DOUBLE_EQ(f.ppe.tolerance, 1e-6);
  EXPECT_EQ(f.ppe.max_iterations, 200);
  EXPECT_EQ(name_of(f.ppe.fallback), "eigen");
  EXPECT_TRUE(c.periodic.axis(0) && !c.periodic.axis(1) && !c.periodic.axis(2));
  EXPECT_DOUBLE_EQ(c.periodic.lo(0), 0.0);
  EXPECT_DOUBLE_EQ(c.periodic.hi(0), 0.1);
  EXPECT_EQ(c.bodies[0].initial_velocity.value, (std::array<double, 3>{0.5, 0, 0}));
  EXPECT_EQ(name_of(c.bodies[1].motion.type), "constant_velocity");
  EXPECT_EQ(c.bodies[1].motion.velocity, (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(name_of(c.probes[0].type), "velocity");

  // Round trip of a case that sets everything.
  const CaseSpec again = load_case(write("couette.resolved.toml", c.resolved_toml));
  EXPECT_EQ(again.resolved_toml, c.resolved_toml);
  EXPECT_EQ(again.bodies[1].motion.velocity, c.bodies[1].motion.velocity);
  EXPECT_EQ(again.periodic, c.periodic);
  EXPECT_EQ(name_of(again.fluid.ppe.preconditioner), "boomeramg");
}

TEST_F(CaseLoaderTest, FluidMaterialErrors) {
  std::string text = kDamBreak;
  text.replace(text.find("density = 1000"), 14, "density = 0");
  text.replace(text.find("viscosity = 1e-6"), 16, "viscosity = -1e-6");
  const auto path = write("bad_water.toml", text);
  auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": materials[0].density: must be > 0 (got 0)"));
  EXPECT_TRUE(reports(p, path + ": materials[0].viscosity: must be > 0 (got -1e-06)"));
  EXPECT_EQ(p.size(), 2u);

  const auto mixed = write("mixed.toml", kDamBreak + R"(
[[materials]]
name = "syrup"
model = "newtonian"
density = 1400
youngs_modulus = 1e9
poisson_ratio = 0.3
[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3
viscosity = 1e-3
[[materials]]
name = "gel"
model = "bingham"
density = 1
)");
  p = problems(mixed);
  EXPECT_TRUE(reports(p, mixed + ": materials[1].viscosity: missing required key"));
  EXPECT_TRUE(reports(p, mixed + ": materials[1].youngs_modulus: only for an elastic model (model = "
                                 "\"newtonian\")"));
  EXPECT_TRUE(reports(p, mixed + ": materials[1].poisson_ratio: only for an elastic model (model = "
                                 "\"newtonian\")"));
  EXPECT_TRUE(reports(p, mixed + ": materials[2].viscosity: only for newtonian (model = "
                                 "\"saint_venant_kirchhoff\")"));
  EXPECT_TRUE(reports(p, mixed + ": materials[3].model: must be one of \"saint_venant_kirchhoff\", "
                                 "\"neo_hookean\", \"mooney_rivlin\", \"newtonian\" (got \"bingham\")"));
  EXPECT_EQ(p.size(), 5u);
}

TEST_F(CaseLoaderTest, BodyKindsAndMaterialModels) {
  const auto path = write("kinds.toml", kDamBreak + R"(
[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3
[[bodies]]
name = "blob"
kind = "fluid"
material = "steel"
motion = { type = "constant_velocity", velocity = [1, 0] }
clamps = []
shape = { type = "circle", center = [0.5, 0.5], radius = 0.05 }
initial_velocity = { type = "cantilever_mode", tip_velocity = 1, length = 1 }
[[bodies]]
name = "gate"
material = "water"
motion = { type = "translation", profile = "sine", amplitude = 0.01, period = 1 }
shape = { type = "rectangle", min = [0.2, 0], max = [0.21, 0.4] }
[[bodies]]
name = "lid"
kind = "wall"
motion = { type = "constant_velocity" }
initial_velocity = { type = "uniform", value = [1, 0] }
shape = { type = "rectangle", min = [0, 0.6], max = [1, 0.63] }
[[bodies]]
name = "sill"
kind = "wall"
velocity = [1, 0]
shape = { type = "rectangle", min = [0.5, 0], max = [0.6, 0.03] }
)");
  const auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": bodies[4].material: material \"steel\" has model = "
                                "\"saint_venant_kirchhoff\", but a fluid body needs model = \"newtonian\""));
  EXPECT_TRUE(reports(p, path + ": bodies[4].motion: only for kind = \"wall\" or \"structure\" (kind = \"fluid\"; "
                                "see initial_velocity)"));
  EXPECT_TRUE(reports(p, path + ": bodies[4].clamps: only for kind = \"structure\" (kind = \"fluid\")"));
  EXPECT_TRUE(reports(p, path + ": bodies[4].initial_velocity: type \"cantilever_mode\" is only for kind = "
                                "\"structure\"; a fluid takes \"none\" or \"uniform\""));
  EXPECT_TRUE(reports(p, path + ": bodies[5].material: material \"water\" has model = \"newtonian\", but a "
                                "structure body needs an elastic model"));
  EXPECT_TRUE(reports(p, path + ": bodies[6].initial_velocity: not for kind = \"wall\" (use motion)"));
  EXPECT_TRUE(reports(p, path + ": bodies[5].motion: moves the clamped particles of a structure, and this body "
                                "has no clamps"));
  EXPECT_TRUE(reports(p, path + ": bodies[6].motion.velocity: missing required key"));
  EXPECT_TRUE(reports(p, path + ": bodies[7].velocity: unknown key"));
  EXPECT_EQ(p.size(), 9u);
}

// A moving gate: a CSV motion read relative to the case file, written back by absolute path.
TEST_F(CaseLoaderTest, MotionFromCsvFile) {
  write("lift.csv", "time [s]\tlift [m]\n# the gate lift\n0\t0\n0.5\t0.1\n1.0\t0.3\n1.5\t0.3\n");
  const auto path = write("gate.toml", kDamBreak + R"(
[[bodies]]
name = "gate"
kind = "wall"
shape = { type = "rectangle", min = [0.2, 0], max = [0.23, 0.45] }
motion = { type = "translation", direction = [0, 2], profile = "csv", file = "lift.csv" }
[[bodies]]
name = "paddle"
kind = "wall"
shape = { type = "rectangle", min = [0.9, 0], max = [0.93, 0.45] }
motion = { type = "rotation", pivot = [0.9, 0], profile = "sine", amplitude = 4, period = 1.2 }
)");
  const CaseSpec c = load_case(path);
  const MotionSpec& m = c.bodies[4].motion;
  EXPECT_EQ(name_of(m.type), "translation");
  EXPECT_EQ(m.direction, (std::array<double, 3>{0, 1, 0}));
  EXPECT_EQ(m.times, (std::vector<double>{0, 0.5, 1.0, 1.5}));
  EXPECT_EQ(m.values, (std::vector<double>{0, 0.1, 0.3, 0.3}));
  EXPECT_EQ(m.file, (dir_ / "lift.csv").string());
  EXPECT_EQ(name_of(c.bodies[5].motion.profile), "sine");
  EXPECT_DOUBLE_EQ(c.bodies[5].motion.period, 1.2);
  // The resolved case names the file absolutely, so it runs from any folder.
  fs::create_directories(dir_ / "elsewhere");
  const CaseSpec again = load_case(write("elsewhere/gate.resolved.toml", c.resolved_toml));
  EXPECT_EQ(again.resolved_toml, c.resolved_toml);
  EXPECT_EQ(again.bodies[4].motion.values, m.values);
}

TEST_F(CaseLoaderTest, MotionErrors) {
  write("unsorted.csv", "0, 0\n0.5, 1\n0.4, 2\n2, 3\n");
  write("short.csv", "0, 0\n0.5, 1\n");
  write("late.csv", "0.1, 0\n2, 1\n");  // the first value holds before t = 0.1
  write("words.csv", "t, s\n0, 0\n0.5, one\n2, 1\n");
  std::string bodies;
  for (const char* file : {"unsorted.csv", "short.csv", "late.csv", "words.csv", "missing.csv"})
    bodies += std::string("[[bodies]]\nname = \"") + file + "\"\nkind = \"wall\"\n" +
              "shape = { type = \"rectangle\", min = [2, 0], max = [2.1, 0.1] }\n" +
              "motion = { type = \"translation\", profile = \"csv\", file = \"" + file + "\" }\n";
  const auto path = write("motions.toml", kDamBreak + bodies + R"(
[[bodies]]
name = "spinner"
kind = "wall"
shape = { type = "rectangle", min = [3, 0], max = [3.1, 0.1] }
motion = { type = "rotation", profile = "polynomial", coefficients = [] }
[[bodies]]
name = "shaker"
kind = "wall"
shape = { type = "rectangle", min = [4, 0], max = [4.1, 0.1] }
motion = { type = "translation", profile = "sine", amplitude = 1, period = 0 }
)");
  const auto p = problems(path);
  const std::string dir = dir_.string() + "/";
  EXPECT_TRUE(reports(p, path + ": bodies[4].motion.file: \"" + dir +
                             "unsorted.csv\" line 3: the rows must be sorted "
                             "by time, strictly increasing (t = 0.4 follows t = 0.5)"));
  EXPECT_TRUE(reports(p, path + ": bodies[5].motion.file: \"" + dir +
                             "short.csv\" ends at t = 0.5 s, before "
                             "end_time = 1 s"));
  EXPECT_TRUE(reports(p, path + ": bodies[7].motion.file: \"" + dir +
                             "words.csv\" line 3: expected two numbers, "
                             "time and value (got \"0.5, one\")"));
  EXPECT_TRUE(reports(p, path + ": bodies[8].motion.file: cannot open \"" + dir + "missing.csv\""));
  EXPECT_TRUE(reports(p, path + ": bodies[9].motion.pivot: missing required key"));
  EXPECT_TRUE(reports(p, path + ": bodies[9].motion.coefficients: must not be empty"));
  EXPECT_TRUE(reports(p, path + ": bodies[10].motion.period: must be > 0 (got 0)"));
  EXPECT_EQ(p.size(), 7u);

  // A file that was long enough becomes too short when end_time grows.
  EXPECT_TRUE(reports(problems(path, {"end_time=3"}), path + ": bodies[6].motion.file: \"" + dir +
                                                          "late.csv\" ends at t = 2 s, before end_time = 3 s"));
}

TEST_F(CaseLoaderTest, FluidMissingMaterial) {
  std::string text = kDamBreak;
  text.replace(text.find("material = \"water\"\n"), 19, "");
  const auto path = write("no_material.toml", text);
  EXPECT_EQ(problems(path), std::vector<std::string>{path + ": bodies[0].material: missing required key"});
}

TEST_F(CaseLoaderTest, StagesFollowTheBodies) {
  std::string text = kDamBreak;
  text.replace(text.find("fluid = true"), 12, "fluid = false");
  const auto path = write("no_fluid_stage.toml", text);
  auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": stages.fluid: the case has fluid bodies (bodies[0] \"water\"); set "
                                "stages.fluid = true"));
  EXPECT_TRUE(reports(p, path + ": stages.structure: needs at least one body of kind = \"structure\" (or set "
                                "stages.fluid = true for a fluid case)"));
  EXPECT_TRUE(reports(p, path + ": probes[0].type: \"pressure\" probes need stages.fluid = true"));
  EXPECT_TRUE(reports(p, path + ": probes[1].type: \"front\" probes need stages.fluid = true"));
  EXPECT_EQ(p.size(), 4u);

  // A beam in a fluid case runs both stages; switching the structure stage off is an error.
  const auto both = write("both.toml", kDamBreak + R"(
[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3
[[bodies]]
name = "beam"
material = "steel"
shape = { type = "rectangle", min = [0.5, 0], max = [0.51, 0.1] }
[[probes]]
name = "tip"
point = [0.51, 0.1]
)");
  const CaseSpec c = load_case(both);
  EXPECT_TRUE(c.stages.structure);
  EXPECT_TRUE(c.stages.fluid);
  p = problems(both, {"stages.structure=false"});
  EXPECT_TRUE(reports(p, both + ": stages.structure: the case has structure bodies (bodies[4] \"beam\"); set "
                                "stages.structure = true"));
  EXPECT_TRUE(reports(p, both + ": probes[2].type: \"displacement\" probes need stages.structure = true"));
  EXPECT_EQ(p.size(), 2u);

  // Neither stage.
  const auto walls = write("walls.toml", R"(
dx = 0.01
end_time = 1
[stages]
structure = false
[[bodies]]
name = "floor"
kind = "wall"
shape = { type = "rectangle", min = [0, 0], max = [1, 0.03] }
)");
  EXPECT_EQ(problems(walls),
            std::vector<std::string>{walls + ": stages: nothing to run: set stages.structure or stages.fluid to true"});

  // A displacement probe in a fluid-only case.
  p = problems(write("fluid_probe.toml", kDamBreak + "[[probes]]\nname = \"tip\"\npoint = [0, 0]\n"));
  EXPECT_EQ(p, std::vector<std::string>{(dir_ / "fluid_probe.toml").string() +
                                        ": probes[2].type: \"displacement\" probes need stages.structure = true"});
}

TEST_F(CaseLoaderTest, FluidSettingErrors) {
  const auto path = write("settings.toml", kDamBreak + R"(
[fluid]
courant = 0
viscous_number = -1
reference_velocity = -1
turbulence = "les"
surface_threshold = 1.5
surface_full = 1.5
[fluid.ppe]
backend = "petsc"
method = "cg"
tolerance = 1
max_iterations = 0
fallback = "amgx"
)");
  auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": fluid.courant: must be > 0 (got 0)"));
  EXPECT_TRUE(reports(p, path + ": fluid.viscous_number: must be > 0 (got -1)"));
  EXPECT_TRUE(reports(p, path + ": fluid.reference_velocity: must be >= 0 (got -1)"));
  EXPECT_TRUE(reports(p, path + ": fluid.turbulence: must be one of \"none\", \"sps\" (got \"les\")"));
  EXPECT_TRUE(reports(p, path + ": fluid.surface_full: must be > surface_threshold (got 1.5 <= 1.5)"));
  EXPECT_TRUE(reports(
      p, path + ": fluid.ppe.backend: must be one of \"eigen\", \"hypre\", \"native\", \"cuda\" (got \"petsc\")"));
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.method: must be one of \"bicgstab\", \"gmres\" (got \"cg\")"));
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.tolerance: must be > 0 and < 1 (got 1)"));
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.max_iterations: must be > 0 (got 0)"));
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.fallback: must be one of \"none\", \"eigen\", \"hypre\" (got \"amgx\")"));
  EXPECT_EQ(p.size(), 10u);

  // A threshold above the default full value (1.6 in 2D).
  p = problems(path, {"fluid.surface_full=0", "fluid.surface_threshold=1.7"});
  EXPECT_TRUE(reports(p, path + ": fluid.surface_full: must be > surface_threshold (got 1.6 (default) <= 1.7)"));
}

// The PPE tolerance of each coupled step's first interface iteration: 0 (the PPE's own) by default, else
// in (0, 1); the resolved case keeps it.
TEST_F(CaseLoaderTest, FirstIterationPpeTolerance) {
  const auto path = write("dam_break.toml", kDamBreak);
  EXPECT_EQ(load_case(path).coupling.first_ppe_tolerance, 0.0);
  const auto c = load_case(path, {"coupling.first_ppe_tolerance=1e-3"});
  EXPECT_EQ(c.coupling.first_ppe_tolerance, 1e-3);
  EXPECT_EQ(load_case(write("resolved.toml", c.resolved_toml)).coupling.first_ppe_tolerance, 1e-3);
  for (const std::string bad : {"1", "-0.5"}) {
    const auto p = problems(path, {"coupling.first_ppe_tolerance=" + bad});
    EXPECT_TRUE(reports(p, path + ": coupling.first_ppe_tolerance: must be >= 0 and < 1 (got " + bad + ")"))
        << (p.empty() ? "" : p[0]);
  }
}

TEST_F(CaseLoaderTest, PpeCombinations) {
  const auto path = write("ppe.toml", kDamBreak + R"(
[fluid.ppe]
backend = "eigen"
preconditioner = "boomeramg"
fallback = "eigen"
)");
  auto p = problems(path);
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.preconditioner: \"boomeramg\" is not available with backend = "
                                "\"eigen\"; must be one of \"ilu\", \"jacobi\", \"none\""));
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.fallback: must differ from backend (both \"eigen\"), or be \"none\""));
  EXPECT_EQ(p.size(), 2u);

  p = problems(path, {"fluid.ppe.backend=hypre", "fluid.ppe.preconditioner=ilu", "fluid.ppe.fallback=none"});
  EXPECT_EQ(p, std::vector<std::string>{path + ": fluid.ppe.preconditioner: \"ilu\" is not available with "
                                               "backend = \"hypre\"; must be one of \"boomeramg\", \"jacobi\", "
                                               "\"none\""});
  p = problems(path, {"fluid.ppe.preconditioner=sor"});
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.preconditioner: must be one of \"ilu\", \"jacobi\", \"none\", "
                                "\"boomeramg\", \"polynomial\", \"amg\" (got \"sor\")"));

  // The project's own BiCGSTAB (native on the host, cuda on the GPU): its preconditioners, no GMRES.
  p = problems(path, {"fluid.ppe.backend=cuda", "fluid.ppe.method=gmres", "fluid.ppe.preconditioner=ilu"});
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.method: \"gmres\" is not available with backend = \"cuda\"; must be "
                                "one of \"bicgstab\""));
  EXPECT_TRUE(reports(p, path + ": fluid.ppe.preconditioner: \"ilu\" is not available with backend = \"cuda\"; "
                                "must be one of \"jacobi\", \"polynomial\", \"amg\", \"none\""));
  EXPECT_EQ(p.size(), 2u);
  const CaseSpec native = load_case(path, {"fluid.ppe.backend=native", "fluid.ppe.preconditioner=polynomial"});
  EXPECT_EQ(name_of(native.fluid.ppe.preconditioner), "polynomial");
  EXPECT_EQ(
      name_of(load_case(path, {"fluid.ppe.backend=cuda", "fluid.ppe.preconditioner=none"}).fluid.ppe.preconditioner),
      "none");

  const CaseSpec c = load_case(path, {"fluid.ppe.backend=hypre", "fluid.ppe.preconditioner=jacobi"});
  EXPECT_EQ(name_of(c.fluid.ppe.preconditioner), "jacobi");
  EXPECT_EQ(name_of(c.fluid.ppe.fallback), "eigen");
}

TEST_F(CaseLoaderTest, ShiftingErrors) {
  const auto path = write("shifting.toml", kDamBreak);
  const auto p = problems(path, {"fluid.shifting.type=lind", "fluid.shifting.coefficient=0",
                                 "fluid.shifting.max_fraction=-0.1", "fluid.shifting.taylor_correction=1"});
  EXPECT_TRUE(reports(p, path + ": fluid.shifting.type: must be one of \"none\", \"xu\", \"ops\" (got \"lind\")"));
  EXPECT_TRUE(reports(p, path + ": fluid.shifting.coefficient: must be > 0 and <= 1 (got 0)"));
  EXPECT_TRUE(reports(p, path + ": fluid.shifting.max_fraction: must be > 0 (got -0.1)"));
  EXPECT_TRUE(reports(p, path + ": fluid.shifting.taylor_correction: expected a boolean, got an integer"));
  EXPECT_EQ(p.size(), 4u);
  EXPECT_TRUE(reports(problems(path, {"fluid.shifting.coefficient=1.5"}),
                      path + ": fluid.shifting.coefficient: must be > 0 and <= 1 (got 1.5)"));
}

TEST_F(CaseLoaderTest, PeriodicAxes) {
  const auto path = write("periodic.toml", kDamBreak);
  const CaseSpec c = load_case(path, {"periodic.x=[0,0.1]", "periodic.y=[-1, 1]"});
  EXPECT_EQ(c.periodic.range[0], (std::vector<double>{0, 0.1}));
  EXPECT_EQ(c.periodic.range[1], (std::vector<double>{-1, 1}));
  EXPECT_FALSE(c.periodic.axis(2));

  const auto p = problems(path, {"periodic.x=[0.1,0.1]", "periodic.y=[0, 1, 2]", "periodic.z=[0, 1]"});
  EXPECT_TRUE(reports(p, path + ": periodic.x: hi must be > lo (got [0.1, 0.1])"));
  EXPECT_TRUE(reports(p, path + ": periodic.y: expected 2 numbers [lo, hi], got 3"));
  EXPECT_TRUE(reports(p, path + ": periodic.z: only in 3D (dimension = 2)"));
  EXPECT_EQ(p.size(), 3u);
  EXPECT_TRUE(reports(problems(path, {"periodic.x=[1,0]"}), path + ": periodic.x: hi must be > lo (got [1, 0])"));
}

TEST_F(CaseLoaderTest, FluidOverrides) {
  const auto path = write("dam_break.toml", kDamBreak);
  const CaseSpec c =
      load_case(path, {"fluid.shifting.type=none", "fluid.ppe.backend=hypre", "materials.water.viscosity=1e-3",
                       "fluid.courant=0.25", "probes.front.point=[0,0.02]"});
  EXPECT_EQ(name_of(c.fluid.shifting.type), "none");
  EXPECT_EQ(name_of(c.fluid.ppe.backend), "hypre");
  EXPECT_EQ(name_of(c.fluid.ppe.preconditioner), "boomeramg");
  EXPECT_DOUBLE_EQ(c.materials[0].viscosity, 1e-3);
  EXPECT_DOUBLE_EQ(c.fluid.courant, 0.25);
  EXPECT_EQ(c.probes[1].point, (std::array<double, 3>{0, 0.02, 0}));
}

// TOML is UTF-8: malformed bytes in a case file or an override are refused before toml11 parses them
// (its parser read out of bounds on one such override; found by fuzzing, docs/RELIABILITY.md).
TEST_F(CaseLoaderTest, TextThatIsNotUtf8IsRefusedWithItsPlace) {
  const auto valid = write("valid.toml", "# \xc2\xa7 3.2, \xe2\x80\x93, \xf0\x9f\x8c\x8a\n" + kBeam);
  EXPECT_TRUE(problems(valid).empty());
  for (const std::string bad : {"\xff", "\xc0\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xe2\x80"}) {
    const auto path = write("bad.toml", "# ok\n# " + bad + "\n" + kBeam);
    const auto found = problems(path);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_EQ(found[0], path + ": not UTF-8 text (line 2, byte 8): a case file is TOML, which is UTF-8");
    const auto set = problems(valid, {"'a" + bad + "'.b=1"});
    ASSERT_EQ(set.size(), 1u);
    EXPECT_EQ(set[0], "--set 'a" + bad + "'.b=1: not UTF-8 text (byte 3)");
  }
}

TEST_F(CaseLoaderTest, FluidResolvedTomlReloadsToTheSameCase) {
  const auto path = write("dam_break.toml", kDamBreak);
  const auto first = load_case(path, {"fluid.ppe.method=gmres", "periodic.x=[0,1]", "fluid.escape=\"stop\""});
  const auto second = load_case(write("resolved.toml", first.resolved_toml));
  EXPECT_EQ(second.name, "dam_break");
  EXPECT_EQ(name_of(second.fluid.escape), "stop");       // was read but not written (issue 35)
  EXPECT_EQ(second.resolved_toml, first.resolved_toml);  // resolving is idempotent
  EXPECT_FALSE(second.stages.structure);
  EXPECT_TRUE(second.stages.fluid);
  EXPECT_EQ(second.materials[0].model, MaterialModel::newtonian);
  EXPECT_EQ(second.materials[0].viscosity, 1e-6);
  EXPECT_EQ(name_of(second.fluid.shifting.type), "xu");
  EXPECT_EQ(name_of(second.fluid.ppe.method), "gmres");
  EXPECT_EQ(second.periodic, first.periodic);
  EXPECT_EQ(name_of(second.bodies[1].motion.type), "none");
  EXPECT_EQ(name_of(second.probes[1].type), "front");
  // Only the keys of each kind and model are written.
  EXPECT_EQ(first.resolved_toml.find("youngs_modulus"), std::string::npos);
  EXPECT_EQ(first.resolved_toml.find("clamps"), std::string::npos);
  EXPECT_NE(first.resolved_toml.find("[fluid.ppe]"), std::string::npos);
  EXPECT_NE(first.resolved_toml.find("x = [0.0, 1.0]"), std::string::npos);
  EXPECT_EQ(first.resolved_toml.find("\ny = "), std::string::npos);
}

TEST(ShapeTest, RectangleContainsItsFaces) {
  const Shape r{.type = ShapeType::rectangle, .min = {0, 0, 0}, .max = {0.3, 0.1, 0}};
  EXPECT_TRUE(r.contains({0.15, 0.05, 0}, 2));
  EXPECT_TRUE(r.contains({0.3, 0.1, 0}, 2));
  EXPECT_TRUE(r.contains({3 * 0.1, 0.05, 0}, 2));  // 0.30000000000000004: on the face
  EXPECT_TRUE(r.contains({0.15, 0.05, 7}, 2));     // the third component does not count in 2D
  EXPECT_FALSE(r.contains({0.3 + 1e-9, 0.05, 0}, 2));
  EXPECT_FALSE(r.contains({0.15, -1e-9, 0}, 2));
}

TEST(ShapeTest, SphereContainsItsSurface) {
  const Shape s{.type = ShapeType::sphere, .center = {1, 1, 1}, .radius = 0.5};
  EXPECT_TRUE(s.contains({1.5, 1, 1}, 3));
  EXPECT_TRUE(s.contains({1, 1, 0.5}, 3));
  EXPECT_FALSE(s.contains({1.4, 1.4, 1}, 3));
  EXPECT_FALSE(s.contains({1, 1, 1.5 + 1e-9}, 3));
}

}  // namespace
}  // namespace isph
