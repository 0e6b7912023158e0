#pragma once
// The time loop of a run: builds the scene, assembles the stages the case needs, advances to
// end_time and writes every output file of the contract (docs/CASES.md, DESIGN.md).
#include <string>

#include "core/parallel.hpp"
#include "io/case.hpp"

namespace isph {

struct RunOptions {
  std::string out_dir;  // default: out/<case name>
  Device device = Device::cpu;
  int threads = 0;       // 0: OpenMP default
  bool progress = true;  // progress line on stderr
  // A snapshot of an earlier run of the same case to continue from, or that run's folder (its newest
  // snapshot that reads back whole: newest_snapshot() in io/output.hpp); the run starts at the snapshot's time and
  // writes to out_dir, which must not be the earlier run's folder.
  std::string restart;
};

struct RunResult {
  std::string status;  // completed | diverged | interrupted
  std::string message;
  std::string out_dir;
};

RunResult run_case(const CaseSpec& spec, const RunOptions& options);

// Stopping a run from outside (README, "Stopping and continuing a run"). After install_stop_handlers()
// the first SIGINT or SIGTERM asks the time loop to stop at the end of its current step: it writes its
// output, a last snapshot and summary.json with status "interrupted"; a second signal ends the process
// at once (exit status 128 + the signal), which leaves every file whole (they are written through
// temporary names). stop_signal() is the signal that asked, or 0.
void install_stop_handlers();
int stop_signal();

}  // namespace isph
