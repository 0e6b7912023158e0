#pragma once
// What every run shares, whichever stages it has: the output files of the contract (probes.csv,
// energy.csv, snapshots, summary.json, case.resolved.toml), their schedule, the energy books, the
// progress line and the run's status. A time loop calls record/snapshot through due_*() and finish()
// once at the end (sim/run_fluid.cpp, sim/run_structure.cpp).
#include <chrono>
#include <string>
#include <vector>

#include "io/case.hpp"
#include "io/output.hpp"
#include "sim/energy_books.hpp"
#include "sim/phase_timer.hpp"
#include "sim/run.hpp"

namespace isph {

using RunClock = std::chrono::steady_clock;

double seconds_since(RunClock::time_point t0);

class RunFrame {
 public:
  RunFrame(const CaseSpec& spec, const RunOptions& opt, std::vector<std::string> probe_columns, int dimension);

  // Output interval: the case's, else every `steps` steps of dt.
  void set_output_interval(double dt, int steps);
  // A restarted run: the schedules continue after t, and the probe and energy rows up to t come from
  // the earlier run's folder (the snapshot's folder's parent) when it has them: the rows the
  // uninterrupted run wrote there.
  void start_at(double t, const std::string& snapshot, bool complete);
  bool due_record(double t, bool last);
  bool due_snapshot(double t);
  bool writes_snapshots() const { return write_snapshots_; }
  // The final snapshot, unless the schedule has just written one at end_time.
  bool final_snapshot_due() const;
  void flush();

  // Writes a row of energy.csv and posts it to the energy books, which open on the first row (a run's
  // start, with `releasable_potential`, the potential energy motion can release). A run whose books no
  // longer balance has diverged. Every kFlushSeconds of wall time probes.csv and energy.csv are written
  // out, so that a long run without snapshots shows its progress on disk.
  static constexpr double kFlushSeconds = 30;
  void add_energy_row(double t, double fluid_kinetic, double fluid_potential, double structure_kinetic,
                      double structure_potential, double structure_strain, double boundary_work,
                      double releasable_potential);
  // What the books' message suggests to a run they stop (the model's step settings).
  void set_books_advice(std::string advice) { books_advice_ = std::move(advice); }
  // The books' state, kept in each snapshot so that a restarted run continues them.
  SnapshotAttributes books_attributes() const;
  // A restart continues the books from the snapshot; one written before they existed opens them anew
  // at the first row after the restart.
  void continue_books(const SnapshotData& state);

  void progress(double t, long long steps, double stepping_seconds);

  bool running() const { return result.status == "completed"; }
  void diverge(const std::string& message);
  // A stop signal arrived (stop_signal()): the run ends after the step that reached t.
  void interrupt(double t, long long step);
  // The last snapshot of a run that ends early: after a divergence where the case writes snapshots,
  // after a stop wherever HDF5 is built in (the run is to be continued from it).
  bool last_snapshot_due() const;

  // Writes summary.json and the closing line.
  void finish(int dimension, const JsonObject& particles, long long fluid_steps, long long structure_steps,
              double simulated_time, const PhaseTimer& timer, const JsonObject& ppe, const JsonObject& performance);

  RunResult result;
  CsvTable probes, energy;
  SnapshotWriter snapshots;

 private:
  const CaseSpec& spec_;
  const RunOptions& opt_;
  RunClock::time_point wall0_, last_progress_, last_flush_;
  bool write_snapshots_ = false;
  double out_interval_ = 0, next_out_ = 0, snap_interval_ = 0, next_snap_ = 0;
  double start_time_ = 0;
  bool restarted_ = false;
  JsonObject restart_;            // the snapshot a restarted run continues from
  std::string stop_signal_name_;  // of an interrupted run
  EnergyBooks books_;
  bool books_open_ = false;
  std::string books_advice_ = "the run is unstable";
};

// The time loop's handling of one step's end, shared by both loops: a stop signal ends a running run
// after the step that reached t (not at end_time); a run that has stopped records its last state (a
// diverged one always, an interrupted one where the schedule falls) and its last snapshot. Else a
// record and a snapshot as scheduled, after which the energy books may have stopped it. Returns
// whether the loop goes on.
template <class Record, class Snapshot>
bool end_of_step(RunFrame& frame, double t, long long step, bool last, Record&& record, Snapshot&& snapshot) {
  if (frame.running() && stop_signal() != 0 && !last) frame.interrupt(t, step);
  if (!frame.running()) {
    if (frame.result.status == "diverged" || frame.due_record(t, false)) record(t);
    if (frame.last_snapshot_due()) snapshot(t);
    return false;
  }
  if (frame.due_record(t, last)) record(t);
  if (!frame.running()) {  // the energy books broke
    if (frame.last_snapshot_due()) snapshot(t);
    return false;
  }
  if (frame.due_snapshot(t)) snapshot(t);
  return true;
}

JsonObject particle_counts(long long fluid, long long wall, long long structure);

}  // namespace isph
