#include "sim/run.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "io/output.hpp"
#include "sim/coupling.hpp"
#include "sim/energy_books.hpp"
#include "sim/phase_timer.hpp"
#include "sim/scene.hpp"

namespace isph {

namespace {

using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t g_stop_signal = 0;

// Async-signal-safe: sets the flag, or ends the process on the second signal.
extern "C" void on_stop_signal(int signal) {
  if (g_stop_signal != 0) _exit(128 + signal);
  g_stop_signal = signal;
  static const char note[] = "\nisph: stopping at the end of this step (a second signal stops at once)\n";
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, note, sizeof note - 1);
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

const char* const kComponents[3] = {"ux", "uy", "uz"};
const char* const kForceComponents[3] = {"fx", "fy", "fz"};

template <int D>
std::array<double, 3> to_array(const Vec<D>& v) {
  std::array<double, 3> a{0, 0, 0};
  for (int d = 0; d < D; ++d) a[d] = v[d];
  return a;
}

template <int D>
Vec<D> gravity_vector(const std::array<double, 3>& g) {
  Vec<D> v;
  for (int d = 0; d < D; ++d) v[d] = g[d];
  return v;
}

template <int D>
void put_vector(SnapshotField& field, Index k, const Vec<D>& v) {
  for (int d = 0; d < D; ++d) field.data[3 * k + d] = v[d];
}

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

// What every run shares: the output files, their schedule, the progress line and summary.json.
// A time loop calls record()/snapshot() through due_*() and finish() once at the end.
class RunFrame {
 public:
  RunFrame(const CaseSpec& spec, const RunOptions& opt, std::vector<std::string> probe_columns, int dimension)
      : spec_(spec), opt_(opt), wall0_(Clock::now()), last_progress_(wall0_) {
    result.out_dir = opt.out_dir.empty() ? "out/" + spec.name : opt.out_dir;
    std::filesystem::create_directories(result.out_dir);
    write_file_atomically(result.out_dir + "/case.resolved.toml", spec.resolved_toml);
    probe_columns.insert(probe_columns.begin(), "time");
    probes = CsvTable(result.out_dir + "/probes.csv", probe_columns);
    energy = CsvTable(result.out_dir + "/energy.csv",
                      {"time", "fluid_kinetic", "fluid_potential", "structure_kinetic", "structure_potential",
                       "structure_strain", "boundary_work", "total"});
    snapshots = SnapshotWriter(result.out_dir, dimension);
    write_snapshots_ = spec.output.snapshots && SnapshotWriter::available();
    snap_interval_ = spec.output.snapshot_interval;
    next_snap_ = snap_interval_ > 0 ? snap_interval_ : spec.end_time * 2;
    result.status = "completed";
    result.message = "reached end_time";
  }

