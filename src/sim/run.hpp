#pragma once
// The time loop of a run: builds the scene, assembles the stages the case needs, advances to
// end_time and writes every output file of the contract (docs/CASES.md, DESIGN.md).
#include <string>

#include "core/parallel.hpp"
#include "io/case.hpp"

namespace isph {

struct RunOptions {
  std::string out_dir;   // default: out/<case name>
  Device device = Device::cpu;
  int threads = 0;       // 0: OpenMP default
  bool progress = true;  // progress line on stderr
  // A snapshot of an earlier run of the same case (ISPH fluid, alone or coupled) to continue from;
  // the run starts at its time and writes to out_dir, which must not be the earlier run's folder.
  std::string restart;
};

struct RunResult {
  std::string status;    // completed | diverged
  std::string message;
  std::string out_dir;
};

RunResult run_case(const CaseSpec& spec, const RunOptions& options);

}  // namespace isph
