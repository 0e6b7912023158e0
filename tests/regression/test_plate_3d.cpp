// The plate of cases/hydrostatic_plate_3d.toml without its water (docs/VALIDATION.md section 32): a square
// aluminium plate clamped on all four edges sags as the 3D continuum that scripts/reference/fe_plate_3d.py solves.
#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "run_support.hpp"

namespace {

// The case's plate (T = 0.05 m at dx = 12.5 mm, T/dx = 4), half as wide: a = 0.5 m between the clamps'
// faces, clamped over 0.05 m beyond each of its four edges, its top face at z = 0.
std::string half_plate(const std::string& material) {
  return R"([[bodies]]
name = "plate"
kind = "structure"
material = ")" +
         material + R"("
dx = 0.0125
shape = { type = "box", min = [-0.05, -0.05, -0.05], max = [0.55, 0.55, 0.0] }
lattice_offset = [0.0, 0.0, 0.5]
clamps = [ { type = "box", min = [-0.05, -0.05, -0.05], max = [0.0, 0.55, 0.0] },
           { type = "box", min = [0.5, -0.05, -0.05], max = [0.55, 0.55, 0.0] },
           { type = "box", min = [0.0, -0.05, -0.05], max = [0.5, 0.0, 0.0] },
           { type = "box", min = [0.0, 0.5, -0.05], max = [0.5, 0.55, 0.0] } ]
)";
}

// The case's plate (T = 0.05 m at T/dx = 4, cell quadrature, velocity-Verlet at Courant 0.75), half as
// wide (a = 0.5 m between the clamps' faces) to run in seconds, under its weight and a traction of 1e5 Pa
// on its top face ramped over 2 ms, damped to rest by 4 ms.
fs::path square_plate_case(const fs::path& folder, const std::string& quadrature) {
  fs::create_directories(folder);
  const fs::path file = folder / "square_plate.toml";
  std::ofstream(file) << R"(name = "square_plate"
dimension = 3
dx = 0.0125
end_time = 0.005
gravity = [0.0, 0.0, -9.81]
[structure]
integrator = "verlet"
courant = 0.75
damping = 8000.0
quadrature = ")" << quadrature
                      << R"("
[output]
interval = 0.0005
snapshots = false
[[materials]]
name = "aluminium"
density = 2700.0
youngs_modulus = 67.5e9
poisson_ratio = 0.34
)" << half_plate("aluminium")
                      << R"([[loads]]
type = "traction"
body = "plate"
region = { type = "box", min = [0.0, 0.0, -0.001], max = [0.5, 0.5, 0.0] }
traction = [0.0, 0.0, -1.0e5]
ramp_time = 0.002
[[probes]]
name = "centre"
point = [0.25, 0.25, -0.025]
)";
  return file;
}

double rest_centre(const std::string& quadrature) {
  const fs::path out = fresh_dir("square_plate_" + quadrature);
  const auto r =
      isph("run " + square_plate_case(out, quadrature).string() + " --quiet --out " + (out / "run").string());
  EXPECT_EQ(r.status, 0) << r.output;
  auto p = read_csv(out / "run" / "probes.csv");
  return -p["centre.uz"].back();
}

}  // namespace

// The 3D continuum's centre deflection (scripts/reference/fe_plate_3d.py --span 0.5 --pressure 1e5, 27-node
// hexahedra): 1.1604e-5, 1.1871e-5 and 1.1887e-5 m at 8 x 8 x 1, 12 x 12 x 2 and 16 x 16 x 2 elements on the
// quarter plate. Cell quadrature comes within 1.2 % of it; the midpoint rule ("point") leaves the plate
// 5.6 % softer. Measured 2026-12-05: cell 1.2029e-5 m, point 1.2554e-5 m.
TEST(Plate3D, ClampedSquarePlateSagsAsThe3DContinuum) {
  constexpr double fe = 1.1887e-5;
  const double cell = rest_centre("cell");
  const double point = rest_centre("point");
  EXPECT_NEAR(cell, 1.2029e-5, 0.01 * 1.2029e-5);
  EXPECT_NEAR(point, 1.2554e-5, 0.01 * 1.2554e-5);
  EXPECT_NEAR(cell / fe, 1.012, 0.01);
  EXPECT_GT(point / fe, cell / fe);
}