  // Output interval: the case's, else every `steps` steps of dt.
  void set_output_interval(double dt, int steps) {
    out_interval_ = spec_.output.interval > 0 ? spec_.output.interval : steps * dt;
    next_out_ = out_interval_;
  }
  // A restarted run: the schedules continue after t, and the probe and energy rows up to t come from
  // the earlier run's folder (the snapshot's folder's parent) when it has them: the rows the
  // uninterrupted run wrote there.
  void start_at(double t, const std::string& snapshot, bool complete) {
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
  bool due_record(double t, bool last) {
    if (!(t >= next_out_ - 1e-12 * spec_.end_time) && !last) return false;
    while (next_out_ <= t + 1e-12 * spec_.end_time) next_out_ += out_interval_;
    return true;
  }
  bool due_snapshot(double t) {
    if (!write_snapshots_ || !(t >= next_snap_ - 1e-12 * spec_.end_time)) return false;
    while (next_snap_ <= t + 1e-12 * spec_.end_time) next_snap_ += snap_interval_;
    return true;
  }
  bool writes_snapshots() const { return write_snapshots_; }
  // The final snapshot, unless the schedule has just written one at end_time.
  bool final_snapshot_due() const {
    return write_snapshots_ && !(snap_interval_ > 0 && std::fabs(std::fmod(spec_.end_time, snap_interval_)) < 1e-12);
  }
  void flush() {
    probes.flush();
    energy.flush();
  }

  // Writes a row of energy.csv and posts it to the energy books, which open on the first row (a run's
  // start, with `releasable_potential`, the potential energy motion can release). A run whose books no
  // longer balance has diverged.
  void add_energy_row(double t, double fluid_kinetic, double fluid_potential, double structure_kinetic,
                      double structure_potential, double structure_strain, double boundary_work,
                      double releasable_potential) {
    const double total =
        fluid_kinetic + fluid_potential + structure_kinetic + structure_potential + structure_strain - boundary_work;
    energy.add_row({t, fluid_kinetic, fluid_potential, structure_kinetic, structure_potential, structure_strain,
                    boundary_work, total});
    if (!books_open_) {
      books_ = EnergyBooks(total, releasable_potential + fluid_kinetic + structure_kinetic + structure_strain);
      books_open_ = true;
    }
    if (result.status == "diverged") return;
    if (auto broken = books_.post(t, total, boundary_work)) diverge(*broken + "; " + books_advice_);
  }
  // What the books' message suggests to a run they stop (the model's step settings).
  void set_books_advice(std::string advice) { books_advice_ = std::move(advice); }
  // The books' state, kept in each snapshot so that a restarted run continues them.
  SnapshotAttributes books_attributes() const {
    if (!books_open_) return {};
    return {{"energy_books_initial_total", books_.initial_total()},
            {"energy_books_initial_energy", books_.initial_energy()},
            {"energy_books_largest_work", books_.largest_work()}};
  }
  // A restart continues the books from the snapshot; one written before they existed opens them anew
  // at the first row after the restart.
  void continue_books(const SnapshotData& state) {
    const auto& a = state.attributes;
    const auto total = a.find("energy_books_initial_total"), energy0 = a.find("energy_books_initial_energy"),
               work = a.find("energy_books_largest_work");
    if (total == a.end() || energy0 == a.end() || work == a.end()) return;
    books_ = EnergyBooks::continued(total->second, energy0->second, work->second);
    books_open_ = true;
  }

  void progress(double t, long long steps, double stepping_seconds) {
    if (!opt_.progress || seconds_since(last_progress_) < 2.0) return;
    last_progress_ = Clock::now();
    const double elapsed = seconds_since(wall0_);
    const double done = (t - start_time_) / (spec_.end_time - start_time_);
    std::fprintf(stderr, "[%s] t = %.4g / %.4g s (%.0f%%)  %.3g steps/s  ETA %s\n", spec_.name.c_str(), t,
                 spec_.end_time, 100.0 * t / spec_.end_time, steps / std::max(1e-9, stepping_seconds),
                 format_duration(elapsed / done - elapsed).c_str());
  }

  void diverge(const std::string& message) {
    result.status = "diverged";
    result.message = message;
  }
  // A stop signal arrived (stop_signal()): the run ends after the step that reached t.
  void interrupt(double t, long long step) {
    const int signal = stop_signal();
    stop_signal_name_ = signal == SIGINT    ? "SIGINT"
                        : signal == SIGTERM ? "SIGTERM"
                                            : "signal " + std::to_string(signal);
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s received: stopped at the end of step %lld, t = %.6g s",
                  stop_signal_name_.c_str(), step, t);
    result.status = "interrupted";
    result.message = buf;
  }
  // The last snapshot of a run that ends early: after a divergence where the case writes snapshots,
  // after a stop wherever HDF5 is built in (the run is to be continued from it).
  bool last_snapshot_due() const {
    return write_snapshots_ || (result.status == "interrupted" && SnapshotWriter::available());
  }

