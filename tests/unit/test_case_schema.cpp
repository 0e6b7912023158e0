// The declared settings keys (src/io/case_schema.hpp): every key read, checked, written back and
// documented from its one declaration.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "io/case_loader.hpp"
#include "io/case_schema.hpp"
#include "io/list_schema.hpp"
#include "io/stl_mesh.hpp"
#include "scratch_dir_test.hpp"

namespace fs = std::filesystem;
using namespace isph;

namespace {

const std::string kSource = ISPH_SOURCE_DIR;

// The parts of two cases that differ, for a failure's message.
std::string differences(const CaseSpec& a, const CaseSpec& b) {
  std::string parts;
  const auto part = [&parts](bool same, const char* name) {
    if (!same) parts += std::string(" ") + name;
  };
  part(a.name == b.name, "name");
  part(a.dimension == b.dimension && a.dx == b.dx && a.end_time == b.end_time && a.gravity == b.gravity, "top-level");
  part(a.kernel == b.kernel, "kernel");
  part(a.structure == b.structure, "structure");
  part(a.fluid == b.fluid, "fluid");
  part(a.coupling == b.coupling, "coupling");
  part(a.periodic == b.periodic, "periodic");
  part(a.output == b.output, "output");
  part(a.stages == b.stages, "stages");
  part(a.materials == b.materials, "materials");
  part(a.bodies == b.bodies, "bodies");
  for (std::size_t i = 0; i < std::min(a.bodies.size(), b.bodies.size()); ++i) {
    const BodySpec &x = a.bodies[i], &y = b.bodies[i];
    if (x == y) continue;
    parts += " (bodies[" + std::to_string(i) + "]:";
    part(x.shape == y.shape, "shape");
    part(x.clamps == y.clamps, "clamps");
    part(x.refinement == y.refinement && x.dx == y.dx, "spacing");
    part(x.lattice_origin == y.lattice_origin && x.lattice_offset == y.lattice_offset, "lattice");
    part(x.initial_velocity == y.initial_velocity, "initial_velocity");
    part(x.motion == y.motion, "motion");
    parts += ")";
  }
  part(a.loads == b.loads, "loads");
  part(a.probes == b.probes, "probes");
  return parts;
}

class CaseSchema : public ScratchDirTest {
 protected:
  CaseSchema() : ScratchDirTest("isph_case_schema_") {}

  // Loads the resolved case of `spec` back; both compared without their file names and TOML text.
  void expect_round_trip(const CaseSpec& spec, const std::string& what) {
    CaseSpec again = load_case(write("resolved.toml", spec.resolved_toml));
    CaseSpec first = spec;
    for (CaseSpec* c : {&first, &again}) {
      c->source_path.clear();
      c->resolved_toml.clear();
    }
    EXPECT_TRUE(first == again) << what << ": the resolved case loads back to another case, differing in"
                                << differences(first, again) << ":\n"
                                << spec.resolved_toml;
  }
};

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Values to try for a key instead of its value in the base case (`text`, as the resolved case writes it):
// valid for the key alone, though a case's cross-key rules may refuse some. TOML text each.
std::vector<std::string> candidates(const SettingKey& key, const std::string& text) {
  std::vector<std::string> out;
  if (!key.choices.empty()) {
    for (const std::string& c : key.choices)
      if (toml_string(c) != text) out.push_back(toml_string(c));
  } else if (key.type == "boolean") {
    out.emplace_back(text == "true" ? "false" : "true");
  } else if (key.type == "integer") {
    const long long i = std::stoll(text);
    for (const long long c : {i + 1, i - 1})
      if (key.bounds.admits(static_cast<double>(c))) out.push_back(std::to_string(c));
  } else if (key.type == "float") {
    const double x = std::stod(text);
    for (const double c : {2 * x, x / 2, 0.5, 2.0, 10.0})
      if (c != x && key.bounds.admits(c)) out.push_back(toml_float(c));
  } else if (key.type == "vector") {
    out.push_back(toml_vector({1.0, -5.0, 0.0}, 2));
  } else {
    out.push_back(text.substr(0, text.size() - 1) + "_renamed\"");
  }
  return out;
}

}  // namespace

TEST_F(CaseSchema, DocsAreCurrent) {
  const std::string path = kSource + "/docs/CASES.md";
  const std::string document = read_text(path);
  EXPECT_TRUE(with_key_reference(document) == document)
      << path << " is stale: regenerate its key tables with `build/isph keys --update docs/CASES.md`";
}