namespace {

// The same half-width plate (a = 0.5 m) under 0.25 m of water at 1/60 m (13,500 particles), with the
// shipped case's coupling (two interface iterations, OPS shifting with the FSI layer, fluid Courant 0.2),
// but 1,000 times softer (E = 67.5 MPa: 31 times fewer substeps) and damped (400 1/s) to rest by 0.06 s.
// Its deflection stays under 1 % of the thickness (linear), so the continuum's is 1,000 times the aluminium's.
fs::path soft_plate_under_water_case(const fs::path& folder) {
  fs::create_directories(folder);
  const fs::path file = folder / "soft_plate_under_water.toml";
  std::ofstream(file) << R"(name = "soft_plate_under_water"
dimension = 3
dx = 0.016666666666666666
end_time = 0.08
gravity = [0.0, 0.0, -9.81]
[stages]
structure = true
fluid = true
[structure]
integrator = "verlet"
quadrature = "cell"
courant = 0.75
damping = 400.0
[fluid]
courant = 0.2
[fluid.ppe]
tolerance = 1e-5
preconditioner_reuse = 10
[fluid.shifting]
type = "ops"
[coupling]
max_iterations = 2
fsi_shifting = true
[output]
interval = 0.001
snapshots = false
[[materials]]
name = "water"
model = "newtonian"
density = 1000.0
viscosity = 1.0e-6
[[materials]]
name = "soft_aluminium"
density = 2700.0
youngs_modulus = 67.5e6
poisson_ratio = 0.34
[[bodies]]
name = "water"
kind = "fluid"
material = "water"
shape = { type = "box", min = [0.0, 0.0, 0.0], max = [0.5, 0.5, 0.25] }
)" << half_plate("soft_aluminium")
                      << R"([[bodies]]
name = "wall_x0"
kind = "wall"
shape = { type = "box", min = [-0.05, -0.05, 0.0], max = [0.0, 0.55, 0.3] }
[[bodies]]
name = "wall_x1"
kind = "wall"
shape = { type = "box", min = [0.5, -0.05, 0.0], max = [0.55, 0.55, 0.3] }
[[bodies]]
name = "wall_y0"
kind = "wall"
shape = { type = "box", min = [0.0, -0.05, 0.0], max = [0.5, 0.0, 0.3] }
[[bodies]]
name = "wall_y1"
kind = "wall"
shape = { type = "box", min = [0.0, 0.5, 0.0], max = [0.5, 0.55, 0.3] }
[[probes]]
name = "centre"
point = [0.25, 0.25, -0.025]
[[probes]]
name = "bottom_p"
type = "pressure"
point = [0.25, 0.25, 0.01]
[[probes]]
name = "plate_force"
type = "force"
body = "plate"
)";
  return file;
}

}  // namespace

// The coupled 3D plate settles under the water as the 3D continuum sags under the column's pressure
// (rho g H = 2,452.5 Pa) and its weight: 1,000 times scripts/reference/fe_plate_3d.py --span 0.5 --pressure
// 2452.5 --elements 16 2, 4.4316e-4 m (thin-plate theory: 3.741e-4 m). The pressure 0.01 m above the
// plate is hydrostatic, rho g (H - 0.01) = 2,354.4 Pa; the water carried by the plate is the column's
// weight less the pairwise force's 3D lattice sum (0.9817, docs/VALIDATION.md section 33), and no water
// enters the plate. Measured 2026-12-07 (means over 0.06-0.08 s): 4.4208e-4 m; 2,347.7 Pa; 602.0 N.
// About a minute on one core.
TEST(Plate3D, CoupledSoftPlateSettlesUnderTheWaterAsTheContinuum) {
  const fs::path out = fresh_dir("soft_plate_under_water");
  const auto r = isph("run " + soft_plate_under_water_case(out).string() + " --quiet --out " + (out / "run").string());
  ASSERT_EQ(r.status, 0) << r.output;
  auto p = read_csv(out / "run" / "probes.csv");
  const auto& t = p["time"];
  const double centre = -mean_over(t, p["centre.uz"], 0.06);
  EXPECT_NEAR(centre, 4.4316e-4, 0.015 * 4.4316e-4);
  EXPECT_NEAR(centre, 4.4208e-4, 0.003 * 4.4208e-4);  // measured 2026-12-07
  EXPECT_NEAR(mean_over(t, p["bottom_p.p"], 0.06), 1000 * 9.81 * 0.24, 0.005 * 2354.4);
  const double column = 1000 * 9.81 * 0.25 * 0.5 * 0.5;
  EXPECT_NEAR(-mean_over(t, p["plate_force.fz"], 0.06), 0.9817 * column, 0.005 * column);
  const std::string s = read_file(out / "run" / "summary.json");
  EXPECT_EQ(json_number(s, "fluid_inside_structure_max"), 0) << s;
  EXPECT_LT(json_number(s, "peak_created_fraction"), 0.01) << s;
}

// `isph check` warns where the support of the water's first layer, dx/2 from a structure's face, reaches
// through the structure (T + dx/2 < 2h): the case's plate thinned to 0.025 m under water at 1/60 m
// (2h = 0.04 m). The case as shipped (0.05 m) and the shipped 3D gate (5 mm under 2h = 6 mm) pass quietly.
TEST(Plate3D, CheckWarnsWhereTheWatersSupportReachesThroughAStructure) {
  const std::string plate = kCases + "hydrostatic_plate_3d.toml";
  const auto thin = isph("check " + plate +
                         " --set 'bodies.plate.shape={type=\"box\",min=[-0.05,-0.05,-0.025],max=[1.05,1.05,0.0]}'");
  EXPECT_EQ(thin.status, 0) << thin.output;
  EXPECT_NE(thin.output.find("warning: " + plate +
                             ": bodies[1]: structure 'plate' is 0.025 m thick: the kernel "
                             "support (2h = 0.04 m)"),
            std::string::npos)
      << thin.output;
  EXPECT_NE(thin.output.find("dx <= 0.0131579 m"), std::string::npos) << thin.output;
  for (const std::string& shipped : {plate, kCases + "elastic_gate_3d.toml"}) {
    const auto r = isph("check " + shipped);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  }
}
