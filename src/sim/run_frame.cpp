#include "sim/run_frame.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/device_emulation.hpp"

namespace isph {

double seconds_since(RunClock::time_point t0) { return std::chrono::duration<double>(RunClock::now() - t0).count(); }

namespace {

std::string format_duration(double s) {
  char buf[64];
  if (s < 90)
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 5400)
    std::snprintf(buf, sizeof buf, "%.1fmin", s / 60);
  else
    std::snprintf(buf, sizeof buf, "%.1fh", s / 3600);
  return buf;
}

}  // namespace

RunFrame::RunFrame(const CaseSpec& spec, const RunOptions& opt, std::vector<std::string> probe_columns, int dimension)
    : spec_(spec), opt_(opt), wall0_(RunClock::now()), last_progress_(wall0_), last_flush_(wall0_) {
  result.out_dir = opt.out_dir.empty() ? "out/" + spec.name : opt.out_dir;
  std::filesystem::create_directories(result.out_dir);
  write_file_atomically(result.out_dir + "/case.resolved.toml", spec.resolved_toml);
  probe_columns.insert(probe_columns.begin(), "time");
  probes = CsvTable(result.out_dir + "/probes.csv", probe_columns);
  energy =
      CsvTable(result.out_dir + "/energy.csv", {"time", "fluid_kinetic", "fluid_potential", "structure_kinetic",
                                                "structure_potential", "structure_strain", "boundary_work", "total"});
  snapshots = SnapshotWriter(result.out_dir, dimension);
  write_snapshots_ = spec.output.snapshots && SnapshotWriter::available();
  snap_interval_ = spec.output.snapshot_interval;
  next_snap_ = snap_interval_ > 0 ? snap_interval_ : spec.end_time * 2;
  result.status = "completed";
  result.message = "reached end_time";
}

void RunFrame::set_output_interval(double dt, int steps) {
  out_interval_ = spec_.output.interval > 0 ? spec_.output.interval : steps * dt;
  next_out_ = out_interval_;
}

void RunFrame::start_at(double t, const std::string& snapshot, bool complete) {
  start_time_ = t;
  restarted_ = true;
  restart_.set("snapshot", snapshot).set("time", t).set("structure_state_complete", complete);
  while (next_out_ <= t + 1e-12 * spec_.end_time) next_out_ += out_interval_;
  while (next_snap_ <= t + 1e-12 * spec_.end_time) next_snap_ += snap_interval_;
  const std::filesystem::path earlier = std::filesystem::absolute(snapshot).parent_path().parent_path();
  if (std::filesystem::equivalent(earlier, result.out_dir))
    throw std::runtime_error("restart: write the continued run to another folder than " + earlier.string() +
                             " (--out), whose snapshots it would overwrite");
  for (auto [table, name] : {std::pair{&probes, "probes.csv"}, std::pair{&energy, "energy.csv"}})
    if (std::filesystem::exists(earlier / name))
      table->add_rows_before((earlier / name).string(), t + CsvTable::kRelativeResolution * spec_.end_time);
}

bool RunFrame::due_record(double t, bool last) {
  if (!(t >= next_out_ - 1e-12 * spec_.end_time) && !last) return false;
  while (next_out_ <= t + 1e-12 * spec_.end_time) next_out_ += out_interval_;
  return true;
}

bool RunFrame::due_snapshot(double t) {
  if (!write_snapshots_ || !(t >= next_snap_ - 1e-12 * spec_.end_time)) return false;
  while (next_snap_ <= t + 1e-12 * spec_.end_time) next_snap_ += snap_interval_;
  return true;
}

bool RunFrame::final_snapshot_due() const {
  return write_snapshots_ && !(snap_interval_ > 0 && std::fabs(std::fmod(spec_.end_time, snap_interval_)) < 1e-12);
}

void RunFrame::flush() {
  probes.flush();
  energy.flush();
  last_flush_ = RunClock::now();
}

void RunFrame::add_energy_row(double t, double fluid_kinetic, double fluid_potential, double structure_kinetic,
                              double structure_potential, double structure_strain, double boundary_work,
                              double releasable_potential) {
  const double total =
      fluid_kinetic + fluid_potential + structure_kinetic + structure_potential + structure_strain - boundary_work;
  energy.add_row({t, fluid_kinetic, fluid_potential, structure_kinetic, structure_potential, structure_strain,
                  boundary_work, total});
  if (seconds_since(last_flush_) >= kFlushSeconds) flush();
  if (!books_open_) {
    books_ = EnergyBooks(total, releasable_potential + fluid_kinetic + structure_kinetic + structure_strain);
    books_open_ = true;
  }
  if (result.status == "diverged") return;
  if (auto broken = books_.post(t, total, boundary_work)) diverge(*broken + "; " + books_advice_);
}

