// Open boundaries (sim/open_boundary.hpp, issue 55): a plane Poiseuille flow through an inlet and an
// outlet keeps its analytical profile and its mass; a run continues across its buffers bit for bit; and
// an open boundary that cannot serve is an error naming its key.
#include <cmath>
#include <fstream>

#include "io/output.hpp"
#include "run_support.hpp"
#include "snapshot_compare.hpp"

namespace {

const std::string kChannel = "run " + kCases + "poiseuille_channel.toml --quiet";
constexpr double kHeight = 0.2, kMeanVelocity = 0.1;

constexpr double kParticleMass = 1000 * 0.01 * 0.01;  // rho dx^2, per metre of depth

// The channel run with `settings` and no snapshots into a fresh folder: its summary.json ("" if it failed).
std::string channel_summary(const std::string& name, const std::string& settings) {
  const fs::path out = fresh_dir(name);
  const auto r = regression::isph(kChannel + " --out " + out.string() + " --set output.snapshots=false " + settings);
  EXPECT_EQ(r.status, 0) << r.output;
  return r.status == 0 ? read_file(out / "summary.json") : "";
}

// The plane Poiseuille profile of the case's inflow.
double poiseuille(double y) { return 1.5 * kMeanVelocity * 4 * y * (kHeight - y) / (kHeight * kHeight); }

}  // namespace

