#include "sim/run.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "io/output.hpp"
#include "sim/scene.hpp"

namespace isph {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Accumulates wall time per phase for summary.json.
class PhaseTimer {
 public:
  template <class F>
  void time(const std::string& phase, F&& f) {
    const auto t0 = Clock::now();
    f();
    seconds_[phase] += seconds_since(t0);
  }
  JsonObject json() const {
    JsonObject o;
    for (const auto& [k, v] : seconds_) o.set(k, v);
    return o;
  }
  double get(const std::string& phase) const {
    auto it = seconds_.find(phase);
    return it == seconds_.end() ? 0.0 : it->second;
  }

 private:
  std::map<std::string, double> seconds_;
};

template <int D>
std::array<double, 3> to_array(const Vec<D>& v) {
  std::array<double, 3> a{0, 0, 0};
  for (int d = 0; d < D; ++d) a[d] = v[d];
  return a;
}

// Writes the fields of the structure particles, in stable-id order.
template <int D>
void write_snapshot(SnapshotWriter& writer, double t, TlsphSolver<D>& solver, const Scene<D>& scene) {
  const Index n = solver.size();
  std::vector<Index> slot(n);
  for (Index a = 0; a < n; ++a) slot[scene.structure_id[a]] = a;
  std::vector<std::array<double, 3>> pos(n);
  SnapshotField disp{"displacement", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField vel{"velocity", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField ref{"reference_position", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField sxx{"sigma_xx", 1, std::vector<double>(n)}, syy{"sigma_yy", 1, std::vector<double>(n)},
      sxy{"sigma_xy", 1, std::vector<double>(n)};
  SnapshotField id{"id", 1, std::vector<double>(n)}, body{"body", 1, std::vector<double>(n)},
      fixed{"clamped", 1, std::vector<double>(n)};
  for (Index k = 0; k < n; ++k) {
    const Index a = slot[k];
    pos[k] = to_array(solver.position()[a]);
    for (int d = 0; d < D; ++d) {
      disp.data[3 * k + d] = solver.position()[a][d] - solver.reference()[a][d];
      vel.data[3 * k + d] = solver.velocity()[a][d];
      ref.data[3 * k + d] = solver.reference()[a][d];
    }
    const Mat<D> sigma = solver.cauchy_stress(a);
    sxx.data[k] = sigma(0, 0);
    syy.data[k] = sigma(1, 1);
    sxy.data[k] = sigma(0, 1);
    id.data[k] = k;
    body.data[k] = scene.structure_body[a];
    fixed.data[k] = solver.fixed()[a];
  }
  writer.write(t, pos, {disp, vel, ref, sxx, syy, sxy, id, body, fixed});
}

// First non-finite or runaway particle, or -1.
template <int D>
Index find_divergence(const TlsphSolver<D>& solver, Real limit) {
  for (Index a = 0; a < solver.size(); ++a) {
    const Real u2 = norm2(solver.position()[a] - solver.reference()[a]);
    if (!std::isfinite(u2) || !std::isfinite(norm2(solver.velocity()[a])) || u2 > limit * limit)
      return a;
  }
  return -1;
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

template <int D>
RunResult run_structure(const CaseSpec& spec, const RunOptions& opt) {
  const auto wall0 = Clock::now();
  PhaseTimer timer;
  RunResult result;
  result.out_dir = opt.out_dir.empty() ? "out/" + spec.name : opt.out_dir;
  std::filesystem::create_directories(result.out_dir);
  write_file_atomically(result.out_dir + "/case.resolved.toml", spec.resolved_toml);

  Scene<D> scene;
  std::unique_ptr<TlsphSolver<D>> solver_ptr;
  timer.time("setup", [&] {
    scene = build_scene<D>(spec);
    solver_ptr = std::make_unique<TlsphSolver<D>>(scene.structure, Exec{opt.device});
  });
  TlsphSolver<D>& solver = *solver_ptr;

  // Step size: the structure's Courant limit, shrunk so that end_time is hit exactly.
  const Real dt_max = solver.stable_dt(spec.structure.courant);
  const long long steps = std::max(1LL, static_cast<long long>(std::ceil(spec.end_time / dt_max - 1e-9)));
  const Real dt = spec.end_time / static_cast<Real>(steps);
  const Real out_interval = spec.output.interval > 0 ? spec.output.interval : 100 * dt;
  const Real snap_interval = spec.output.snapshot_interval;

  std::vector<std::string> probe_cols{"time"};
  const char* comp[3] = {"ux", "uy", "uz"};
  for (const auto& p : scene.probes)
    for (int d = 0; d < D; ++d) probe_cols.push_back(p.name + "." + comp[d]);
  CsvTable probes(result.out_dir + "/probes.csv", probe_cols);
  CsvTable energy(result.out_dir + "/energy.csv",
                  {"time", "fluid_kinetic", "fluid_potential", "structure_kinetic", "structure_potential",
                   "structure_strain", "boundary_work", "total"});
  SnapshotWriter snapshots(result.out_dir, D);
  const bool write_snapshots = spec.output.snapshots && SnapshotWriter::available();

  Real boundary_work = 0;  // work of the applied loads, integrated by the trapezoidal rule
  auto record = [&](Real t) {
    timer.time("output", [&] {
      solver.update_stress();
      std::vector<double> row{t};
      for (const auto& p : scene.probes) {
        const Index a = p.particle;
        // u at the probe point by the particle's own deformation gradient
        const Vec<D> u = (solver.position()[a] - solver.reference()[a]) +
                         (solver.deformation_gradient()[a] - Mat<D>::identity()) * (p.point - solver.reference()[a]);
        for (int d = 0; d < D; ++d) row.push_back(u[d]);
      }
      probes.add_row(row);
      const Real ek = solver.kinetic_energy(), ep = solver.potential_energy(), es = solver.strain_energy();
      energy.add_row({t, 0, 0, ek, ep, es, boundary_work, ek + ep + es - boundary_work});
    });
  };
  auto snapshot = [&](Real t) {
    if (write_snapshots)
      timer.time("output", [&] {
        write_snapshot(snapshots, t, solver, scene);
        probes.flush();
        energy.flush();
      });
  };

  record(0);
  snapshot(0);
  Real next_out = out_interval, next_snap = snap_interval > 0 ? snap_interval : spec.end_time * 2;
  long long step = 0;
  const bool loaded = !scene.structure.loads.empty();
  auto last_progress = Clock::now();
  result.status = "completed";
  result.message = "reached end_time";
  for (; step < steps; ++step) {
    const Real t = step * dt;
    const Real p0 = loaded ? solver.external_power(t) : 0;
    timer.time("structure", [&] { solver.step(t, dt); });
    const Real t1 = (step + 1) * dt;
    if (loaded) boundary_work += 0.5 * dt * (p0 + solver.external_power(t1));
    if ((step + 1) % 16 == 0 || step + 1 == steps) {
      const Index bad = find_divergence(solver, 10 * scene.body_extent);
      if (bad >= 0) {
        result.status = "diverged";
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "structure particle %d (id %d) became non-finite or moved more than 10 body lengths at t = %.6g s "
                      "(step %lld); try a smaller structure.courant",
                      bad, scene.structure_id[bad], t1, step + 1);
        result.message = buf;
        ++step;
        record(t1);
        snapshot(t1);
        break;
      }
    }
    if (t1 >= next_out - 1e-12 * spec.end_time || step + 1 == steps) {
      record(t1);
      while (next_out <= t1 + 1e-12 * spec.end_time) next_out += out_interval;
    }
    if (t1 >= next_snap - 1e-12 * spec.end_time) {
      snapshot(t1);
      while (next_snap <= t1 + 1e-12 * spec.end_time) next_snap += snap_interval;
    }
    if (opt.progress && seconds_since(last_progress) > 2.0) {
      last_progress = Clock::now();
      const double elapsed = seconds_since(wall0);
      const double rate = (step + 1) / std::max(1e-9, timer.get("structure"));
      std::fprintf(stderr, "[%s] t = %.4g / %.4g s (%.0f%%)  %.0f steps/s  ETA %s\n", spec.name.c_str(), t1,
                   spec.end_time, 100.0 * t1 / spec.end_time, rate,
                   format_duration(elapsed / (t1 / spec.end_time) - elapsed).c_str());
    }
  }
  if (result.status == "completed" && !(snap_interval > 0 && std::fabs(std::fmod(spec.end_time, snap_interval)) < 1e-12))
    snapshot(spec.end_time);
  probes.flush();
  energy.flush();

  const double wall = seconds_since(wall0);
  const double t_struct = timer.get("structure");
  JsonObject particles;
  particles.set("fluid", static_cast<long long>(scene.fluid_particles))
      .set("wall", static_cast<long long>(scene.wall_particles))
      .set("structure", static_cast<long long>(solver.size()));
  JsonObject step_counts;
  step_counts.set("fluid", 0LL).set("structure", step);
  JsonObject ppe;
  ppe.set("solver", "none").set("mean_iterations", 0.0).set("max_iterations", 0LL).set("failures", 0LL);
  JsonObject perf;
  perf.set("threads", static_cast<long long>(omp_get_max_threads()))
      .set("structure_dt", dt)
      .set("structure_pairs", static_cast<long long>(solver.pairs()))
      .set("pair_evaluations", static_cast<long long>(solver.pair_evaluations()))
      .set("pair_evaluations_per_s", t_struct > 0 ? solver.pair_evaluations() / t_struct : 0.0)
      .set("particle_steps_per_s", t_struct > 0 ? double(solver.size()) * step / t_struct : 0.0);
  JsonObject summary;
  summary.set("case", spec.name)
      .set("dimension", D)
      .set("device", device_name(opt.device))
      .set("particles", particles)
      .set("steps", step_counts)
      .set("simulated_time", step * dt)
      .set("wall_time_s", wall)
      .set("phases", timer.json())
      .set("ppe", ppe)
      .set("performance", perf)
      .set("status", result.status)
      .set("message", result.message);
  write_file_atomically(result.out_dir + "/summary.json", summary.dump() + "\n");
  if (opt.progress)
    std::fprintf(stderr, "[%s] %s: %s; %lld steps in %.2f s wall; output in %s\n", spec.name.c_str(),
                 result.status.c_str(), result.message.c_str(), step, wall, result.out_dir.c_str());
  return result;
}

}  // namespace

RunResult run_case(const CaseSpec& spec, const RunOptions& options) {
  if (options.threads > 0) omp_set_num_threads(options.threads);
  if (options.device != Device::cpu)
    throw std::runtime_error("--device cuda: the structure time loop runs on the cpu only in this version");
  return spec.dimension == 3 ? run_structure<3>(spec, options) : run_structure<2>(spec, options);
}

}  // namespace isph