  // Writes summary.json and the closing line.
  void finish(int dimension, const JsonObject& particles, long long fluid_steps, long long structure_steps,
              double simulated_time, const PhaseTimer& timer, const JsonObject& ppe, const JsonObject& performance) {
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

  RunResult result;
  CsvTable probes, energy;
  SnapshotWriter snapshots;

 private:
  const CaseSpec& spec_;
  const RunOptions& opt_;
  Clock::time_point wall0_, last_progress_;
  bool write_snapshots_ = false;
  double out_interval_ = 0, next_out_ = 0, snap_interval_ = 0, next_snap_ = 0;
  double start_time_ = 0;
  bool restarted_ = false;
  JsonObject restart_;  // the snapshot a restarted run continues from
  std::string stop_signal_name_;  // of an interrupted run
  EnergyBooks books_;
  bool books_open_ = false;
  std::string books_advice_ = "the run is unstable";
};

JsonObject particle_counts(long long fluid, long long wall, long long structure) {
  JsonObject o;
  o.set("fluid", fluid).set("wall", wall).set("structure", structure);
  return o;
}

// The potential energy motion can release, for the energy books: the structure's above its lowest
// particle, and (with the fluid) the fluid's above its own lowest particle.
template <int D>
Real structure_releasable_potential(const TlsphSolver<D>& s) {
  return releasable_potential_energy<D>(
      std::span<const Vec<D>>(s.position()), [&](std::size_t a) { return s.mass(a); }, s.gravity());
}
template <int D>
Real fluid_releasable_potential(const ParticleSet<D>& p) {
  return releasable_potential_energy<D>(
      std::span<const Vec<D>>(p.position),
      [&](std::size_t a) { return p.kind[a] == FluidKind::fluid ? p.density() * p.volume[a] : Real(0); }, p.gravity());
}

// ------------------------------------------------------------------------------------------------
// Structure only (TLSPH)
// ------------------------------------------------------------------------------------------------

// Writes the fields of the structure particles, in stable-id order, with what a restart needs besides
// positions and velocities: the last acceleration (velocity-Verlet's) and the loads' work.
template <int D>
void write_structure_snapshot(SnapshotWriter& writer, double t, TlsphSolver<D>& solver, const Scene<D>& scene,
                              Real boundary_work, SnapshotAttributes attributes) {
  const Index n = solver.size();
  std::vector<Index> slot(n);
  for (Index a = 0; a < n; ++a) slot[scene.structure_id[a]] = a;
  std::vector<std::array<double, 3>> pos(n);
  SnapshotField disp{"displacement", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField vel{"velocity", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField acc{"acceleration", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField ref{"reference_position", 3, std::vector<double>(3 * n, 0.0)};
  // The Cauchy stress's independent components: xx, yy, xy, and in 3D zz, xz, yz as well.
  constexpr std::array<std::pair<int, int>, 6> stress_entries{{{0, 0}, {1, 1}, {0, 1}, {2, 2}, {0, 2}, {1, 2}}};
  constexpr int stress_components = D == 3 ? 6 : 3;
  std::vector<SnapshotField> stress;
  for (int c = 0; c < stress_components; ++c) {
    const auto [i, j] = stress_entries[c];
    stress.push_back({std::string("sigma_") + "xyz"[i] + "xyz"[j], 1, std::vector<double>(n)});
  }
  SnapshotField id{"id", 1, std::vector<double>(n)}, body{"body", 1, std::vector<double>(n)},
      fixed{"clamped", 1, std::vector<double>(n)};
  for (Index k = 0; k < n; ++k) {
    const Index a = slot[k];
    pos[k] = to_array(solver.position()[a]);
    put_vector(disp, k, solver.position()[a] - solver.reference()[a]);
    put_vector(vel, k, solver.velocity()[a]);
    put_vector(acc, k, solver.acceleration()[a]);
    put_vector(ref, k, solver.reference()[a]);
    const Mat<D> sigma = solver.cauchy_stress(a);
    for (int c = 0; c < stress_components; ++c)
      stress[c].data[k] = sigma(stress_entries[c].first, stress_entries[c].second);
    id.data[k] = k;
    body.data[k] = scene.structure_body[a];
    fixed.data[k] = solver.fixed()[a];
  }
  attributes.insert(attributes.end(), {{"boundary_work", boundary_work}, {"clamp_work", solver.clamp_work()}});
  std::vector<SnapshotField> fields{std::move(disp), std::move(vel), std::move(acc), std::move(ref)};
  for (SnapshotField& f : stress) fields.push_back(std::move(f));
  for (SnapshotField* f : {&id, &body, &fixed}) fields.push_back(std::move(*f));
  writer.write(t, pos, fields, attributes);
}

// Continues a structure-only run from its snapshot: positions, velocities and the last acceleration by
// stable id, and the clamps' work; returns the loads' work. A snapshot of another case is refused.
template <int D>
Real restore_structure(const SnapshotData& state, TlsphSolver<D>& solver, const Scene<D>& scene) {
  const Index n = solver.size();
  const auto mismatch = [&](const std::string& what) {
    return std::runtime_error("restart: " + state.path + " is not a snapshot of this case: " + what);
  };
  if (state.size() != static_cast<std::size_t>(n))
    throw mismatch(std::to_string(state.size()) + " particles against the case's " + std::to_string(n));
  const SnapshotField &x = state.field("position"), &v = state.field("velocity"),
                      &X = state.field("reference_position");
  const auto acc = state.fields.find("acceleration");
  const std::vector<long long> row = state.rows_by_id();
  std::vector<Vec<D>> xs(n), vs(n), as(acc != state.fields.end() ? n : 0);
  for (Index a = 0; a < n; ++a) {
    const Index k = scene.structure_id[a];
    const long long r = static_cast<std::size_t>(k) < row.size() ? row[k] : -1;
    if (r < 0) throw mismatch("it lacks particle id " + std::to_string(k));
    if (norm2(snapshot_vector<D>(X, r) - solver.reference()[a]) > 1e-20 * scene.body_extent * scene.body_extent)
      throw mismatch("particle id " + std::to_string(k) + " has another reference position");
    xs[a] = snapshot_vector<D>(x, r);
    vs[a] = snapshot_vector<D>(v, r);
    if (!as.empty()) as[a] = snapshot_vector<D>(acc->second, r);
  }
  solver.set_motion(xs, vs, as);
  const auto attribute = [&](const char* name) {
    const auto it = state.attributes.find(name);
    return it != state.attributes.end() ? it->second : 0.0;
  };
  solver.set_clamp_work(attribute("clamp_work"));
  return attribute("boundary_work");
}

// Probe columns and values of the displacement probes: u at the probe point by the particle's own
// deformation gradient, u_a + (F_a - I)(point - X_a) (after update_stress()).
template <int D>
void add_displacement_columns(const Scene<D>& scene, std::vector<std::string>& columns) {
  for (const auto& p : scene.probes)
    for (int d = 0; d < D; ++d) columns.push_back(p.name + "." + kComponents[d]);
}
template <int D>
void add_displacement_values(const Scene<D>& scene, const TlsphSolver<D>& solver, std::vector<double>& row) {
  for (const auto& p : scene.probes) {
    const Index a = p.particle;
    const Vec<D> u = (solver.position()[a] - solver.reference()[a]) +
                     (solver.deformation_gradient()[a] - Mat<D>::identity()) * (p.point - solver.reference()[a]);
    for (int d = 0; d < D; ++d) row.push_back(u[d]);
  }
}

// The message for a structure particle that became non-finite or ran away.
template <int D>
std::string structure_divergence_message(const Scene<D>& scene, Index bad, Real t, long long step) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "structure particle %d (id %d) became non-finite or moved more than 10 body lengths at t = %.6g s "
                "(step %lld); try a smaller structure.courant",
                bad, scene.structure_id[bad], t, step);
  return buf;
}

template <int D>
RunResult run_structure(const CaseSpec& spec, const RunOptions& opt, Scene<D>& scene, PhaseTimer& timer) {
  std::vector<std::string> columns;
  add_displacement_columns(scene, columns);
  RunFrame frame(spec, opt, columns, D);
  frame.set_books_advice("try a smaller structure.courant");
  std::unique_ptr<TlsphSolver<D>> solver_ptr;
  timer.time("setup", [&] { solver_ptr = std::make_unique<TlsphSolver<D>>(scene.structure, Exec{opt.device}); });
  TlsphSolver<D>& solver = *solver_ptr;

  // Step size: the structure's Courant limit, shrunk so that end_time is hit exactly.
  const Real dt_max = solver.stable_dt(spec.structure.courant);
  const long long steps = std::max(1LL, static_cast<long long>(std::ceil(spec.end_time / dt_max - 1e-9)));
  const Real dt = spec.end_time / static_cast<Real>(steps);
  frame.set_output_interval(dt, 100);

  Real boundary_work = 0;  // work of the applied loads, integrated by the trapezoidal rule (moving clamps': the solver's)
  const Real releasable = structure_releasable_potential(solver);
  auto record = [&](Real t) {
    timer.time("output", [&] {
      solver.update_stress();
      std::vector<double> row{t};
      add_displacement_values(scene, solver, row);
      frame.probes.add_row(row);
      frame.add_energy_row(t, 0, 0, solver.kinetic_energy(), solver.potential_energy(), solver.strain_energy(),
                           boundary_work + solver.clamp_work(), releasable);
    });
  };
  auto snapshot = [&](Real t) {
    timer.time("output", [&] {
      write_structure_snapshot(frame.snapshots, t, solver, scene, boundary_work, frame.books_attributes());
      frame.flush();
    });
  };

  // A restart continues on the same steps of dt: the snapshot lies at the end of step first_step.
  long long first_step = 0;
  if (!opt.restart.empty()) {
    timer.time("setup", [&] {
      const SnapshotData state = read_snapshot(opt.restart);
      first_step = std::llround(state.time / dt);
      if (first_step >= steps)
        throw std::runtime_error("restart: " + opt.restart + " is at t = " + std::to_string(state.time) +
                                 " s, not before end_time; raise it with --set end_time=...");
      if (std::fabs(first_step * dt - state.time) > 1e-9 * dt)
        throw std::runtime_error("restart: " + opt.restart + " is at t = " + std::to_string(state.time) +
                                 " s, between two steps of this case (dt = " + std::to_string(dt) +
                                 " s): its end_time or structure.courant differ from the earlier run's");
      boundary_work = restore_structure(state, solver, scene);
      frame.continue_books(state);
      frame.start_at(first_step * dt, opt.restart, true);
      if (opt.progress)
        std::fprintf(stderr, "[%s] continuing from %s at t = %.6g s\n", spec.name.c_str(), opt.restart.c_str(),
                     state.time);
    });
  }
  if (first_step == 0) record(0);  // a restart carries the earlier run's rows
  if (frame.writes_snapshots()) snapshot(first_step * dt);
  long long step = first_step;
  const bool loaded = !scene.structure.loads.empty();
  for (; step < steps; ++step) {
    const Real t = step * dt;
    const Real p0 = loaded ? solver.external_power(t) : 0;
    timer.time("structure", [&] { solver.step(t, dt); });
    const Real t1 = (step + 1) * dt;
    if (loaded) boundary_work += 0.5 * dt * (p0 + solver.external_power(t1));
    if ((step + 1) % 16 == 0 || step + 1 == steps) {
      const Index bad = solver.first_runaway(10 * scene.body_extent);
      if (bad >= 0) {
        frame.diverge(structure_divergence_message(scene, bad, t1, step + 1));
      }
    }
    if (frame.result.status == "completed" && stop_signal() != 0 && step + 1 < steps) frame.interrupt(t1, step + 1);
    if (frame.result.status != "completed") {
      ++step;
      if (frame.result.status == "diverged" || frame.due_record(t1, false)) record(t1);
      if (frame.last_snapshot_due()) snapshot(t1);
      break;
    }
    if (frame.due_record(t1, step + 1 == steps)) record(t1);
    if (frame.result.status == "diverged") {  // the energy books broke
      ++step;
      if (frame.last_snapshot_due()) snapshot(t1);
      break;
    }
    if (frame.due_snapshot(t1)) snapshot(t1);
    frame.progress(t1, step + 1 - first_step, timer.get("structure"));
  }
  if (frame.result.status == "completed" && frame.final_snapshot_due()) snapshot(spec.end_time);

  const double t_struct = timer.get("structure");
  JsonObject ppe;
  ppe.set("solver", "none").set("solves", 0LL).set("mean_iterations", 0.0).set("max_iterations", 0LL).set("failures", 0LL);
  JsonObject perf;
  perf.set("threads", static_cast<long long>(omp_get_max_threads()))
      .set("structure_dt", dt)
      .set("structure_pairs", static_cast<long long>(solver.pairs()))
      .set("pair_evaluations", static_cast<long long>(solver.pair_evaluations()))
      .set("pair_evaluations_per_s", t_struct > 0 ? solver.pair_evaluations() / t_struct : 0.0)
      .set("particle_steps_per_s", t_struct > 0 ? double(solver.size()) * (step - first_step) / t_struct : 0.0);
  frame.finish(D, particle_counts(scene.fluid_particles, scene.wall_particles, solver.size()), 0, step - first_step,
               step * dt, timer, ppe, perf);
  return frame.result;
}

// ------------------------------------------------------------------------------------------------
// Fluid (ISPH), alone or coupled with structures (ISPH-TLSPH, seed 001 Algorithm 1)
// ------------------------------------------------------------------------------------------------

// Writes the fields of the fluid, wall and structure particles, in stable-id order, with the fluid
// model's own fields; with a coupled structure, its Cauchy stress on the structure particles (zero on
// the others).
template <int D>
void write_fluid_snapshot(SnapshotWriter& writer, double t, const FluidModel<D>& model,
                          const StructureCoupling<D>* coupling, SnapshotAttributes restart_state) {
  const ParticleSet<D>& particles = model.particles();
  const TlsphSolver<D>* structure = coupling ? &coupling->solver() : nullptr;
  const Index n = particles.size();
  std::vector<Index> slot(n);  // particles by stable id (ids of removed particles are missing)
  std::iota(slot.begin(), slot.end(), 0);
  std::sort(slot.begin(), slot.end(), [&](Index a, Index b) { return particles.id[a] < particles.id[b]; });
  std::vector<std::array<double, 3>> pos(n);
  SnapshotField vel{"velocity", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField p{"pressure", 1, std::vector<double>(n)}, kind{"kind", 1, std::vector<double>(n)},
      id{"id", 1, std::vector<double>(n)}, memory_row{"memory_row", 1, std::vector<double>(n)};
  SnapshotField sxx{"sigma_xx", 1, std::vector<double>(n, 0.0)}, syy{"sigma_yy", 1, std::vector<double>(n, 0.0)},
      sxy{"sigma_xy", 1, std::vector<double>(n, 0.0)};
  for (Index k = 0; k < n; ++k) {
    const Index a = slot[k];
    pos[k] = to_array(particles.position[a]);
    if (const Index s = particles.structure_index[a]; structure && s >= 0) {
      const Mat<D> sigma = structure->cauchy_stress(s);
      sxx.data[k] = sigma(0, 0);
      syy.data[k] = sigma(1, 1);
      sxy.data[k] = sigma(0, 1);
    }
    put_vector(vel, k, particles.velocity[a]);
    p.data[k] = particles.pressure[a];
    kind.data[k] = static_cast<double>(particles.kind[a]);  // 0 fluid, 1 wall, 2 structure
    id.data[k] = particles.id[a];
    memory_row.data[k] = a;
  }
  std::vector<SnapshotField> fields{vel, p, kind, id, memory_row};
  model.add_snapshot_fields(slot, fields);
  restart_state.insert(restart_state.end(),
                       {{"wall_work", particles.wall_work},
                        {"neighbour_searches", static_cast<double>(particles.neighbour_searches())}});
  if (coupling) {
    fields.insert(fields.end(), {sxx, syy, sxy});
    coupling->add_snapshot_fields(particles, slot, fields);
    coupling->add_snapshot_attributes(restart_state);
  }
  writer.write(t, pos, fields, restart_state);
}

// The force probes: each row holds the time mean of the body's force over the fluid steps since the
// previous row, sum(F dt) / sum(dt) (the instantaneous force swings from step to step). The sums go
// into the snapshots, so that a restart writes the rows the uninterrupted run would.
template <int D>
class ForceProbes {
 public:
  explicit ForceProbes(std::vector<ForceProbe> probes) : probes_(std::move(probes)), impulse_(probes_.size()) {}
  void add_columns(std::vector<std::string>& columns) const {
    for (const auto& p : probes_)
      for (int d = 0; d < D; ++d) columns.push_back(p.name + "." + kForceComponents[d]);
  }
  void add_step(const ParticleSet<D>& particles, Real dt) {
    if (probes_.empty()) return;
    for (std::size_t i = 0; i < probes_.size(); ++i) impulse_[i] += dt * particles.body_force(probes_[i].body);
    window_ += dt;
  }
  // The means since the previous row (NaN in the first row, before any step), and a new window.
  void add_values(std::vector<double>& row) {
    for (auto& impulse : impulse_) {
      for (int d = 0; d < D; ++d) row.push_back(window_ > 0 ? impulse[d] / window_ : std::nan(""));
      impulse = Vec<D>::zero();
    }
    window_ = 0;
  }
  void add_attributes(SnapshotAttributes& attributes) const {
    if (probes_.empty()) return;
    attributes.emplace_back("force_probe_window", window_);
    for (std::size_t i = 0; i < probes_.size(); ++i)
      for (int d = 0; d < D; ++d) attributes.emplace_back(key(i, d), impulse_[i][d]);
  }
  // A snapshot without the sums (written before force probes were asked for) starts a new window.
  void restore(const SnapshotData& state) {
    const auto& a = state.attributes;
    const auto window = a.find("force_probe_window");
    if (probes_.empty() || window == a.end()) return;
    window_ = window->second;
    for (std::size_t i = 0; i < probes_.size(); ++i)
      for (int d = 0; d < D; ++d)
        if (const auto v = a.find(key(i, d)); v != a.end()) impulse_[i][d] = v->second;
  }

 private:
  std::string key(std::size_t i, int d) const {
    return "force_probe_impulse." + probes_[i].name + "." + kForceComponents[d];
  }
  std::vector<ForceProbe> probes_;
  std::vector<Vec<D>> impulse_;  // sum of F dt over the window
  Real window_ = 0;              // sum of dt
};

template <int D>
RunResult run_fluid(const CaseSpec& spec, const RunOptions& opt, Scene<D>& scene, PhaseTimer& timer) {
  std::vector<std::string> columns;
  for (const auto& p : scene.fluid_probes) {
    if (p.type == ProbeType::pressure) columns.push_back(p.name + ".p");
    if (p.type == ProbeType::front) columns.push_back(p.name + ".x");
    if (p.type == ProbeType::max_speed) columns.push_back(p.name + ".u");
    if (p.type == ProbeType::water_level) columns.push_back(p.name + ".h");
    if (p.type == ProbeType::velocity)
      for (int d = 0; d < D; ++d) columns.push_back(p.name + "." + kComponents[d]);
  }
  if (scene.has_structure) add_displacement_columns(scene, columns);
  for (const auto& p : scene.pressure_probes) columns.push_back(p.name + ".p");
  ForceProbes<D> forces(scene.force_probes);
  forces.add_columns(columns);
  RunFrame frame(spec, opt, columns, D);
  frame.set_books_advice(spec.fluid.model == FluidMethod::wcsph
                             ? "try a smaller fluid.courant (or structure.courant with a structure)"
                             : "try a smaller fluid.courant, or shifting (fluid.shifting.type), or, with a "
                               "structure, a smaller structure.courant or more coupling.max_iterations");
  std::unique_ptr<FluidModel<D>> model_ptr;
  IsphSolver<D>* isph = nullptr;    // the model in use: one of these two
  WcsphSolver<D>* wcsph = nullptr;
  std::unique_ptr<StructureCoupling<D>> coupling;
  timer.time("setup", [&] {
    scene.fluid.device = opt.device;
    if (spec.fluid.model == FluidMethod::wcsph) {
      auto model = std::make_unique<WcsphSolver<D>>(std::move(scene.fluid));
      wcsph = model.get();
      model_ptr = std::move(model);
    } else {
      auto model = std::make_unique<IsphSolver<D>>(std::move(scene.fluid));
      isph = model.get();
      model_ptr = std::move(model);
    }
    if (scene.has_structure)
      coupling = std::make_unique<StructureCoupling<D>>(std::move(scene.structure), spec.coupling, spec.structure.courant,
                                                        gravity_vector<D>(spec.gravity), opt.device);
  });
  FluidModel<D>& model = *model_ptr;
  ParticleSet<D>& particles = model.particles();
  frame.set_output_interval(model.time_step(), 20);
  // The weakly compressible model advances a coupled structure at each of its acoustic steps.
  typename WcsphSolver<D>::AcousticHook structure_hook;
  if (wcsph && coupling)
    structure_hook = [&](Real t0, Real h) { coupling->explicit_step(t0, h, *wcsph, timer); };

  const Real releasable =
      fluid_releasable_potential(particles) + (coupling ? structure_releasable_potential(coupling->solver()) : 0);
  auto record = [&](Real t) {
    timer.time("output", [&] {
      std::vector<double> row{t};
      for (const auto& p : scene.fluid_probes) {
        if (p.type == ProbeType::pressure) row.push_back(particles.interpolate_pressure(p.point));
        if (p.type == ProbeType::front) row.push_back(particles.front(p.point[D - 1]));
        if (p.type == ProbeType::max_speed) row.push_back(particles.max_speed());
        if (p.type == ProbeType::water_level) row.push_back(particles.water_level(p.point));
        if (p.type == ProbeType::velocity) {
          const Vec<D> u = particles.interpolate_velocity(p.point);
          for (int d = 0; d < D; ++d) row.push_back(u[d]);
        }
      }
      const Real ek = particles.kinetic_energy(), ep = particles.potential_energy();
      Real sk = 0, sp = 0, ss = 0;
      if (coupling) {
        const TlsphSolver<D>& s = coupling->solver();
        add_displacement_values(scene, s, row);
        for (const auto& p : scene.pressure_probes) row.push_back(particles.structure_pressure(p.particle));
        sk = s.kinetic_energy(), sp = s.potential_energy();
        ss = s.strain_energy() + s.obstacle_contact().energy;  // the wall contact's penalty stores strain energy too
      }
      forces.add_values(row);
      frame.probes.add_row(row);
      // energy the moving walls gave the fluid, and the moving clamps the structure
      const Real ww = particles.wall_work + (coupling ? coupling->solver().clamp_work() : 0);
      frame.add_energy_row(t, ek, ep, sk, sp, ss, ww, releasable);
    });
  };
  auto snapshot = [&](Real t) {
    timer.time("output", [&] {
      SnapshotAttributes attributes = frame.books_attributes();
      forces.add_attributes(attributes);
      write_fluid_snapshot(frame.snapshots, t, model, coupling.get(), attributes);
      frame.flush();
    });
  };

  Real t = 0;
  if (!opt.restart.empty()) {
    timer.time("setup", [&] {
      const SnapshotData state = read_snapshot(opt.restart);
      if (state.time >= spec.end_time * (1 - 1e-12))
        throw std::runtime_error("restart: " + opt.restart + " is at t = " + std::to_string(state.time) +
                                 " s, not before end_time; raise it with --set end_time=...");
      particles.restore(state);
      model.restore_fields(state);
      const bool complete = coupling ? coupling->restore(state, particles) : true;
      frame.continue_books(state);
      forces.restore(state);
      t = state.time;
      frame.start_at(t, opt.restart, complete);
      if (opt.progress)
        std::fprintf(stderr, "[%s] continuing from %s at t = %.6g s%s\n", spec.name.c_str(), opt.restart.c_str(), t,
                     complete ? "" : " (a snapshot without the structure's own velocity and acceleration: TLSPH "
                                     "starts from the chord velocity, the interface iterations from zero)");
    });
  }
  const Real start_time = t;
  if (opt.restart.empty()) record(t);  // a restart carries the earlier run's rows
  if (frame.writes_snapshots()) snapshot(t);
  long long step = 0, solves = 0, iterations = 0, max_iterations = 0, failures = 0, removed_total = 0;
  const Index initial_fluid = particles.fluid_count();
  double worst_residual = 0;
  Real first_dt = 0, first_removal = 0;
  ContactRecord<D> wall_contact;  // fluid inside the walls, step by step
  const Real eps = 1e-12 * spec.end_time;
  while (t < spec.end_time - eps) {
    // Land on end_time without a sliver of a step (the PPE's source div u*/dt is sensitive to tiny dt):
    // the last two steps share what is left.
    Real dt = model.time_step();
    if (step == 0) first_dt = dt;
    const Real left = spec.end_time - t;
    if (dt >= left - eps) dt = left;
    else if (2 * dt > left) dt = 0.5 * left;
    FluidStepReport report;
    if (wcsph) {
      report = wcsph->step(dt, timer, structure_hook);
      if (coupling) coupling->record_contact(particles, timer);
    } else {
      report = coupling ? coupling->step(t, dt, *isph, timer) : isph->step(dt, timer);
    }
    ++step;
    t += dt;
    timer.time("output", [&] { forces.add_step(particles, dt); });
    if (particles.wall_count() > 0)
      timer.time("contact", [&] { wall_contact.add(particles.contact(FluidKind::wall), t); });
    solves += report.ppe_solves;
    iterations += report.ppe_iterations;
    worst_residual = std::max(worst_residual, report.ppe.relative_residual);
    max_iterations = std::max<long long>(max_iterations, report.ppe_max_iterations);
    char buf[512];
    // A structure that ran away inside the step's substeps poisons the PPE's right-hand side: name it first.
    const Index bad_s = coupling ? coupling->solver().first_runaway(10 * scene.body_extent) : -1;
    if (bad_s >= 0) {
      frame.diverge(structure_divergence_message(scene, bad_s, t, step));
    } else if (report.ppe_failed) {
      ++failures;
      std::snprintf(buf, sizeof buf,
                    "the pressure Poisson equation was not solved at t = %.6g s (step %lld): %s after %d iterations, "
                    "relative residual %.3g (%s)%s",
                    t, step, report.ppe_solver.c_str(), report.ppe.iterations, report.ppe.relative_residual,
                    report.ppe.message.c_str(),
                    spec.fluid.ppe.fallback == FallbackSolver::none
                        ? "; a fallback solver can be set with fluid.ppe.fallback"
                        : "");
      frame.diverge(buf);
    } else if (const Index bad = particles.first_non_finite(); bad >= 0) {
      static const char* const kKindNames[] = {"fluid", "wall", "structure"};
      std::snprintf(buf, sizeof buf, "%s particle id %d became non-finite at t = %.6g s (step %lld)",
                    kKindNames[static_cast<int>(particles.kind[bad])], particles.id[bad], t, step);
      frame.diverge(buf);
    } else if (dt < 1e-3 * first_dt && dt < left) {
      std::snprintf(buf, sizeof buf,
                    "the time step collapsed to %.3g s (%.3g of the first) at t = %.6g s (step %lld): a fluid particle "
                    "reached %.4g m/s",
                    dt, dt / first_dt, t, step, particles.max_speed());
      frame.diverge(buf);
    } else if (Index out = particles.first_outside(scene.domain_lo, scene.domain_hi); out >= 0) {
      // Thrown out over the walls: removed (fluid.escape = "remove"); through a wall or the floor: diverged.
      if (spec.fluid.escape == EscapePolicy::remove) {
        const Index removed = particles.remove_fluid_outside(scene.domain_lo, scene.domain_hi, scene.up, scene.rim);
        if (removed > 0 && removed_total == 0) first_removal = t;
        removed_total += removed;
        if (removed > 0 && opt.progress)
          std::fprintf(stderr, "[%s] t = %.6g s: %d fluid particle(s) thrown out over the walls were removed (%lld so far)\n",
                       spec.name.c_str(), t, removed, removed_total);
        out = particles.first_outside(scene.domain_lo, scene.domain_hi);
      }
      if (out >= 0) {
        std::snprintf(buf, sizeof buf, "fluid particle id %d escaped the tank at t = %.6g s (step %lld), at (%g, %g)",
                      particles.id[out], t, step, particles.position[out][0], particles.position[out][1]);
        frame.diverge(buf);
      }
    }
    if (frame.result.status == "completed" && stop_signal() != 0 && t < spec.end_time - eps) frame.interrupt(t, step);
    if (frame.result.status != "completed") {
      // An interrupted run keeps the output schedule, so that its continuation writes what an
      // uninterrupted run would; a diverged one records its last state.
      if (frame.result.status == "diverged" || frame.due_record(t, false)) record(t);
      if (frame.last_snapshot_due()) snapshot(t);
      break;
    }
    if (frame.due_record(t, t >= spec.end_time - eps)) record(t);
    if (frame.result.status == "diverged") {  // the energy books broke
      if (frame.last_snapshot_due()) snapshot(t);
      break;
    }
    if (frame.due_snapshot(t)) snapshot(t);
    frame.progress(t, step, timer.total() - timer.get("output") - timer.get("setup"));
  }
  if (frame.result.status == "completed" && frame.final_snapshot_due()) snapshot(t);

  const double stepping = timer.total() - timer.get("output") - timer.get("setup");
  JsonObject ppe;
  ppe.set("solver", isph ? isph->ppe_solver_name() : "none")
      .set("solves", solves)
      .set("mean_iterations", solves > 0 ? double(iterations) / solves : 0.0)
      .set("max_iterations", max_iterations)
      .set("max_relative_residual", worst_residual)
      .set("failures", failures);
  JsonObject perf;
  perf.set("threads", static_cast<long long>(omp_get_max_threads()))
      .set("mean_fluid_dt", step > 0 ? (t - start_time) / step : 0.0)
      .set("fluid_particle_steps_per_s", stepping > 0 ? double(initial_fluid) * step / stepping : 0.0);
  if (coupling) {
    perf.set("coupling", coupling->summary());
    if (const std::string warning = coupling->convergence_warning(); !warning.empty())
      std::fprintf(stderr, "warning: %s\n", warning.c_str());
  }
  if (wcsph) {
    JsonObject w;
    w.set("time_stepping", name_of(spec.fluid.wcsph.time_stepping))
        .set("sound_speed", wcsph->sound_speed())
        .set("advection_steps", wcsph->advection_steps())
        .set("acoustic_steps", wcsph->acoustic_steps())
        .set("mean_acoustic_per_advection",
             wcsph->advection_steps() > 0 ? double(wcsph->acoustic_steps()) / wcsph->advection_steps() : 0.0);
    perf.set("wcsph", w);
  }
  JsonObject counts = particle_counts(initial_fluid, particles.wall_count(), coupling ? coupling->solver().size() : 0);
  counts.set("fluid_removed", removed_total);
  if (removed_total > 0) counts.set("fluid_first_removed_at", first_removal);
  if (particles.wall_count() > 0) wall_contact.write(counts, "wall");
  frame.finish(D, counts,
               step, coupling ? coupling->substeps() : 0, t, timer, ppe, perf);
  return frame.result;
}

template <int D>
RunResult run_dimension(const CaseSpec& spec, const RunOptions& opt) {
  PhaseTimer timer;
  Scene<D> scene;
  timer.time("setup", [&] { scene = build_scene<D>(spec); });
  for (const auto& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return scene.has_fluid ? run_fluid<D>(spec, opt, scene, timer) : run_structure<D>(spec, opt, scene, timer);
}

}  // namespace

RunResult run_case(const CaseSpec& spec, const RunOptions& options) {
  if (options.threads > 0) omp_set_num_threads(options.threads);
  RunOptions opt = options;
  if (!opt.restart.empty() && std::filesystem::is_directory(opt.restart)) opt.restart = newest_snapshot(opt.restart);
  return spec.dimension == 3 ? run_dimension<3>(spec, opt) : run_dimension<2>(spec, opt);
}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int stop_signal() { return g_stop_signal; }

}  // namespace isph
