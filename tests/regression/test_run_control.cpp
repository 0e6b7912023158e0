// Stopping runs from outside and continuing them (README, "Stopping and continuing a run"): real
// processes of the isph command, real signals.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "io/output.hpp"
#include "run_support.hpp"
#include "sim/run.hpp"
#include "snapshot_compare.hpp"

namespace {

// The isph command started in the background (one thread, its stderr to `log`); signal() and wait() it.
class Process {
 public:
  Process(const std::string& args, const fs::path& log) {
    const std::string cmd = "exec " + kIsph + " " + args + " --threads 1 2> " + log.string();
    pid_ = fork();
    if (pid_ == 0) {
      execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  void signal(int s) const { ::kill(pid_, s); }
  // The exit status, or 128 + the signal that ended it (as a shell reports it).
  int wait() {
    int status = 0;
    waitpid(pid_, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  pid_t pid_ = -1;
};

// Waits (up to a minute) until `done` holds; false if it never does.
template <class Condition>
bool wait_until(Condition done) {
  for (int k = 0; k < 60000; ++k) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}
bool wait_for(const fs::path& file) {
  return wait_until([&] { return fs::exists(file); });
}

// The oscillating plate (T/dx = 10, velocity-Verlet, 1,030 particles) to 0.1 s, a snapshot every 0.01 s.
const std::string kPlate = "run " + kCases +
                           "oscillating_plate.toml --quiet --set end_time=0.1"
                           " --set structure.integrator=\"verlet\" --set structure.courant=0.8"
                           " --set output.snapshot_interval=0.01";

}  // namespace

// SIGTERM stops the run at the end of a step with a last snapshot, status "interrupted" and exit status
// 4; `--restart DIR` continues from it, and the continued run ends with the uninterrupted run's bits
// (the same steps of dt from the same positions, velocities and velocity-Verlet acceleration).
TEST(RunControl, SigtermStopsAStructureRunThatThenContinuesBitForBit) {
  if (!isph::SnapshotWriter::available()) GTEST_SKIP() << "this build writes no snapshots (no HDF5)";
  const fs::path full = fresh_dir("stop_plate_full"), stopped = fresh_dir("stop_plate_stopped"),
                 continued = fresh_dir("stop_plate_continued");
  ASSERT_EQ(regression::isph(kPlate + " --out " + full.string()).status, 0);

  Process run(kPlate + " --out " + stopped.string(), stopped.string() + ".log");
  ASSERT_TRUE(wait_for(stopped / "snapshots" / "snapshot_00002.h5"));
  run.signal(SIGTERM);
  ASSERT_EQ(run.wait(), 4);
  const std::string summary = read_file(stopped / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"interrupted\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"stop_signal\": \"SIGTERM\""), std::string::npos) << summary;
  const double stopped_at = json_number(summary, "simulated_time");
  EXPECT_LT(stopped_at, 0.1) << summary;
  const std::string last = isph::newest_snapshot(stopped.string());
  EXPECT_NEAR(isph::read_snapshot(last).time, stopped_at, 1e-12);  // the step it stopped after, not a scheduled one

  const auto c = regression::isph(kPlate + " --out " + continued.string() + " --restart " + stopped.string());
  ASSERT_EQ(c.status, 0) << c.output;
  expect_same_bits(isph::newest_snapshot(full.string()), isph::newest_snapshot(continued.string()));
  EXPECT_EQ(read_file(full / "probes.csv"), read_file(continued / "probes.csv"));
  EXPECT_EQ(read_file(full / "energy.csv"), read_file(continued / "energy.csv"));
}

// The weakly compressible dam break (a/dx = 20) continued from its snapshot at 0.045 s ends with the
// uninterrupted run's bits at 0.1 s: the snapshot holds the particles' order in memory, the neighbour
// searches' count, the density, the Verlet step's pressure acceleration and the force on the walls. It
// falls inside an output interval, whose force sum it carries: the force probe on the emptying left wall
// writes the same rows.
TEST(RunControl, WeaklyCompressibleRunContinuesBitForBit) {
  if (!isph::SnapshotWriter::available()) GTEST_SKIP() << "this build writes no snapshots (no HDF5)";
  const std::string dam = "run " + kCases +
                          "dam_break.toml --quiet --set fluid.model=\"wcsph\" --set dx=0.0073"
                          " --set end_time=0.1 --set output.snapshot_interval=0.045"
                          " --set 'probes=[{name=\"left\",type=\"force\",body=\"left_wall\"}]'"
                          " --set 'bodies.floor.shape={type=\"rectangle\",min=[-0.0219,-0.0219],max=[0.6059,0.0]}'"
                          " --set 'bodies.left_wall.shape={type=\"rectangle\",min=[-0.0219,0.0],max=[0.0,0.584]}'"
                          " --set 'bodies.right_wall.shape={type=\"rectangle\",min=[0.584,0.0],max=[0.6059,0.584]}'";
  const fs::path full = fresh_dir("restart_wcsph_full"), continued = fresh_dir("restart_wcsph_continued");
  const auto r = regression::isph(dam + " --out " + full.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto c = regression::isph(dam + " --out " + continued.string() + " --restart " +
                                  (full / "snapshots" / "snapshot_00001.h5").string());
  ASSERT_EQ(c.status, 0) << c.output;
  expect_same_bits(isph::newest_snapshot(full.string()), isph::newest_snapshot(continued.string()));
  EXPECT_EQ(isph::read_snapshot(isph::newest_snapshot(continued.string())).time, 0.1);
  EXPECT_EQ(read_file(full / "probes.csv"), read_file(continued / "probes.csv"));
  EXPECT_LT(read_csv(full / "probes.csv").at("left.fx").back(), -1.0);  // the water still pushes on it
  // The energy books carry on, the largest fraction created before the snapshot included.
  EXPECT_EQ(json_number(read_file(full / "summary.json"), "peak_created_fraction"),
            json_number(read_file(continued / "summary.json"), "peak_created_fraction"));
}

namespace {

// What a run ended abruptly leaves in `out`: every snapshot under its final name reads back whole (at
// least `at_least` of them), so do the XDMF index and probes.csv, and `--restart DIR` continues from the
// newest snapshot (`args`: the run's arguments, its snapshots at the case's interval).
void expect_whole_files_and_restart(const std::string& args, const fs::path& out, int at_least) {
  int snapshots = 0;
  for (const auto& entry : fs::directory_iterator(out / "snapshots")) {
    if (entry.path().extension() != ".h5") continue;
    EXPECT_NO_THROW(isph::read_snapshot(entry.path().string())) << entry.path();
    ++snapshots;
  }
  EXPECT_GE(snapshots, at_least);
  const std::string index = read_file(out / "snapshots" / "snapshots.xmf");
  EXPECT_NE(index.find("</Xdmf>"), std::string::npos);
  EXPECT_GE(read_csv(out / "probes.csv").at("time").size(), 1u);
  const auto c = regression::isph(args + " --out " + (out.string() + "_continued") + " --restart " + out.string());
  EXPECT_EQ(c.status, 0) << c.output;
}

}  // namespace

// A second SIGINT ends the run at once (exit status 128 + 2), in the middle of its step, leaving no file
// half-written. The coupled hydrostatic plate (about 0.1 s per fluid step on one thread, a snapshot after
// every step): the second signal goes once the first one's note is on stderr.
TEST(RunControl, SecondSigintStopsAtOnceLeavingEveryFileWhole) {
  if (!isph::SnapshotWriter::available()) GTEST_SKIP() << "this build writes no snapshots (no HDF5)";
  const fs::path out = fresh_dir("stop_twice"), log = out.string() + ".log";
  const std::string plate = "run " + kCases + "hydrostatic_plate.toml --quiet --set end_time=0.015";
  Process run(plate + " --set output.snapshot_interval=1e-6 --out " + out.string(), log);
  ASSERT_TRUE(wait_for(out / "snapshots" / "snapshot_00003.h5"));
  run.signal(SIGINT);
  ASSERT_TRUE(wait_until([&] { return read_file(log).find("stopping at the end of this step") != std::string::npos; }));
  run.signal(SIGINT);
  EXPECT_EQ(run.wait(), 128 + SIGINT);
  EXPECT_FALSE(fs::exists(out / "summary.json"));  // it never reached the end of the step
  expect_whole_files_and_restart(plate, out, 3);
}

// kill -9 while the run writes a snapshot at every step (the oscillating plate: 0.2 ms per step, about
// as long as a snapshot's write): the earlier snapshots and the XDMF index stay readable.
TEST(RunControl, KillDuringSnapshotWritesLeavesEarlierSnapshotsReadable) {
  if (!isph::SnapshotWriter::available()) GTEST_SKIP() << "this build writes no snapshots (no HDF5)";
  const fs::path out = fresh_dir("kill_9");
  Process run(kPlate + " --set output.snapshot_interval=1e-6 --out " + out.string(), out.string() + ".log");
  ASSERT_TRUE(wait_for(out / "snapshots" / "snapshot_00020.h5"));
  run.signal(SIGKILL);
  EXPECT_EQ(run.wait(), 128 + SIGKILL);
  expect_whole_files_and_restart(kPlate, out, 20);
}
