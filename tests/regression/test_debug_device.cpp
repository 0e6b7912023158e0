// The debug device (`--device debug`, core/device_emulation.hpp): the cuda device's code path run on the
// CPU. Its runs give the host's results to the bit (the same functors in the same order, on memory that
// starts as NaN), and it counts the pages of device memory the host touches between launches, which on
// a GPU are pages of managed memory moved to the host and back. These run in CI, where no GPU is.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "run_support.hpp"

namespace {

void expect_debug_device_gives_the_hosts_bits(const std::string& name, const std::string& case_file,
                                              const std::string& sets) {
  const fs::path host = run_on_device("cpu", name, case_file, sets);
  const fs::path debug = run_on_device("debug", name, case_file, sets);
  if (::testing::Test::HasFailure()) return;
  for (const char* file : {"probes.csv", "energy.csv"}) {
    const std::string expected = read_file(host / file);
    EXPECT_GT(expected.size(), 100u) << file;
    EXPECT_EQ(read_file(debug / file), expected) << name << ": " << file;
  }
  EXPECT_NE(read_file(debug / "summary.json").find("\"device\": \"debug\""), std::string::npos);
}

}  // namespace

TEST(DebugDevice, CoupledGateGivesTheHostsBits) {
  expect_debug_device_gives_the_hosts_bits("debug_gate", "elastic_gate.toml",
                                           " --set end_time=0.003 --set output.interval=0.0005");
}

TEST(DebugDevice, DamBreakGivesTheHostsBits) {
  expect_debug_device_gives_the_hosts_bits("debug_dam_break", "dam_break.toml", " --set end_time=0.02");
}

TEST(DebugDevice, WeaklyCompressibleGateGivesTheHostsBits) {
  expect_debug_device_gives_the_hosts_bits(
      "debug_gate_wcsph", "elastic_gate.toml",
      " --set end_time=0.002 --set output.interval=0.0005 --set fluid.model=\"wcsph\"");
}

// Moving walls, a moving clamp and the clamp's work: three fluid steps and 257 substeps.
TEST(DebugDevice, RollingTankGivesTheHostsBits) {
  expect_debug_device_gives_the_hosts_bits("debug_rolling_tank", "sloshing_baffle.toml",
                                           " --set dx=0.002 --set end_time=0.001 --set output.interval=0.0005");
}

// A structure alone, stepped by the recorded graph of the RK4 step.
TEST(DebugDevice, OscillatingPlateGivesTheHostsBits) {
  expect_debug_device_gives_the_hosts_bits("debug_plate", "oscillating_plate.toml", " --set end_time=0.01");
}

// Between launches the host reads only what must come back, one page each: per PPE assembly the sizes
// of the full and the compacted matrix; per BiCGSTAB iteration its six dot products (poisson/krylov.hpp);
// per solve the norm of b, the initial residual's norm and the true residual before and after (two sums
// each). No other stepping phase touches device memory, at either of two resolutions (3,200 and 6,786
// fluid particles), so what is touched does not grow with the particles. The PPE is solved by the cuda
// backend (on this device, the project's BiCGSTAB and AMG on device arrays).
TEST(DebugDevice, HostTouchesOnlyWhatMustComeBack) {
  for (const char* dx : {"0.00365", "0.0025"}) {
    const fs::path out = run_on_device("debug", std::string("debug_touches_") + dx, "dam_break.toml",
                                       std::string(" --set dx=") + dx +
                                           " --set end_time=0.006 --set output.interval=1"
                                           " --set fluid.ppe.backend=\"cuda\" --set fluid.ppe.preconditioner=\"amg\"");
    if (HasFailure()) return;
    const std::string s = read_file(out / "summary.json");
    const double steps = json_number(s.substr(s.find("\"steps\"")), "fluid"), solves = json_number(s, "solves");
    const double iterations = solves * json_number(s, "mean_iterations");
    const std::string touches = s.substr(s.find("\"host_page_touches\""));
    ASSERT_GT(steps, 10) << s;
    for (const char* phase : {"neighbours", "predictor", "free_surface", "projection", "shifting", "contact"})
      EXPECT_EQ(json_number(touches, phase), 0) << "dx = " << dx << ", " << phase;
    EXPECT_LE(json_number(touches, "ppe_assembly"), 2 * steps) << "dx = " << dx;
    EXPECT_LE(json_number(touches, "ppe_solve"), 6 * iterations + 6 * solves) << "dx = " << dx;
    EXPECT_GT(json_number(touches, "ppe_solve"), 0) << "dx = " << dx;  // the count works
  }
}