TEST_F(CaseSchema, EveryKeyIsDeclaredOnceAndDocumented) {
  std::set<std::string> paths;
  for (const SettingKey& key : case_keys()) {
    EXPECT_TRUE(paths.insert(key.path()).second) << key.path() << " is declared twice";
    EXPECT_FALSE(key.doc.empty()) << key.path() << " has no documentation";
    if (!key.choices.empty()) {
      EXPECT_GE(key.choices.size(), 2u) << key.path();
    }
  }
  EXPECT_EQ(paths.size(), 62u);  // the settings keys on 2026-12-08
}

// Every key, set alone to each value that differs from the hydrostatic plate's, is read into the case,
// written to the resolved case, and loads back to the same case, compared field by field. The stage
// switches and the dimension must agree with the bodies, so no single change of theirs loads; the
// bundled cases and the 3D case below cover their other values. The plate leaves the PPE solver to the
// build's default, so that another backend, with its own default preconditioner, loads alone.
TEST_F(CaseSchema, EveryKeyRoundTripsFieldByField) {
  const std::string plate = kSource + "/cases/hydrostatic_plate.toml";
  const CaseSpec base = load_case(plate);
  for (const SettingKey& key : case_keys()) {
    int loaded = 0;
    for (const std::string& value : candidates(key, key_text(key, base, base.dimension))) {
      const std::string text = key.path() + "=" + value;
      CaseSpec changed;
      try {
        changed = load_case(plate, {text});
      } catch (const CaseError&) {
        continue;  // refused by a rule across keys
      }
      ++loaded;
      EXPECT_EQ(key_text(key, changed, changed.dimension), value) << "--set " << text << " was not read into the case";
      expect_round_trip(changed, "--set " + text);
    }
    const bool fixed_by_bodies = key.section == "stages" || key.path() == "dimension";
    if (fixed_by_bodies) {
      EXPECT_EQ(loaded, 0) << key.path();
    } else {
      EXPECT_GE(loaded, 1) << "no other value of " << key.path() << " loads";
    }
  }
}

TEST_F(CaseSchema, BundledCasesRoundTripFieldByField) {
  int cases = 0;
  for (const auto& entry : fs::directory_iterator(kSource + "/cases")) {
    if (entry.path().extension() != ".toml") continue;
    ++cases;
    expect_round_trip(load_case(entry.path().string()), entry.path().filename().string());
  }
  EXPECT_EQ(cases, 24);
}

TEST_F(CaseSchema, ThreeDimensionalCaseRoundTripsFieldByField) {
  const std::string path = write("block.toml", R"(dimension = 3
dx = 0.01
end_time = 0.1
gravity = [0, 0, -9.81]
[[materials]]
name = "rubber"
density = 1100
youngs_modulus = 1e7
poisson_ratio = 0.4
[[bodies]]
name = "block"
kind = "structure"
material = "rubber"
shape = { type = "box", min = [0, 0, 0], max = [0.05, 0.05, 0.1] }
clamps = [{ type = "box", min = [0, 0, -0.01], max = [0.05, 0.05, 0.01] }]
)");
  const CaseSpec spec = load_case(path);
  EXPECT_EQ(spec.dimension, 3);
  EXPECT_NE(spec.resolved_toml.find("gravity = [0.0, 0.0, -9.81]"), std::string::npos) << spec.resolved_toml;
  expect_round_trip(spec, path);
}

