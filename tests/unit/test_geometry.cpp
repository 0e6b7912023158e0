// 3D geometry of bodies: the cylinder primitive, bodies from STL meshes (with CGAL), and shapes of the
// wrong dimension.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "io/case_loader.hpp"
#include "scratch_dir_test.hpp"
#include "sim/scene.hpp"

namespace isph {
namespace {

using Point = std::array<double, 3>;
using Triangle = std::array<Point, 3>;

// A 3D structure case of one body, `ball`, whose shape is SHAPE.
const std::string kSolid = R"(
dimension = 3
dx = 0.01
end_time = 1

[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3

[[bodies]]
name = "ball"
material = "steel"
shape = SHAPE
)";

std::string with_shape(std::string text, const std::string& shape) {
  return text.replace(text.find("SHAPE"), 5, shape);
}

class GeometryTest : public ScratchDirTest {
 protected:
  GeometryTest() : ScratchDirTest("isph_geometry_") {}

  static std::vector<std::string> problems(const std::string& path) {
    try {
      load_case(path);
    } catch (const CaseError& e) {
      return e.problems();
    }
    return {};
  }

  // The problems of loading the case and building its scene (`isph check`).
  static std::vector<std::string> check_problems(const std::string& path) {
    try {
      build_scene<3>(load_case(path));
    } catch (const CaseError& e) {
      return e.problems();
    }
    return {};
  }