// cases/poiseuille_channel.toml (H = 0.2 m at dx = H/20, Re = 2) to 2 s, five times the settling time.
// Between x = 0.5 m and the outlet's plane at 0.6 m the fluid particles' u_x follows the analytical
// profile to an RMS of 1 % of its peak (measured 2026-12-07: 0.50 %); the largest deviation, 1.04 %, is
// the particle at the plane (0.73 % further in) and falls to 0.46 % at H/40 (docs/VALIDATION.md section
// 34). The particles the inlet let in match the flow its profile prescribed within one per lattice row
// (20 rows; measured 2.5 particles), and the mass books balance: what came in less what went out is the
// fluid's gain, and in the steady state that is nothing. The floor's viscous drag is the wall shear
// stress 6 rho nu U / H = 30 Pa over the channel's 0.6 m, 18 N/m, within 5 % (measured -3.1 %).
TEST(OpenBoundaries, PoiseuilleChannelKeepsItsProfileAndItsMass) {
  if (!isph::SnapshotWriter::available()) GTEST_SKIP() << "this build writes no snapshots (no HDF5)";
  const fs::path out = fresh_dir("poiseuille_channel");
  const auto r = regression::isph(kChannel + " --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const isph::SnapshotData last = isph::read_snapshot(isph::newest_snapshot(out.string()));
  EXPECT_NEAR(last.time, 2.0, 1e-12);
  const auto &x = last.field("position").data, &u = last.field("velocity").data, &kind = last.field("kind").data;
  double worst = 0, squares = 0;
  int near_outlet = 0;
  for (std::size_t k = 0; k < kind.size(); ++k) {
    if (kind[k] != 0 || x[3 * k] < 0.5 || x[3 * k] > 0.6) continue;
    ++near_outlet;
    const double error = (u[3 * k] - poiseuille(x[3 * k + 1])) / poiseuille(kHeight / 2);
    worst = std::max(worst, std::abs(error));
    squares += error * error;
  }
  EXPECT_GE(near_outlet, 200);  // 10 columns of 20 (one mid-crossing)
  const double rms = std::sqrt(squares / near_outlet);
  EXPECT_LT(rms, 0.01);
  EXPECT_NEAR(rms, 0.0050, 0.001);    // windows on the measured values: a regression of a few tenths of a
  EXPECT_NEAR(worst, 0.0104, 0.002);  // per cent of the peak shows

  const auto probes = read_csv(out / "probes.csv");
  const double viscous_drag = probes.at("floor.fx").back() - probes.at("floor_pressure.fx").back();
  EXPECT_NEAR(viscous_drag, 18.0, 0.05 * 18.0);
  EXPECT_NEAR(viscous_drag, 17.45, 0.2);

  const std::string summary = read_file(out / "summary.json");
  EXPECT_NEAR(json_number(summary, "mass_in"), json_number(summary, "mass_prescribed"), 20 * kParticleMass) << summary;
  EXPECT_NEAR(json_number(summary, "mass_prescribed"), 1000 * kMeanVelocity * kHeight * 2.0, 0.01 * 40) << summary;
  EXPECT_LT(std::abs(json_number(summary, "mass_balance")), 1e-12) << summary;
  EXPECT_NEAR(json_number(summary, "fluid_mass_change"), 0, 5 * kParticleMass) << summary;  // steady: in = out
}

// The channel with its ceiling a clamped elastic structure (a wall above it closes the domain): the
// structure feels the water's shear (ViscousBoundaryForce) as the floor does, 6 rho nu U / H = 30 Pa over
// 0.6 m, 18 N/m within 5 % (measured 2026-12-07: 17.66 at 2 s, the floor 17.40 in the same run), and the
// force the structure's solver receives carries it (before, only the pressure's -0.3 N/m).
TEST(OpenBoundaries, StructureWallFeelsTheWatersShear) {
  std::string text = read_file(kCases + "poiseuille_channel.toml");
  const std::pair<std::string, std::string> edits[] = {
      {"structure = false", "structure = true"},
      {"name = \"ceiling\"\nkind = \"wall\"\nshape = { type = \"rectangle\", min = [-0.1, 0.2], max = [0.7, 0.23] }",
       "name = \"ceiling\"\nkind = \"structure\"\nmaterial = \"lid\"\n"
       "shape = { type = \"rectangle\", min = [-0.1, 0.2], max = [0.7, 0.23] }\n"
       "clamps = [{ type = \"rectangle\", min = [-0.1, 0.2], max = [0.7, 0.23] }]\n\n"
       "[[bodies]]\nname = \"roof\"\nkind = \"wall\"\n"
       "shape = { type = \"rectangle\", min = [-0.1, 0.23], max = [0.7, 0.26] }\n\n"
       "[[materials]]\nname = \"lid\"\ndensity = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.3"},
  };
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  text +=
      "\n[[probes]]\nname = \"ceiling\"\ntype = \"force\"\nbody = \"ceiling\"\nterms = \"all\"\n"
      "\n[[probes]]\nname = \"ceiling_pressure\"\ntype = \"force\"\nbody = \"ceiling\"\n";
  const fs::path out = fresh_dir("channel_structure_ceiling");
  const fs::path file = out / "case.toml";
  fs::create_directories(out);
  std::ofstream(file) << text;
  const auto r = regression::isph("run " + file.string() + " --quiet --set output.snapshots=false --out " +
                                  (out / "run").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto probes = read_csv(out / "run/probes.csv");
  const double ceiling = probes.at("ceiling.fx").back() - probes.at("ceiling_pressure.fx").back();
  const double floor = probes.at("floor.fx").back() - probes.at("floor_pressure.fx").back();
  EXPECT_NEAR(ceiling, 18.0, 0.05 * 18.0);
  EXPECT_NEAR(ceiling, 17.66, 0.2);  // a window on the measured value
  EXPECT_NEAR(ceiling, floor, 0.03 * 18.0);
  const std::string summary = read_file(out / "run/summary.json");
  const auto at = summary.find("mean_force_on_structure");
  ASSERT_NE(at, std::string::npos) << summary;
  // the run's mean over every step, the start's thinner shear layer included (measured 18.01)
  EXPECT_NEAR(json_number(summary.substr(at), "fx"), 18.0, 0.05 * 18.0) << summary;
}

// Turek & Hron's channel at D/dx = 10 (the case's header).
const std::string kCoarseTurekHron = kCases +
                                     "turek_hron.toml --set dx=0.01 --set "
                                     "'bodies.fluid.shape={type=\"rectangle\",min=[-0.04,0.0],max=[2.54,0.41]}'";

// Turek & Hron's channel starts from rest, without gravity: the energy books' scale is the fluid's kinetic
// energy at the inlet's peak speed once ramped up, (1/2) M (1.5 U)^2 with M = 10,100 particles of 0.1 kg
// and U = 1 m/s: 1,136.25 J (before, 5e-24 J, and the coupling's round-off stopped the run at 0.018 s).
TEST(OpenBoundaries, ChannelStartedFromRestKeepsItsEnergyBooks) {
  const fs::path out = fresh_dir("turek_hron_start");
  const auto r = regression::isph("run " + kCoarseTurekHron + " --quiet --set end_time=0.05 --out " + out.string() +
                                  " --set output.snapshots=false");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string summary = read_file(out / "summary.json");
  EXPECT_EQ(json_number(summary, "fluid"), 10100) << summary;
  EXPECT_NEAR(json_number(summary, "scale"), 0.5 * 10100 * 0.1 * 1.5 * 1.5, 0.01) << summary;
}

// CFD2 (the bar clamped whole, the case header's line) at D/dx = 10 with the cylinder on rings and half the shipped
// fluid Courant number, 0.125, from rest to 5 s: the drag on cylinder and bar over 4-5 s lies within 5 % of Turek &
// Hron's 136.7 N/m (measured 2026-12-07: 142.5 N/m, +4.2 %; +14.4 % at Courant 0.25, +24 % on the lattice's
// staircase; docs/STUDIES.md), and the channel loses less than 0.5 % of its inflow (measured 0.08 %).
TEST(OpenBoundaries, CoarseCfd2DragWithinFivePercentAtHalfTheCourantNumber) {
  const fs::path out = fresh_dir("turek_hron_cfd2");
  const auto r = regression::isph(
      "run " + kCoarseTurekHron + " --quiet --set end_time=5 --set output.snapshots=false --set fluid.courant=0.125" +
      " --set 'bodies.bar.clamps=[{type=\"rectangle\",min=[0.2,0.19],max=[0.6,0.21]}]' --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto probes = read_csv(out / "probes.csv");
  const auto& t = probes.at("time");
  const double drag = mean_over(t, probes.at("cylinder.fx"), 4.0) + mean_over(t, probes.at("bar.fx"), 4.0);
  EXPECT_NEAR(drag / 136.7, 1.0, 0.05);
  EXPECT_NEAR(drag, 142.5, 2.5);
  const std::string summary = read_file(out / "summary.json");
  EXPECT_LT(std::abs(json_number(summary, "fluid_mass_change")) / json_number(summary, "mass_in"), 0.005) << summary;
}

// FSI1's bar is as light as the water, and its interface iterations meet their tolerance (1e-2) only when the
// PPE is solved to 1e-8 (the case header's FSI1 line): at D/10 over the first 0.5 s they converge in about six
// iterations every step (measured 6.0 to 0.8 s), where at the shipped 1e-6 they stall at the limit of 30 in
// some steps (7 of 22 to 0.4 s) and the bar diverged at 0.4 s (docs/VALIDATION.md section 36).
TEST(OpenBoundaries, LightBarsInterfaceConvergesWithTheTightPressureSolve) {
  const std::string fsi1 =
      " --quiet --set end_time=0.5 --set output.snapshots=false --set materials.bar.density=1000"
      " --set 'open_boundaries.inlet.velocity=\"1.5 * 0.2 * 4 * y * (0.41 - y) / 0.41^2\"'";
  for (const char* tolerance : {"1e-8", "1e-6"}) {
    const fs::path out = fresh_dir(std::string("turek_hron_fsi1_") + tolerance);
    const auto r = regression::isph("run " + kCoarseTurekHron + fsi1 + " --set fluid.ppe.tolerance=" + tolerance +
                                    " --out " + out.string());
    const std::string summary = read_file(out / "summary.json");
    if (std::string(tolerance) == "1e-8") {
      ASSERT_EQ(r.status, 0) << r.output;
      EXPECT_EQ(json_number(summary, "unconverged_steps"), 0) << summary;
      EXPECT_LT(json_number(summary, "mean_interface_iterations"), 8) << summary;
    } else {
      EXPECT_GT(json_number(summary, "unconverged_steps"), 0) << summary;
    }
  }
}

// A structure with water on both sides whose middle particles' support reaches the water on both: Turek &
// Hron's bar, 2 cm thick, at dx = 1 cm (2h = 2.4 cm) was crushed and the run diverged at 1.4 s
// (docs/VALIDATION.md section 36). `isph check` warns, with the spacing that avoids it, T / (2 * 2h/dx - 1) =
// 0.02 / 3.8; not at the shipped dx = 5 mm, nor for the gate, whose water is on one side.
TEST(OpenBoundaries, CheckWarnsWhereAStructureHasWaterOnBothSidesOfItsSupport) {
  const auto coarse = regression::isph("check " + kCoarseTurekHron);
  EXPECT_EQ(coarse.status, 0) << coarse.output;
  EXPECT_NE(coarse.output.find("structure 'bar' is 0.02 m thick with water on both sides"), std::string::npos)
      << coarse.output;
  EXPECT_NE(coarse.output.find("dx <= 0.00526316 m"), std::string::npos) << coarse.output;
  for (const std::string& shipped : {kCases + "turek_hron.toml", kCases + "elastic_gate.toml"}) {
    const auto r = regression::isph("check " + shipped);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  }
}

// Stopped at 0.25 s and continued to 0.6 s, the channel ends with the uninterrupted run's bits: the
// snapshot carries each buffer particle's boundary and the next stable id, and the particles the inlet
// created since the start are created again with their ids.
TEST(OpenBoundaries, RestartAcrossTheBuffersIsBitForBit) {
  if (!isph::SnapshotWriter::available()) GTEST_SKIP() << "this build writes no snapshots (no HDF5)";
  const std::string run = kChannel + " --set end_time=0.6 --set output.snapshot_interval=0.25";
  const fs::path full = fresh_dir("channel_full"), continued = fresh_dir("channel_continued");
  const auto f = regression::isph(run + " --out " + full.string());
  ASSERT_EQ(f.status, 0) << f.output;
  const auto c = regression::isph(run + " --out " + continued.string() + " --restart " +
                                  (full / "snapshots/snapshot_00001.h5").string());
  ASSERT_EQ(c.status, 0) << c.output;
  const isph::SnapshotData at_stop = isph::read_snapshot((full / "snapshots/snapshot_00001.h5").string());
  EXPECT_GT(at_stop.attributes.at("next_id"), 1832) << "the inlet has created particles before the stop";
  expect_same_bits(isph::newest_snapshot(full.string()), isph::newest_snapshot(continued.string()));
  EXPECT_EQ(read_file(full / "probes.csv"), read_file(continued / "probes.csv"));
}

// An inlet whose plane lies outside the channel, a profile that does not parse and a buffer thinner
// than the kernel's support are each one error naming the key.
TEST(OpenBoundaries, BadInputIsAClearErrorNamingTheKey) {
  const std::string check = "check " + kCases + "poiseuille_channel.toml";
  const std::pair<std::string, std::string> cases[] = {
      {"open_boundaries.inlet.point=[-1.0,0.1]", "open_boundaries[0].point: the plane's point lies outside"},
      {"open_boundaries.inlet.velocity=\"1.5 * (y\"", "open_boundaries[0].velocity: missing ')' at character 9"},
      {"open_boundaries.outlet.layers=2",
       "open_boundaries[1].layers: the buffer, 2 x dx = 0.02 m, is thinner than the kernel's support"},
  };
  for (const auto& [set, message] : cases) {
    const auto r = regression::isph(check + " --set '" + set + "'");
    EXPECT_NE(r.status, 0) << set;
    EXPECT_NE(r.output.find(message), std::string::npos) << set << "\n" << r.output;
    EXPECT_NE(r.output.find("1 problem(s) found"), std::string::npos) << set << "\n" << r.output;
  }
}

// Rings fill a wall's 2D circle only, one whose radius fills the kernel's support, and take no Cartesian
// lattice's origin: each of these is one error naming the key.
TEST(OpenBoundaries, RingsFillACircleThatFillsTheSupport) {
  const std::string check = "check " + kCases + "dfg_cylinder.toml";
  const std::pair<std::string, std::string> cases[] = {
      {"bodies.floor.lattice=\"rings\"",
       "bodies[1].lattice: \"rings\" fills a circle in 2D (shape.type = \"rectangle\")"},
      {"bodies.cylinder.shape.radius=0.02",
       "bodies[3].shape.radius: 0.02 m is less than the kernel support 2h = 0.024 m"},
      {"bodies.cylinder.lattice_origin=[0.0,0.0]", "bodies[3].lattice_origin: not with lattice = \"rings\""},
      {"bodies.fluid.lattice=\"rings\"", "bodies[0].lattice: \"rings\" is for walls (kind = \"fluid\")"},
  };
  for (const auto& [set, message] : cases) {
    const auto r = regression::isph(check + " --set '" + set + "'");
    EXPECT_NE(r.status, 0) << set;
    EXPECT_NE(r.output.find(message), std::string::npos) << set << "\n" << r.output;
    EXPECT_NE(r.output.find("1 problem(s) found"), std::string::npos) << set << "\n" << r.output;
  }
}

// Started from rest with the inflow ramped up over 1 s, the outlet lets out what the inlet lets in: its
// buffer moves with the fluid beside it, so that it neither holds the flow back nor draws it out (a
// buffer that kept the velocity its particles crossed with, at rest at the start, blocked the channel).
TEST(OpenBoundaries, StartedFromRestTheOutletPassesWhatTheInletFeeds) {
  const std::string summary =
      channel_summary("channel_from_rest",
                      "--set open_boundaries.inlet.ramp_time=1.0 --set 'bodies.oil.initial_velocity={type=\"none\"}'");
  EXPECT_NEAR(json_number(summary, "mass_in"), 1000 * kMeanVelocity * kHeight * 1.5, 20 * kParticleMass) << summary;
  EXPECT_NEAR(json_number(summary, "fluid_mass_change"), 0, 3 * kParticleMass) << summary;
}

// The flow around the cylinder of cases/dfg_cylinder.toml keeps its mass, with or without the density term
// (fluid.density_relaxation): by 1.2 s, as the ramp ends, 1.6 % of the inflow is lost without it and 1.7 % gained
// with it (measured 2026-12-08 with the shipped constraint weight 0.6; at 1, 2.3 % lost and 1.7 % gained; on the
// staircase 2.6 % and 2.3 % lost; by 4 s 0.3 % is lost with it). Before the kinematic wall condition was switched off
// in confined flows, the velocity it took from the particles at the cylinder's front spread them at its shoulders:
// without the term 10.5 % was lost by 1.2 s and the run diverged at 1.28 s (docs/VALIDATION.md section 35).
TEST(OpenBoundaries, ConfinedChannelKeepsItsMassAroundACylinder) {
  const std::string run = "run " + kCases + "dfg_cylinder.toml --quiet --set end_time=1.2 --set output.snapshots=false";
  double loss[2];
  for (const int relaxed : {0, 1}) {
    const fs::path out = fresh_dir(relaxed ? "cylinder_relaxed" : "cylinder_divergence_free");
    const auto r =
        regression::isph(run + " --out " + out.string() + (relaxed ? "" : " --set fluid.density_relaxation=0"));
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string summary = read_file(out / "summary.json");
    loss[relaxed] = -json_number(summary, "fluid_mass_change") / json_number(summary, "mass_in");
  }
  for (const double l : loss) EXPECT_LT(std::abs(l), 0.04);
  EXPECT_NEAR(loss[0], 0.0157, 0.004);
  EXPECT_NEAR(loss[1], -0.0175, 0.004);
}

// cases/dfg_cylinder.toml, the DFG benchmark 2D-1 of Schäfer & Turek (1996), to 4 s at D/dx = 7.3 and 10: the
// drag on the cylinder (pressure and viscous traction), its time mean over 2-4 s, lies above the benchmark's
// c_D = 5.5795 (11.159 N/m at rho = 1000) and falls towards it as dx falls: +11.1 % and +6.8 % (measured
// 2026-12-08 with the constraint weight 0.6: 12.401 and 11.917 N/m; at 1, 12.601 and 12.081; on the lattice's
// staircase 12.611 and 12.179; docs/VALIDATION.md section 35). The pressure gives 69 and 66 % of it.
TEST(OpenBoundaries, CylinderInAChannelConvergesToTheBenchmarksDrag) {
  const std::string coarse =
      " --set dx=0.013666666666666667 --set 'bodies.fluid.shape.min=[-0.054667,0.0]'"
      " --set 'bodies.fluid.shape.max=[2.254667,0.41]'"
      " --set 'bodies.floor.shape.min=[-0.1,-0.041]' --set 'bodies.floor.lattice_origin=[-0.1,-0.041]'"
      " --set 'bodies.ceiling.shape.max=[2.3,0.451]'";
  constexpr double kBenchmark = 11.159;
  double error[2];
  for (const int fine : {0, 1}) {
    const fs::path out = fresh_dir(fine ? "dfg_cylinder" : "dfg_cylinder_coarse");
    const auto r =
        regression::isph("run " + kCases + "dfg_cylinder.toml --quiet --set end_time=4 --set output.snapshots=false" +
                         (fine ? std::string() : coarse) + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const auto probes = read_csv(out / "probes.csv");
    const double drag = mean_over(probes.at("time"), probes.at("cylinder.fx"), 2.0);
    const double pressure_drag = mean_over(probes.at("time"), probes.at("cylinder_pressure.fx"), 2.0);
    error[fine] = drag / kBenchmark - 1;
    EXPECT_NEAR(drag, fine ? 11.917 : 12.401, 0.25);
    EXPECT_NEAR(pressure_drag / drag, fine ? 0.661 : 0.687, 0.02);
    const std::string summary = read_file(out / "summary.json");
    EXPECT_LT(-json_number(summary, "fluid_mass_change") / json_number(summary, "mass_in"), 0.02) << summary;
  }
  EXPECT_GT(error[1], 0);
  EXPECT_LT(error[1], error[0] - 0.02);
}

// Water at rest around a clamped structure bar finer than the water (a lattice of its own) stays at rest
// with the density term on: rows beside a structure take no density correction. With it everywhere, the
// bar's neighbours' kernel sums, off the water's lattice value, drove 10 kPa and 0.013 m/s in one step.
TEST(OpenBoundaries, DensityTermLeavesWaterAtRestBesideAStructure) {
  const fs::path out = fresh_dir("density_term_at_rest"), file = out / "bar_at_rest.toml";
  fs::create_directories(out);
  std::ofstream(file) << R"(name = "bar_at_rest"
dx = 0.01
end_time = 0.02
[stages]
structure = true
fluid = true
[fluid]
free_surface = false
reference_velocity = 1.0
density_relaxation = 0.05
[output]
snapshots = false
[[materials]]
name = "water"
model = "newtonian"
density = 1000.0
viscosity = 1.0e-3
[[materials]]
name = "bar"
density = 1000.0
youngs_modulus = 1.4e6
poisson_ratio = 0.4
[[bodies]]
name = "water"
kind = "fluid"
material = "water"
shape = { type = "rectangle", min = [0.0, 0.0], max = [0.4, 0.2] }
holes = [{ type = "rectangle", min = [0.1, 0.09], max = [0.3, 0.11] }]
[[bodies]]
name = "bar"
kind = "structure"
material = "bar"
refinement = 2
shape = { type = "rectangle", min = [0.1, 0.09], max = [0.3, 0.11] }
clamps = [{ type = "rectangle", min = [0.1, 0.09], max = [0.3, 0.11] }]
[[bodies]]
name = "tank"
kind = "wall"
shape = { type = "rectangle", min = [-0.03, -0.03], max = [0.43, 0.0] }
[[bodies]]
name = "lid"
kind = "wall"
shape = { type = "rectangle", min = [-0.03, 0.2], max = [0.43, 0.23] }
[[bodies]]
name = "left"
kind = "wall"
shape = { type = "rectangle", min = [-0.03, 0.0], max = [0.0, 0.2] }
[[bodies]]
name = "right"
kind = "wall"
shape = { type = "rectangle", min = [0.4, 0.0], max = [0.43, 0.2] }
[[probes]]
name = "fastest"
type = "max_speed"
)";
  const auto r = regression::isph("run " + file.string() + " --quiet --out " + (out / "run").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto probes = read_csv(out / "run" / "probes.csv");
  EXPECT_LT(*std::max_element(probes.at("fastest.u").begin(), probes.at("fastest.u").end()), 1e-6);
}

// An inlet given a flow rate scales its profile's shape to carry it: a uniform shape ("1") at 0.02 m^2/s
// for 0.5 s prescribes 10 kg per metre of depth, and lets in as much within a particle per lattice row.
TEST(OpenBoundaries, FlowRateScalesTheProfile) {
  const std::string summary = channel_summary("channel_flow_rate",
                                              "--set end_time=0.5 --set 'open_boundaries.inlet.velocity=\"1\"' "
                                              "--set open_boundaries.inlet.flow_rate=0.02");
  EXPECT_NEAR(json_number(summary, "mass_prescribed"), 10.0, 1e-9) << summary;
  EXPECT_NEAR(json_number(summary, "mass_in"), 10.0, 20 * kParticleMass) << summary;
}
