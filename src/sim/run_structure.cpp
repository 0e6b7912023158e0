// The structure-only time loop (TLSPH, structure/): fixed steps from the structure's Courant limit,
// landing on end_time, with the applied loads' work for the energy books.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "sim/probes.hpp"
#include "sim/run_parts.hpp"

namespace isph {

namespace {

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

// The potential energy motion can release, for the energy books: the structure's above its lowest
// particle.
template <int D>
Real structure_releasable_potential(const TlsphSolver<D>& s) {
  return releasable_potential_energy<D>(
      std::span<const Vec<D>>(s.position()), [&](std::size_t a) { return s.mass(a); }, s.gravity());
}

// Continues from the snapshot opt.restart on the same steps of dt; returns the step it lies at the end of.
template <int D>
long long restart_structure(const CaseSpec& spec, const RunOptions& opt, const Scene<D>& scene, TlsphSolver<D>& solver,
                            RunFrame& frame, PhaseTimer& timer, Real dt, long long steps, Real& boundary_work) {
  long long first_step = 0;
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
  return first_step;
}

}  // namespace

template <int D>
RunResult run_structure(const CaseSpec& spec, const RunOptions& opt, Scene<D>& scene, PhaseTimer& timer) {
  std::unique_ptr<TlsphSolver<D>> solver_ptr;
  timer.time("setup", [&] { solver_ptr = std::make_unique<TlsphSolver<D>>(scene.structure, Exec{opt.device}); });
  TlsphSolver<D>& solver = *solver_ptr;
  ProbeSet<D> probes = structure_run_probes(scene, solver);
  RunFrame frame(spec, opt, probes.columns(), D);
  frame.set_books_advice("try a smaller structure.courant");

  // Step size: the structure's Courant limit, shrunk so that end_time is hit exactly.
  const Real dt_max = solver.stable_dt(spec.structure.courant);
  const long long steps = std::max(1LL, static_cast<long long>(std::ceil(spec.end_time / dt_max - 1e-9)));
  const Real dt = spec.end_time / static_cast<Real>(steps);
  frame.set_output_interval(dt, 100);

  Real boundary_work =
      0;  // work of the applied loads, integrated by the trapezoidal rule (moving clamps': the solver's)
  const Real releasable = structure_releasable_potential(solver);
  auto record = [&](Real t) {
    timer.time("output", [&] {
      solver.update_stress();
      frame.probes.add_row(probes.sample(t));
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
  const long long first_step =
      opt.restart.empty() ? 0 : restart_structure(spec, opt, scene, solver, frame, timer, dt, steps, boundary_work);
  if (first_step == 0) record(0);  // a restart carries the earlier run's rows
  if (frame.writes_snapshots()) snapshot(first_step * dt);
  long long step = first_step;
  const bool loaded = !scene.structure.loads.empty();
  for (bool going = true; going && step < steps;) {
    const Real t = step * dt;
    const Real p0 = loaded ? solver.external_power(t) : 0;
    timer.time("structure", [&] { solver.step(t, dt); });
    ++step;
    const Real t1 = step * dt;
    if (loaded) boundary_work += 0.5 * dt * (p0 + solver.external_power(t1));
    if (step % 16 == 0 || step == steps)
      if (const Index bad = solver.first_runaway(10 * scene.body_extent); bad >= 0)
        frame.diverge(structure_divergence_message(scene, bad, t1, step));
    going = end_of_step(frame, t1, step, step == steps, record, snapshot);
    if (going) frame.progress(t1, step - first_step, timer.get("structure"));
  }
  if (frame.running() && frame.final_snapshot_due()) snapshot(spec.end_time);

  const double t_struct = timer.get("structure");
  JsonObject ppe;
  ppe.set("solver", "none")
      .set("solves", 0LL)
      .set("mean_iterations", 0.0)
      .set("max_iterations", 0LL)
      .set("failures", 0LL);
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

template RunResult run_structure<2>(const CaseSpec&, const RunOptions&, Scene<2>&, PhaseTimer&);
template RunResult run_structure<3>(const CaseSpec&, const RunOptions&, Scene<3>&, PhaseTimer&);

}  // namespace isph