SnapshotAttributes RunFrame::books_attributes() const {
  if (!books_open_) return {};
  return {{"energy_books_initial_total", books_.initial_total()},
          {"energy_books_initial_energy", books_.initial_energy()},
          {"energy_books_largest_work", books_.largest_work()},
          {"energy_books_peak_created_fraction", books_.peak_created_fraction()}};
}

void RunFrame::continue_books(const SnapshotData& state) {
  const auto& a = state.attributes;
  const auto total = a.find("energy_books_initial_total"), energy0 = a.find("energy_books_initial_energy"),
             work = a.find("energy_books_largest_work");
  if (total == a.end() || energy0 == a.end() || work == a.end()) return;
  const auto peak = a.find("energy_books_peak_created_fraction");  // absent in snapshots before 2026-12-06
  books_ = EnergyBooks::continued(total->second, energy0->second, work->second, peak == a.end() ? 0 : peak->second);
  books_open_ = true;
}

void RunFrame::progress(double t, long long steps, double stepping_seconds) {
  if (!opt_.progress || seconds_since(last_progress_) < 2.0) return;
  last_progress_ = RunClock::now();
  const double elapsed = seconds_since(wall0_);
  const double done = (t - start_time_) / (spec_.end_time - start_time_);
  std::fprintf(stderr, "[%s] t = %.4g / %.4g s (%.0f%%)  %.3g steps/s  ETA %s\n", spec_.name.c_str(), t, spec_.end_time,
               100.0 * t / spec_.end_time, steps / std::max(1e-9, stepping_seconds),
               format_duration(elapsed / done - elapsed).c_str());
}

void RunFrame::diverge(const std::string& message) {
  result.status = "diverged";
  result.message = message;
}

void RunFrame::interrupt(double t, long long step) {
  const int signal = stop_signal();
  stop_signal_name_ = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "signal " + std::to_string(signal);
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s received: stopped at the end of step %lld, t = %.6g s", stop_signal_name_.c_str(),
                step, t);
  result.status = "interrupted";
  result.message = buf;
}

bool RunFrame::last_snapshot_due() const {
  return write_snapshots_ || (result.status == "interrupted" && SnapshotWriter::available());
}

void RunFrame::finish(int dimension, const JsonObject& particles, long long fluid_steps, long long structure_steps,
                      double simulated_time, const PhaseTimer& timer, const JsonObject& ppe,
                      const JsonObject& performance) {
  flush();
  const double wall = seconds_since(wall0_);
  JsonObject steps, phases;
  steps.set("fluid", fluid_steps).set("structure", structure_steps);
  for (const auto& [k, v] : timer.phases()) phases.set(k, v);
  JsonObject summary;
  summary.set("case", spec_.name)
      .set("dimension", dimension)
      .set("device", device_name(opt_.device))
      .set("particles", particles)
      .set("steps", steps)
      .set("simulated_time", simulated_time)
      .set("wall_time_s", wall)
      .set("phases", phases)
      .set("ppe", ppe)
      .set("performance", performance)
      .set("status", result.status)
      .set("message", result.message);
  if (books_open_) {
    JsonObject books;
    books.set("created_fraction_bound", EnergyBooks::kCreationBound)
        .set("peak_created_fraction", books_.peak_created_fraction())
        .set("scale", books_.scale());
    summary.set("energy_books", books);
  }
  if (restarted_) summary.set("restart", restart_);
  if (!stop_signal_name_.empty()) summary.set("stop_signal", stop_signal_name_);
  if (device_emulated()) {  // --device debug: the host's touches of device memory, per phase
    JsonObject touches, debug;
    for (const auto& [k, v] : timer.host_touches()) touches.set(k, v);
    debug.set("launches", emulated_launches())
        .set("host_page_touches", touches)
        .set("host_page_touches_total", emulated_host_touches());
    summary.set("debug_device", debug);
  }
  write_file_atomically(result.out_dir + "/summary.json", summary.dump() + "\n");
  if (opt_.progress)
    std::fprintf(stderr, "[%s] %s: %s; %lld steps in %.2f s wall; output in %s\n", spec_.name.c_str(),
                 result.status.c_str(), result.message.c_str(), std::max(fluid_steps, structure_steps), wall,
                 result.out_dir.c_str());
}

JsonObject particle_counts(long long fluid, long long wall, long long structure) {
  JsonObject o;
  o.set("fluid", fluid).set("wall", wall).set("structure", structure);
  return o;
}

}  // namespace isph