// Every key of the lists and of the tables inside them (src/io/list_schema.hpp), each given a value that
// differs from its default in one of two cases (2D and 3D), is written to the resolved case, which
// loads back to the same case, field by field.
TEST_F(CaseSchema, EveryListKeyRoundTripsFieldByField) {
  write("roll.csv", "time, angle\n0, 0\n0.05, 1\n0.2, 2\n");
  const std::string planar = write("lists.toml", R"(dx = 0.01
end_time = 0.1
gravity = [0, -9.81]
[stages]
fluid = true
[periodic]
x = [-1.0, 2.0]
y = [-1.5, 3.0]
[[materials]]
name = "water"
model = "newtonian"
density = 1000
viscosity = 1e-6
[[materials]]
name = "rubber"
density = 1100
poisson_ratio = 0.4
bulk_modulus = 2e7
plane = "stress"
[[materials]]
name = "steel"
density = 7800
poisson_ratio = 0.3
youngs_modulus = 2e11
[[materials]]
name = "gum"
model = "mooney_rivlin"
density = 1000
poisson_ratio = 0.45
youngs_modulus = 1e6
c01_fraction = 0.2
[[materials]]
name = "latex"
model = "neo_hookean"
density = 950
poisson_ratio = 0.45
youngs_modulus = 2e6
[[bodies]]
name = "water"
kind = "fluid"
material = "water"
shape = { type = "circle", center = [0.5, 0.5], radius = 0.1 }
initial_velocity = { type = "uniform", value = [0.1, 0.0] }
holes = [{ type = "circle", center = [0.5, 0.5], radius = 0.02 }]
[[bodies]]
name = "beam"
material = "rubber"
shape = { type = "rectangle", min = [0, 0], max = [0.2, 0.02] }
clamps = [{ type = "rectangle", min = [0, 0], max = [0.02, 0.02] }]
dx = 0.005
lattice_origin = [0.001, 0.0]
lattice_offset = [0.0, 0.25]
initial_velocity = { type = "cantilever_mode", tip_velocity = 0.1, length = 0.2, kL = 4.694, root = [0.0, 0.01], axis = [2.0, 0.0], direction = [0.0, -1.0] }
motion = { type = "translation", direction = [1.0, 1.0], profile = "sine", amplitude = 0.01, period = 0.5, phase = 0.1 }
[[bodies]]
name = "plate"
material = "steel"
shape = { type = "rectangle", min = [0.3, 0], max = [0.5, 0.02] }
clamps = [{ type = "circle", center = [0.3, 0.01], radius = 0.02 }]
refinement = 2
motion = { type = "rotation", pivot = [0.3, 0.0], profile = "csv", file = "roll.csv" }
[[bodies]]
name = "floor"
kind = "wall"
shape = { type = "rectangle", min = [-0.1, -0.03], max = [0.7, 0.0] }
motion = { type = "constant_velocity", velocity = [0.1, 0.0] }
[[bodies]]
name = "gate"
kind = "wall"
material = "steel"
shape = { type = "rectangle", min = [0.6, 0.0], max = [0.63, 0.3] }
motion = { type = "translation", profile = "polynomial", coefficients = [0.0, 0.1, -0.5], until = 0.05 }
[[bodies]]
name = "hull"
material = "steel"
shape = { type = "wedge", apex = [1.0, 0.4], half_breadth = 0.1, deadrise = 15.0, thickness = 0.01 }
clamps = [{ type = "rectangle", min = [0.9, 0.4], max = [0.91, 0.5] }]
[[loads]]
type = "edge"
body = "beam"
region = { type = "rectangle", min = [0.19, 0], max = [0.2, 0.02] }
force = [0, -1]
ramp_time = 0.01
[[loads]]
type = "traction"
body = "beam"
region = { type = "rectangle", min = [0.1, 0.015], max = [0.2, 0.02] }
traction = [0, -100]
[[loads]]
type = "point"
body = "plate"
point = [0.5, 0.01]
force = [1, 0]
[[loads]]
type = "body"
body = "plate"
acceleration = [0, -2]
[[probes]]
name = "tip"
point = [0.2, 0.01]
[[probes]]
name = "bottom"
type = "pressure"
point = [0.5, 0.45]
[[probes]]
name = "fastest"
type = "max_speed"
[[probes]]
name = "keel"
type = "structure_pressure"
point = [1.0, 0.4]
[[probes]]
name = "drag"
type = "force"
body = "floor"
terms = "all"
[[open_boundaries]]
name = "in"
type = "inlet"
point = [0.4, 0.5]
normal = [1.0, 0.0]
layers = 4
velocity = "0.1 - 10 * (y - 0.5)^2"
flow_rate = 0.01
ramp_time = 0.5
[[open_boundaries]]
name = "out"
type = "outlet"
point = [0.6, 0.5]
normal = [-1.0, 0.0]
pressure = 10.0
)");
  const std::string solid = write("lists3d.toml", R"(dimension = 3
dx = 0.01
end_time = 0.1
[periodic]
z = [-0.5, 0.5]
[[materials]]
name = "rubber"
density = 1100
youngs_modulus = 1e7
poisson_ratio = 0.4
[[bodies]]
name = "ball"
material = "rubber"
shape = { type = "sphere", center = [0, 0, 0], radius = 0.05 }
clamps = [{ type = "box", min = [-0.05, -0.05, -0.05], max = [0.05, 0.05, -0.03] }]
[[bodies]]
name = "rod"
material = "rubber"
shape = { type = "cylinder", base = [0.2, 0, 0], axis = [0, 0.1, 0.1], radius = 0.02 }
)" + std::string(stl_available() ? R"(
[[bodies]]
name = "cube"
material = "rubber"
shape = { type = "stl", file = "cube.stl", scale = 0.1, translate = [0.5, 0.0, 0.0] }
)"
                                 : ""));
  // a unit cube, two triangles a face
  std::string cube = "solid cube\n";
  const int faces[6][4][3] = {
      {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
      {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
      {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
  const int halves[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (const auto& f : faces)
    for (const auto& corners : halves) {
      cube += "facet normal 0 0 0\nouter loop\n";
      for (int c = 0; c < 3; ++c) {
        const int* v = f[corners[c]];
        cube += "vertex " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
      }
      cube += "endloop\nendfacet\n";
    }
  write("cube.stl", cube + "endsolid cube\n");
  std::string written;
  for (const std::string& path : {planar, solid}) {
    const CaseSpec spec = load_case(path);
    expect_round_trip(spec, path);
    written += spec.resolved_toml;
  }
  const auto given = [&written](const std::string& key) {
    for (const std::string before : {"\n", "{ ", ", "})
      if (written.find(before + key + " = ") != std::string::npos) return true;
    return false;
  };
  const auto expect_every_key_given = [&given](const auto& keys, const std::string& table) {
    for (const auto& key : keys) {
      const bool stl_only = table == "shape" && (key.name == "file" || key.name == "scale" || key.name == "translate");
      if (stl_only && !stl_available()) continue;  // no stl shape loads without CGAL
      EXPECT_TRUE(given(key.name)) << table << "." << key.name << " is never written";
    }
  };
  expect_every_key_given(material_keys(), "materials");
  expect_every_key_given(body_keys(), "bodies");
  expect_every_key_given(shape_keys(), "shape");
  expect_every_key_given(initial_velocity_keys(), "initial_velocity");
  expect_every_key_given(motion_keys(), "motion");
  expect_every_key_given(load_keys(), "loads");
  expect_every_key_given(probe_keys(), "probes");
  expect_every_key_given(open_boundary_keys(), "open_boundaries");
  expect_every_key_given(periodic_keys(), "periodic");
}

// A key given where it does not apply is refused with the element's own value in the message.
TEST_F(CaseSchema, ListKeysOutsideTheirElementsAreRefusedSayingWhy) {
  const std::string path = write("misplaced.toml", R"(dx = 0.01
end_time = 0.1
[[materials]]
name = "rubber"
density = 1100
youngs_modulus = 1e7
poisson_ratio = 0.4
[[bodies]]
name = "beam"
material = "rubber"
shape = { type = "rectangle", min = [0, 0], max = [0.2, 0.02], center = [0.1, 0.01] }
clamps = [{ type = "rectangle", min = [0, 0], max = [0.02, 0.02] }]
motion = { type = "constant_velocity", velocity = [0.1, 0.0], pivot = [0, 0] }
initial_velocity = { type = "uniform", value = [1.0, 0.0], kL = 2 }
[[loads]]
type = "body"
body = "beam"
acceleration = [0, -1]
force = [0, 1]
)");
  try {
    load_case(path);
    FAIL() << "misplaced keys loaded";
  } catch (const CaseError& e) {
    const std::vector<std::string> expected = {
        "bodies[0].shape.center: only for type = \"circle\" or \"sphere\" (type = \"rectangle\")",
        "bodies[0].motion.pivot: only for type = \"rotation\" (type = \"constant_velocity\")",
        "bodies[0].initial_velocity.kL: only for type = \"cantilever_mode\" (type = \"uniform\")",
        "loads[0].force: only for type = \"edge\" or \"point\" (type = \"body\")"};
    EXPECT_EQ(e.problems().size(), expected.size()) << e.what();
    for (const std::string& problem : expected)
      EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << problem << "\nnot in:\n" << e.what();
  }
}

// A key's bounds are its message and its documentation.
TEST(CaseKeyBounds, TextNamesTheInterval) {
  EXPECT_EQ((KeyBounds{0, 1, true, true}).text(false), "> 0 and < 1");
  EXPECT_EQ((KeyBounds{0, 1, false, true}).text(false), ">= 0 and < 1");
  EXPECT_EQ((KeyBounds{0, 100}).text(true), "in 0..100");
  EXPECT_EQ((KeyBounds{1}).text(true), "> 0");
  EXPECT_EQ((KeyBounds{0}).text(false), ">= 0");
  EXPECT_TRUE((KeyBounds{0, 1, false, true}).admits(0));
  EXPECT_FALSE((KeyBounds{0, 1, false, true}).admits(1));
}

TEST(EnumNames, EveryNameReadsBackAsItsValue) {
  for (const auto& entry : enum_names(ShiftingType{})) EXPECT_EQ(enum_from_name<ShiftingType>(entry.name), entry.value);
  for (const auto& entry : enum_names(SubstepInteraction{}))
    EXPECT_EQ(name_of(*enum_from_name<SubstepInteraction>(entry.name)), entry.name);
  EXPECT_FALSE(enum_from_name<KernelType>("gaussian").has_value());
  EXPECT_FALSE(enum_from_name<StructureIntegrator>("euler").has_value());
  EXPECT_EQ(name_of(StructureGradient::uncorrected), "?");  // not a case's choice: it follows kernel.correction
}