  // The structure particles' positions of a 3D case, sorted.
  std::vector<Point> particles(const std::string& name, const std::string& text) {
    const Scene<3> scene = build_scene<3>(load_case(write(name, text)));
    std::vector<Point> x;
    for (const auto& p : scene.structure.X) x.push_back({p[0], p[1], p[2]});
    std::sort(x.begin(), x.end());
    return x;
  }
};

::testing::AssertionResult reports(const std::vector<std::string>& problems, const std::string& expected) {
  if (std::find(problems.begin(), problems.end(), expected) != problems.end()) return ::testing::AssertionSuccess();
  auto failure = ::testing::AssertionFailure()
                 << "\"" << expected << "\" not among the " << problems.size() << " problems:";
  for (const auto& p : problems) failure << "\n  " << p;
  return failure;
}

double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point minus(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// ---------------------------------------------------------------------------------------------
// Cylinders
// ---------------------------------------------------------------------------------------------

// A cylinder of radius 0.1 m and length 0.3 m at dx = 0.01 m holds about pi r^2 L / dx^3 = 9425 particles:
// along x, y and z exactly as many (the lattice is anchored at the bounding box's corner, so the three are
// the same lattice turned), within 1 % of that (measured: 9480, +0.58 %), and along an oblique axis
// (1, 2, 2)/3 within 1 % too (measured: 9450, +0.27 %). Every particle lies inside: within r of the axis,
// between the two ends.
TEST_F(GeometryTest, CylinderAlongAnyAxisHoldsItsVolume) {
  const double r = 0.1, L = 0.3, dx = 0.01;
  const double expected = std::numbers::pi * r * r * L / (dx * dx * dx);
  const std::vector<std::pair<Point, Point>> cylinders = {{{0.2, 0.5, 0.5}, {L, 0, 0}},
                                                          {{0.5, 0.2, 0.5}, {0, L, 0}},
                                                          {{0.5, 0.5, 0.2}, {0, 0, L}},
                                                          {{0.5, 0.5, 0.5}, {L / 3, 2 * L / 3, 2 * L / 3}}};
  std::vector<std::size_t> counts;
  for (const auto& [base, axis] : cylinders) {
    char shape[400];
    std::snprintf(shape, sizeof shape,
                  "{ type = \"cylinder\", base = [%.17g, %.17g, %.17g], axis = [%.17g, %.17g, %.17g], radius = 0.1 }",
                  base[0], base[1], base[2], axis[0], axis[1], axis[2]);
    const auto x = particles("cylinder" + std::to_string(counts.size()) + ".toml", with_shape(kSolid, shape));
    counts.push_back(x.size());
    const double length = std::sqrt(dot(axis, axis));
    for (const Point& p : x) {
      const Point d = minus(p, base);
      const double along = dot(d, axis) / length;
      const double off2 = dot(d, d) - along * along;
      EXPECT_GE(along, -1e-12);
      EXPECT_LE(along, length + 1e-12);
      EXPECT_LE(off2, r * r + 1e-12);
    }
    EXPECT_NEAR(counts.back() / expected, 1.0, 0.01) << "axis " << axis[0] << " " << axis[1] << " " << axis[2];
  }
  EXPECT_EQ(counts[0], counts[1]);
  EXPECT_EQ(counts[0], counts[2]);
  EXPECT_EQ(counts[0], 9480u);
  EXPECT_EQ(counts[3], 9450u);
}

// A cylinder clamps a rod at its base and is the region of a load at its tip (grown by dx/2, as a load's
// region is): each holds one cross-section of the rod, the same disc of particles, 1/30 of the rod.
TEST_F(GeometryTest, CylinderClampsAndLoads) {
  const auto path =
      write("rod.toml", with_shape(kSolid, R"({ type = "cylinder", base = [0, 0, 0], axis = [0.3, 0, 0], radius = 0.05 }
clamps = [{ type = "cylinder", base = [-0.01, 0, 0], axis = [0.02, 0, 0], radius = 0.05 }]
[[loads]]
type = "edge"
body = "ball"
region = { type = "cylinder", base = [0.291, 0, 0], axis = [0.009, 0, 0], radius = 0.05 }
force = [0, 0, -1])"));
  const Scene<3> scene = build_scene<3>(load_case(path));
  const auto& s = scene.structure;
  ASSERT_EQ(s.X.size() % 30, 0u);
  std::size_t clamped = 0, loaded = 0;
  for (std::size_t a = 0; a < s.X.size(); ++a) {
    if (s.fixed[a]) {
      ++clamped;
      EXPECT_NEAR(s.X[a][0], 0.005, 1e-12);
    }
    if (norm2(s.loads[0].acc[a]) > 0) {
      ++loaded;
      EXPECT_NEAR(s.X[a][0], 0.295, 1e-12);
    }
  }
  EXPECT_EQ(clamped, s.X.size() / 30);
  EXPECT_EQ(loaded, clamped);
}

TEST_F(GeometryTest, CylinderErrors) {
  const auto zero = write(
      "zero.toml", with_shape(kSolid, R"({ type = "cylinder", base = [0, 0, 0], axis = [0, 0, 0], radius = 0.1 })"));
  EXPECT_TRUE(
      reports(problems(zero),
              zero + ": bodies[0].shape.axis: must not be the zero vector (its length is the cylinder's length)"));
  const auto flat = write(
      "flat.toml", with_shape(kSolid, R"({ type = "cylinder", base = [0, 0, 0], axis = [0, 0, 1], radius = 0 })"));
  EXPECT_TRUE(reports(problems(flat), flat + ": bodies[0].shape.radius: must be > 0 (got 0)"));
  const auto missing = write("missing.toml", with_shape(kSolid, R"({ type = "cylinder", center = [0, 0, 0] })"));
  const auto p = problems(missing);
  EXPECT_TRUE(reports(p, missing + ": bodies[0].shape.base: missing required key"));
  EXPECT_TRUE(reports(p, missing + ": bodies[0].shape.axis: missing required key"));
  EXPECT_TRUE(reports(p, missing + ": bodies[0].shape.radius: missing required key"));
  EXPECT_TRUE(
      reports(p, missing + ": bodies[0].shape.center: only for type = \"circle\" or \"sphere\" (type = \"cylinder\")"));
}

// A 2D shape in a 3D case and a 3D one in a 2D case: the body's shape, the shape and the dimension are
// named, and the other keys of the shape are not judged.
TEST_F(GeometryTest, ShapesOfTheOtherDimensionAreRefused) {
  const auto planar =
      write("planar.toml", with_shape(kSolid, R"({ type = "rectangle", min = [0, 0, 0], max = [1, 1, 1] })"));
  const auto p = problems(planar);
  EXPECT_TRUE(reports(p, planar + ": bodies[0].shape.type: \"rectangle\" is a 2D shape, but dimension = 3; must be one "
                                  "of \"box\", \"sphere\", \"cylinder\", \"stl\""));
  EXPECT_EQ(p.size(), 1u);
  std::string flat = kSolid;
  flat.replace(flat.find("dimension = 3"), 13, "dimension = 2");
  for (const std::string type : {"cylinder", "stl", "box"}) {
    const auto path = write(type + ".toml", with_shape(flat, "{ type = \"" + type + "\", file = \"ball.stl\" }"));
    const auto q = problems(path);
    EXPECT_TRUE(
        reports(q, path + ": bodies[0].shape.type: \"" + type +
                       "\" is a 3D shape, but dimension = 2; must be one of \"rectangle\", \"circle\", \"wedge\""));
    EXPECT_EQ(q.size(), 1u);
  }
}

TEST_F(GeometryTest, ResolvedCylinderReloadsToTheSameCase) {
  const auto path = write(
      "original.toml",
      with_shape(kSolid, R"({ type = "cylinder", base = [0.1, 0.2, 0.3], axis = [0, 0.1, 0.2], radius = 0.05 })"));
  const CaseSpec first = load_case(path);
  const CaseSpec second = load_case(write("resolved.toml", first.resolved_toml));
  EXPECT_EQ(second.bodies[0].shape, first.bodies[0].shape);
  EXPECT_EQ(second.bodies[0].lattice_origin, first.bodies[0].lattice_origin);
  EXPECT_EQ(second.resolved_toml, first.resolved_toml);
}

// ---------------------------------------------------------------------------------------------
// STL meshes
// ---------------------------------------------------------------------------------------------

// A closed triangulated sphere: the octahedron's faces split `levels` times, the new vertices pushed out
// onto the sphere. Its six extreme vertices lie on the axes, so its bounding box is the sphere's.
std::vector<Triangle> octasphere(const Point& c, double R, int levels) {
  const auto on_sphere = [&](const Point& u) {
    const double n = std::sqrt(dot(u, u));
    return Point{c[0] + R * u[0] / n, c[1] + R * u[1] / n, c[2] + R * u[2] / n};
  };
  const Point px{1, 0, 0}, nx{-1, 0, 0}, py{0, 1, 0}, ny{0, -1, 0}, pz{0, 0, 1}, nz{0, 0, -1};
  std::vector<std::array<Point, 3>> unit = {{px, py, pz}, {py, nx, pz}, {nx, ny, pz}, {ny, px, pz},
                                            {py, px, nz}, {nx, py, nz}, {ny, nx, nz}, {px, ny, nz}};
  for (int level = 0; level < levels; ++level) {
    std::vector<std::array<Point, 3>> finer;
    // a midpoint a + b is the same sum from either side, so neighbouring triangles share it exactly
    const auto mid = [](const Point& a, const Point& b) {
      const Point m{a[0] + b[0], a[1] + b[1], a[2] + b[2]};
      const double n = std::sqrt(dot(m, m));
      return Point{m[0] / n, m[1] / n, m[2] / n};
    };
    for (const auto& [a, b, t] : unit) {
      const Point ab = mid(a, b), bt = mid(b, t), ta = mid(t, a);
      finer.push_back({a, ab, ta});
      finer.push_back({ab, b, bt});
      finer.push_back({ta, bt, t});
      finer.push_back({ab, bt, ta});
    }
    unit = std::move(finer);
  }
  std::vector<Triangle> mesh;
  for (const auto& [a, b, t] : unit) mesh.push_back({on_sphere(a), on_sphere(b), on_sphere(t)});
  return mesh;
}

void write_ascii_stl(const std::string& path, const std::vector<Triangle>& mesh) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fprintf(f, "solid sphere\n");
  for (const auto& t : mesh) {
    std::fprintf(f, "  facet normal 0 0 0\n    outer loop\n");
    for (const auto& v : t) std::fprintf(f, "      vertex %.17g %.17g %.17g\n", v[0], v[1], v[2]);
    std::fprintf(f, "    endloop\n  endfacet\n");
  }
  std::fprintf(f, "endsolid sphere\n");
  std::fclose(f);
}

const Point kCenter{0.3, 0.3, 0.3};
constexpr double kRadius = 0.1;

#ifdef ISPH_HAVE_CGAL

// Whether one of `problems` starts with `start` and contains `part`.
::testing::AssertionResult reports_like(const std::vector<std::string>& problems, const std::string& start,
                                        const std::string& part) {
  for (const auto& p : problems)
    if (p.rfind(start, 0) == 0 && p.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  auto failure = ::testing::AssertionFailure()
                 << "no problem \"" << start << "...\" with \"" << part << "\" among the " << problems.size() << ":";
  for (const auto& p : problems) failure << "\n  " << p;
  return failure;
}

// Binary STL: an 80-byte header, the count, then per triangle a normal and three corners (float32) and
// two bytes of attributes.
void write_binary_stl(const std::string& path, const std::vector<Triangle>& mesh) {
  std::ofstream out(path, std::ios::binary);
  const std::string header(80, ' ');
  out.write(header.data(), 80);
  const auto count = static_cast<std::uint32_t>(mesh.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : mesh) {
    float values[12] = {};
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) values[3 + 3 * v + k] = static_cast<float>(t[v][k]);
    out.write(reinterpret_cast<const char*>(values), sizeof values);
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
}

// The sphere of radius 0.1 m = 10 dx as a primitive and as a closed mesh of 8192 triangles (ASCII and
// binary STL) gives the same particles, 4224 of them at the same positions. The mesh lies inside the sphere
// down to its inscribed radius; the lattice points' distances from the centre are sqrt(m)/2 dx with m = 3
// mod 8, so none lies within 0.06 dx of the sphere, outside the sag of the mesh (0.01 dx, checked here),
// and the two inside tests must agree point by point.
TEST_F(GeometryTest, SphereFromStlIsTheSphere) {
  const auto mesh = octasphere(kCenter, kRadius, 5);
  ASSERT_EQ(mesh.size(), 8192u);
  double inscribed = kRadius;  // the least distance from the centre to a triangle's plane
  for (const auto& t : mesh) {
    const Point u = minus(t[1], t[0]), v = minus(t[2], t[0]);
    const Point n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    inscribed = std::min(inscribed, std::abs(dot(n, minus(t[0], kCenter))) / std::sqrt(dot(n, n)));
  }
  const double dx = 0.01;
  EXPECT_LT(kRadius - inscribed, 0.015 * dx);
  for (int i = -12; i < 12; ++i)
    for (int j = -12; j < 12; ++j)
      for (int k = -12; k < 12; ++k) {
        const double r = dx * std::sqrt((i + 0.5) * (i + 0.5) + (j + 0.5) * (j + 0.5) + (k + 0.5) * (k + 0.5));
        ASSERT_FALSE(r >= inscribed - 0.01 * dx && r <= kRadius + 0.01 * dx) << i << " " << j << " " << k;
      }
  write_ascii_stl((dir_ / "ball.stl").string(), mesh);
  write_binary_stl((dir_ / "ball_binary.stl").string(), mesh);

  // one lattice for all (float32 corners would move the bounding box, the lattice's default origin, by 3e-9 m)
  const std::string origin = "\nlattice_origin = [0.2, 0.2, 0.2]";
  const auto sphere = particles(
      "sphere.toml", with_shape(kSolid, R"({ type = "sphere", center = [0.3, 0.3, 0.3], radius = 0.1 })" + origin));
  const auto ascii = particles("ascii.toml", with_shape(kSolid, R"({ type = "stl", file = "ball.stl" })" + origin));
  const auto binary =
      particles("binary.toml", with_shape(kSolid, R"({ type = "stl", file = "ball_binary.stl" })" + origin));
  EXPECT_EQ(sphere.size(), 4224u);
  EXPECT_EQ(ascii, sphere);
  EXPECT_EQ(binary, sphere);

  // translate moves the same particles; scale then translate maps the bounding box (and the lattice's
  // default origin, its lower corner) from [0.2, 0.4] to [0.1, 0.5]
  auto moved = particles("moved.toml",
                         with_shape(kSolid, R"({ type = "stl", file = "ball.stl", translate = [0.7, 0.7, 0.7] })"));
  ASSERT_EQ(moved.size(), sphere.size());
  for (std::size_t a = 0; a < moved.size(); ++a)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(moved[a][k], sphere[a][k] + 0.7, 1e-12);
  const CaseSpec scaled = load_case(
      write("scaled.toml",
            with_shape(kSolid, R"({ type = "stl", file = "ball.stl", scale = 2, translate = [-0.3, -0.3, -0.3] })")));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(scaled.bodies[0].lattice_origin[k], 0.1, 1e-12);
}

// An open mesh (the sphere less three triangles) is refused, naming the file and its border edges; so
// are a file that is no STL and a missing one.
TEST_F(GeometryTest, OpenMeshIsRefused) {
  auto mesh = octasphere(kCenter, kRadius, 4);
  for (const std::size_t gone : {1500u, 900u, 10u}) mesh.erase(mesh.begin() + static_cast<std::ptrdiff_t>(gone));
  std::map<std::pair<Point, Point>, int> edges;  // each undirected edge's triangles
  for (const auto& t : mesh)
    for (int e = 0; e < 3; ++e) ++edges[std::minmax(t[e], t[(e + 1) % 3])];
  const auto border = std::count_if(edges.begin(), edges.end(), [](const auto& e) { return e.second == 1; });
  EXPECT_EQ(border, 9);
  write_ascii_stl((dir_ / "open.stl").string(), mesh);
  const auto path = write("open.toml", with_shape(kSolid, R"({ type = "stl", file = "open.stl" })"));
  const auto file = (dir_ / "open.stl").lexically_normal().string();
  EXPECT_TRUE(reports(problems(path), path + ": bodies[0].shape.file: \"" + file + "\" is not a closed surface (" +
                                          std::to_string(border) +
                                          " edges border one triangle only); an stl shape must be watertight"));
  write("junk.stl", "not a mesh");  // neither ASCII STL (no "solid") nor binary (no triangle)
  const auto junk = write("junk.toml", with_shape(kSolid, R"({ type = "stl", file = "junk.stl" })"));
  EXPECT_TRUE(reports(problems(junk), junk + ": bodies[0].shape.file: \"" + (dir_ / "junk.stl").string() +
                                          "\" holds no triangle with three distinct corners"));
  const auto missing = write("missing.toml", with_shape(kSolid, R"({ type = "stl", file = "none.stl" })"));
  EXPECT_TRUE(reports(problems(missing), missing + ": bodies[0].shape.file: cannot open \"" +
                                             (dir_ / "none.stl").lexically_normal().string() + "\""));
}

// A mesh in millimetres: the loader refuses a bounding box of more than 1e8 lattice points at the body's
// spacing (here 2e12), and the scene a mesh (partly) outside the tank, saying how many times the tank's
// size it is when ten times or more.
TEST_F(GeometryTest, MeshOfTheWrongSizeOrPlaceIsNamed) {
  write_ascii_stl((dir_ / "ball.stl").string(), octasphere(kCenter, kRadius, 4));
  const auto mm = write("mm.toml", with_shape(kSolid, R"({ type = "stl", file = "ball.stl", scale = 1000 })"));
  EXPECT_TRUE(reports_like(
      problems(mm), mm + ": bodies[0].shape.scale: the mesh \"" + (dir_ / "ball.stl").string() + "\" spans 200",
      " m, 8e+12 lattice points at the body's spacing of 0.01 m (at most 1e+08): STL has no units, "
      "and a file in millimetres needs scale = 0.001 (in centimetres, 0.01)"));

  const std::string tank = R"(
dimension = 3
dx = 0.01
end_time = 1
gravity = [0, 0, -9.81]
[stages]
fluid = true
[[materials]]
name = "water"
model = "newtonian"
density = 1000
viscosity = 1e-6
[[materials]]
name = "steel"
density = 7800
youngs_modulus = 2e11
poisson_ratio = 0.3
[[bodies]]
name = "water"
kind = "fluid"
material = "water"
shape = { type = "box", min = [0, 0, 0], max = [0.2, 0.2, 0.1] }
[[bodies]]
name = "floor"
kind = "wall"
shape = { type = "box", min = [0, 0, -0.03], max = [0.4, 0.4, 0] }
[[bodies]]
name = "ball"
material = "steel"
shape = SHAPE
)";
  // above the floor, where the tank is open, the ball is inside; beyond its side it is not
  const auto above =
      write("above.toml", with_shape(tank, R"({ type = "stl", file = "ball.stl", translate = [0, 0, 5] })"));
  const auto p = check_problems(above);
  EXPECT_FALSE(reports_like(p, above + ": bodies[2].shape: the mesh", "outside the tank"));
  const auto beyond =
      write("beyond.toml", with_shape(tank, R"({ type = "stl", file = "ball.stl", translate = [0.8, 0, 0] })"));
  const auto q = check_problems(beyond);
  EXPECT_TRUE(
      reports_like(q, beyond + ": bodies[2].shape: the mesh of body 'ball' spans (",
                   " m, partly outside the tank (the wall bodies' bounding box, (0, 0, -0.03) to (0.4, 0.4, 0) m, "
                   "open against gravity)"));
  EXPECT_EQ(q.size(), 1u);  // no advice on units for a mesh of half the tank's size
  EXPECT_FALSE(reports_like(q, beyond, "times the tank's size"));
  std::string coarse = tank;
  coarse.replace(coarse.find("dx = 0.01"), 9, "dx = 0.1");
  const auto cm = write("cm.toml", with_shape(coarse, R"({ type = "stl", file = "ball.stl", scale = 100 })"));
  EXPECT_TRUE(reports_like(check_problems(cm), cm + ": bodies[2].shape: the mesh of body 'ball' spans (",
                           "; it is 50 times the tank's size: is the file in centimetres? STL has no units: scale = "
                           "0.01 makes them metres"));
}

TEST_F(GeometryTest, ResolvedStlReloadsToTheSameCase) {
  write_ascii_stl((dir_ / "ball.stl").string(), octasphere(kCenter, kRadius, 2));
  const auto path =
      write("original.toml",
            with_shape(kSolid, R"({ type = "stl", file = "ball.stl", scale = 0.5, translate = [0.1, 0, 0] })"));
  const CaseSpec first = load_case(path);
  EXPECT_EQ(first.bodies[0].shape.file, (dir_ / "ball.stl").string());
  std::filesystem::create_directories(dir_ / "elsewhere");
  const CaseSpec second = load_case(write("elsewhere/resolved.toml", first.resolved_toml));
  EXPECT_EQ(second.bodies[0].shape, first.bodies[0].shape);
  EXPECT_EQ(second.bodies[0].lattice_origin, first.bodies[0].lattice_origin);
  EXPECT_EQ(second.resolved_toml, first.resolved_toml);
}

#else

TEST_F(GeometryTest, StlNeedsCgal) {
  write_ascii_stl((dir_ / "ball.stl").string(), octasphere(kCenter, kRadius, 2));
  const auto path = write("ball.toml", with_shape(kSolid, R"({ type = "stl", file = "ball.stl" })"));
  EXPECT_TRUE(reports(problems(path), path + ": bodies[0].shape.type: \"stl\" needs CGAL, and this build has none: "
                                             "apt-get install libcgal-dev, then configure and build again"));
}

#endif

}  // namespace
}  // namespace isph
