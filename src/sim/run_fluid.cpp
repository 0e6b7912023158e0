// The time loop of a run with a fluid (seed 001 Algorithm 1 around the fluid model's step): ISPH or
// WCSPH, alone or coupled with structures. The loop only steps the model, lets the probes follow, asks
// the divergence monitor, and records and snapshots on the frame's schedule.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "sim/coupling.hpp"
#include "sim/isph.hpp"
#include "sim/probes.hpp"
#include "sim/run_parts.hpp"
#include "sim/wcsph.hpp"

namespace isph {

namespace {

template <int D>
Vec<D> gravity_vector(const std::array<double, 3>& g) {
  Vec<D> v;
  for (int d = 0; d < D; ++d) v[d] = g[d];
  return v;
}

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
  if (!particles.open_zones().empty()) {  // the buffers (ParticleSet::restore)
    SnapshotField zone{"open_zone", 1, std::vector<double>(n)};
    for (Index k = 0; k < n; ++k) zone.data[k] = particles.open_zone[slot[k]];
    fields.push_back(zone);
    restart_state.push_back({"next_id", static_cast<double>(particles.next_id())});
  }
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

// The checks after each fluid step that stop a run that has diverged (DESIGN.md principle 6), and the
// removal of fluid thrown out over the walls (fluid.escape = "remove").
template <int D>
class DivergenceMonitor {
 public:
  DivergenceMonitor(const CaseSpec& spec, const Scene<D>& scene, const RunOptions& opt)
      : spec_(spec), scene_(scene), opt_(opt) {}

  // Why the run has diverged in the step of length dt that ended at t, or "". `left` was the time to
  // end_time before the step, first_dt the model's first step.
  std::string check(const FluidStepReport& report, ParticleSet<D>& particles, const StructureCoupling<D>* coupling,
                    Real t, Real dt, Real first_dt, Real left, long long step) {
    char buf[512];
    // A structure that ran away inside the step's substeps poisons the PPE's right-hand side: name it first.
    if (const Index bad = coupling ? coupling->solver().first_runaway(10 * scene_.body_extent) : -1; bad >= 0)
      return structure_divergence_message(scene_, bad, t, step);
    if (report.ppe_failed) {
      ++ppe_failures_;
      std::snprintf(buf, sizeof buf,
                    "the pressure Poisson equation was not solved at t = %.6g s (step %lld): %s after %d iterations, "
                    "relative residual %.3g (%s)%s",
                    t, step, report.ppe_solver.c_str(), report.ppe.iterations, report.ppe.relative_residual,
                    report.ppe.message.c_str(),
                    spec_.fluid.ppe.fallback == FallbackSolver::none
                        ? "; a fallback solver can be set with fluid.ppe.fallback"
                        : "");
      return buf;
    }
    if (const Index bad = particles.first_non_finite(); bad >= 0) {
      static const char* const kKindNames[] = {"fluid", "wall", "structure"};
      std::snprintf(buf, sizeof buf, "%s particle id %d became non-finite at t = %.6g s (step %lld)",
                    kKindNames[static_cast<int>(particles.kind[bad])], particles.id[bad], t, step);
      return buf;
    }
    if (dt < 1e-3 * first_dt && dt < left) {
      std::snprintf(buf, sizeof buf,
                    "the time step collapsed to %.3g s (%.3g of the first) at t = %.6g s (step %lld): a fluid particle "
                    "reached %.4g m/s",
                    dt, dt / first_dt, t, step, particles.max_speed());
      return buf;
    }
    return escaped(particles, t, step);
  }
  long long ppe_failures() const { return ppe_failures_; }
  // summary.json's particles: the fluid removed, and when the first was.
  void add_counts(JsonObject& counts) const {
    counts.set("fluid_removed", removed_);
    if (removed_ > 0) counts.set("fluid_first_removed_at", first_removal_);
  }

 private:
  // Fluid outside the tank: thrown out over the walls, it is removed (fluid.escape = "remove"); through
  // a wall or the floor, the run has diverged.
  std::string escaped(ParticleSet<D>& particles, Real t, long long step) {
    Index out = particles.first_outside(scene_.domain_lo, scene_.domain_hi);
    if (out < 0) return "";
    if (spec_.fluid.escape == EscapePolicy::remove) {
      const Index removed = particles.remove_fluid_outside(scene_.domain_lo, scene_.domain_hi, scene_.up, scene_.rim);
      if (removed > 0 && removed_ == 0) first_removal_ = t;
      removed_ += removed;
      if (removed > 0 && opt_.progress)
        std::fprintf(stderr,
                     "[%s] t = %.6g s: %d fluid particle(s) thrown out over the walls were removed (%lld so far)\n",
                     spec_.name.c_str(), t, removed, removed_);
      out = particles.first_outside(scene_.domain_lo, scene_.domain_hi);
      if (out < 0) return "";
    }
    char buf[256];
    std::snprintf(buf, sizeof buf, "fluid particle id %d escaped the tank at t = %.6g s (step %lld), at (%g, %g)",
                  particles.id[out], t, step, particles.position[out][0], particles.position[out][1]);
    return buf;
  }

  const CaseSpec& spec_;
  const Scene<D>& scene_;
  const RunOptions& opt_;
  long long ppe_failures_ = 0, removed_ = 0;
  Real first_removal_ = 0;
};

// The PPE's figures over a run, for summary.json.
struct PpeTally {
  long long solves = 0, iterations = 0, max_iterations = 0;
  double worst_residual = 0;

  void add(const FluidStepReport& report) {
    solves += report.ppe_solves;
    iterations += report.ppe_iterations;
    worst_residual = std::max(worst_residual, report.ppe.relative_residual);
    max_iterations = std::max<long long>(max_iterations, report.ppe_max_iterations);
  }
  JsonObject summary(const std::string& solver, long long failures) const {
    JsonObject ppe;
    ppe.set("solver", solver)
        .set("solves", solves)
        .set("mean_iterations", solves > 0 ? double(iterations) / solves : 0.0)
        .set("max_iterations", max_iterations)
        .set("max_relative_residual", worst_residual)
        .set("failures", failures);
    return ppe;
  }
};

// The fluid's volume (fluid particles only: an open boundary's buffer is not in it).
template <int D>
Real fluid_volume(const ParticleSet<D>& p) {
  Real v = 0;
  for (Index a = 0; a < p.size(); ++a)
    if (p.kind[a] == FluidKind::fluid) v += p.volume[a];
  return v;
}

// summary.json's open_boundaries: per boundary the particles and the mass across its plane (an inlet's
// prescribed mass beside), and the balance inflow - outflow - the change of the fluid's mass, over the
// inflow (docs/CASES.md "Open boundaries").
template <int D>
JsonObject open_boundary_summary(const ParticleSet<D>& p, Real initial_fluid_volume) {
  JsonObject o;
  Real in = 0, out = 0;
  for (std::size_t z = 0; z < p.open_zones().size(); ++z) {
    const OpenZone<D>& zone = p.open_zones()[z];
    const OpenZoneFlow& flow = p.open_flows()[z];
    JsonObject b;
    b.set("type", zone.outlet ? "outlet" : "inlet")
        .set("particles_crossed", flow.crossed)
        .set("mass_crossed", p.density() * flow.volume_crossed);
    if (zone.outlet)
      b.set("particles_removed", flow.removed);
    else
      b.set("mass_prescribed", p.density() * flow.volume_prescribed);
    (zone.outlet ? out : in) += p.density() * flow.volume_crossed;
    o.set(zone.name, b);
  }
  const Real change = p.density() * (fluid_volume(p) - initial_fluid_volume);
  o.set("mass_in", in).set("mass_out", out).set("fluid_mass_change", change);
  if (in > 0) o.set("mass_balance", (in - out - change) / in);
  return o;
}

// The parts of a run with a fluid: the model and its coupled structure, the probes, the output frame.
template <int D>
struct FluidRun {
  FluidRun(const CaseSpec& spec, const RunOptions& opt, Scene<D>& scene, PhaseTimer& timer)
      : spec(spec),
        opt(opt),
        scene(scene),
        timer(timer),
        model(make_model()),
        coupling(make_coupling()),
        probes(fluid_run_probes(scene, model->particles(), coupling ? &coupling->solver() : nullptr)),
        frame(spec, opt, probes.columns(), D),
        releasable(fluid_releasable_potential() + inflow_kinetic_energy() +
                   (coupling ? structure_releasable_potential() : 0)) {
    frame.set_books_advice(spec.fluid.model == FluidMethod::wcsph
                               ? "try a smaller fluid.courant (or structure.courant with a structure)"
                               : "try a smaller fluid.courant, or shifting (fluid.shifting.type), or, with a "
                                 "structure, a smaller structure.courant or more coupling.max_iterations");
  }

  // The fluid model the case names, and with a structure the coupling.
  std::unique_ptr<FluidModel<D>> make_model() {
    std::unique_ptr<FluidModel<D>> m;
    timer.time("setup", [&] {
      scene.fluid.device = opt.device;
      if (spec.fluid.model == FluidMethod::wcsph)
        m = std::make_unique<WcsphSolver<D>>(std::move(scene.fluid));
      else
        m = std::make_unique<IsphSolver<D>>(std::move(scene.fluid));
    });
    return m;
  }
  std::unique_ptr<StructureCoupling<D>> make_coupling() {
    std::unique_ptr<StructureCoupling<D>> c;
    if (scene.has_structure)
      timer.time("setup", [&] {
        c = std::make_unique<StructureCoupling<D>>(std::move(scene.structure), spec.coupling, spec.structure.courant,
                                                   gravity_vector<D>(spec.gravity), opt.device);
      });
    return c;
  }

  // The potential energy motion can release, for the energy books: each medium's above its lowest particle.
  Real fluid_releasable_potential() const {
    const ParticleSet<D>& p = model->particles();
    return releasable_potential_energy<D>(
        std::span<const Vec<D>>(p.position),
        [&](std::size_t a) { return p.kind[a] == FluidKind::fluid ? p.density() * p.volume[a] : Real(0); },
        p.gravity());
  }
  // With inlets, the fluid's kinetic energy at their largest speed once ramped up: the flow they will
  // drive, which a channel started from rest does not yet hold (its books would weigh round-off against
  // nothing).
  Real inflow_kinetic_energy() const {
    const ParticleSet<D>& p = model->particles();
    Real mass = 0, peak = 0;
    for (Index a = 0; a < p.size(); ++a) {
      if (p.kind[a] == FluidKind::fluid) mass += p.density() * p.volume[a];
      const Index z = p.open_zone[a];
      if (z >= 0 && !p.open_zones()[z].outlet)
        peak = std::max(peak, std::abs(p.open_zones()[z].speed(p.position[a], p.open_zones()[z].ramp_time)));
    }
    return 0.5 * mass * peak * peak;
  }
  Real structure_releasable_potential() const {
    const TlsphSolver<D>& s = coupling->solver();
    return releasable_potential_energy<D>(
        std::span<const Vec<D>>(s.position()), [&](std::size_t a) { return s.mass(a); }, s.gravity());
  }

  void record(Real t) {
    timer.time("output", [&] {
      const ParticleSet<D>& particles = model->particles();
      const std::vector<double> row = probes.sample(t);
      const Real ek = fluid_kinetic_energy(particles), ep = fluid_potential_energy(particles);
      Real sk = 0, sp = 0, ss = 0;
      if (coupling) {
        const TlsphSolver<D>& s = coupling->solver();
        sk = s.kinetic_energy(), sp = s.potential_energy();
        ss = s.strain_energy() + s.obstacle_contact().energy;  // the wall contact's penalty stores strain energy too
      }
      frame.probes.add_row(row);
      // energy the moving walls gave the fluid, and the moving clamps the structure
      const Real ww = particles.wall_work + (coupling ? coupling->solver().clamp_work() : 0);
      frame.add_energy_row(t, ek, ep, sk, sp, ss, ww, releasable);
    });
  }
  void snapshot(Real t) {
    timer.time("output", [&] {
      SnapshotAttributes attributes = frame.books_attributes();
      probes.save(attributes);
      write_fluid_snapshot(frame.snapshots, t, *model, coupling.get(), attributes);
      frame.flush();
    });
  }

  // Continues from the snapshot opt.restart; returns its time.
  Real restart() {
    Real t = 0;
    timer.time("setup", [&] {
      const SnapshotData state = read_snapshot(opt.restart);
      if (state.time >= spec.end_time * (1 - 1e-12))
        throw std::runtime_error("restart: " + opt.restart + " is at t = " + std::to_string(state.time) +
                                 " s, not before end_time; raise it with --set end_time=...");
      model->particles().restore(state);
      model->restore_fields(state);
      const bool complete = coupling ? coupling->restore(state, model->particles()) : true;
      frame.continue_books(state);
      probes.restore(state);
      t = state.time;
      frame.start_at(t, opt.restart, complete);
      if (opt.progress)
        std::fprintf(stderr, "[%s] continuing from %s at t = %.6g s%s\n", spec.name.c_str(), opt.restart.c_str(), t,
                     complete ? ""
                              : " (a snapshot without the structure's own velocity and acceleration: TLSPH "
                                "starts from the chord velocity, the interface iterations from zero)");
    });
    return t;
  }

  // summary.json's ppe, performance and particles, and the closing line.
  void finish(Real t, Real start_time, long long steps, const PpeTally& ppe, const DivergenceMonitor<D>& monitor,
              const ContactRecord<D>& wall_contact, Index initial_fluid, Real initial_fluid_volume) {
    const ParticleSet<D>& particles = model->particles();
    const double stepping = timer.total() - timer.get("output") - timer.get("setup");
    JsonObject perf;
    perf.set("threads", static_cast<long long>(omp_get_max_threads()))
        .set("mean_fluid_dt", steps > 0 ? (t - start_time) / steps : 0.0)
        .set("fluid_particle_steps_per_s", stepping > 0 ? double(initial_fluid) * steps / stepping : 0.0);
    if (coupling) {
      perf.set("coupling", coupling->summary());
      if (const std::string warning = coupling->convergence_warning(); !warning.empty())
        std::fprintf(stderr, "warning: %s\n", warning.c_str());
    }
    model->add_performance(perf);
    JsonObject counts =
        particle_counts(initial_fluid, particles.wall_count(), coupling ? coupling->solver().size() : 0);
    monitor.add_counts(counts);
    if (!particles.open_zones().empty())
      counts.set("open_boundaries", open_boundary_summary(particles, initial_fluid_volume));
    if (particles.wall_count() > 0) wall_contact.write(counts, "wall");
    frame.finish(D, counts, steps, coupling ? coupling->substeps() : 0, t, timer,
                 ppe.summary(model->pressure_solver(), monitor.ppe_failures()), perf);
  }

  const CaseSpec& spec;
  const RunOptions& opt;
  Scene<D>& scene;
  PhaseTimer& timer;
  std::unique_ptr<FluidModel<D>> model;
  std::unique_ptr<StructureCoupling<D>> coupling;
  ProbeSet<D> probes;
  RunFrame frame;
  Real releasable = 0;
};

}  // namespace

template <int D>
RunResult run_fluid(const CaseSpec& spec, const RunOptions& opt, Scene<D>& scene, PhaseTimer& timer) {
  FluidRun<D> run(spec, opt, scene, timer);
  FluidModel<D>& model = *run.model;
  ParticleSet<D>& particles = model.particles();
  RunFrame& frame = run.frame;
  frame.set_output_interval(model.time_step(), 20);
  const Real start_time = opt.restart.empty() ? 0 : run.restart();
  if (opt.restart.empty()) run.record(start_time);  // a restart carries the earlier run's rows
  if (frame.writes_snapshots()) run.snapshot(start_time);
  const auto record = [&](Real t) { run.record(t); };
  const auto snapshot = [&](Real t) { run.snapshot(t); };
  DivergenceMonitor<D> monitor(spec, scene, opt);
  PpeTally ppe;
  ContactRecord<D> wall_contact;  // fluid inside the walls, step by step
  const Index initial_fluid = particles.fluid_count();
  const Real initial_fluid_volume = fluid_volume(particles);
  const Real eps = 1e-12 * spec.end_time;
  Real t = start_time, first_dt = 0;
  long long step = 0;
  for (bool going = t < spec.end_time - eps; going;) {
    // Land on end_time without a sliver of a step (the PPE's source div u*/dt is sensitive to tiny dt):
    // the last two steps share what is left.
    Real dt = model.time_step();
    if (step == 0) first_dt = dt;
    const Real left = spec.end_time - t;
    if (dt >= left - eps)
      dt = left;
    else if (2 * dt > left)
      dt = 0.5 * left;
    const FluidStepReport report = model.step(t, dt, run.coupling.get(), timer);
    ++step;
    t += dt;
    timer.time("output", [&] { run.probes.after_step(dt); });
    if (particles.wall_count() > 0)
      timer.time("contact", [&] { wall_contact.add(particles.contact(FluidKind::wall), t); });
    ppe.add(report);
    if (const std::string why = monitor.check(report, particles, run.coupling.get(), t, dt, first_dt, left, step);
        !why.empty())
      frame.diverge(why);
    const bool last = t >= spec.end_time - eps;
    going = end_of_step(frame, t, step, last, record, snapshot) && !last;
    if (going) frame.progress(t, step, timer.total() - timer.get("output") - timer.get("setup"));
  }
  if (frame.running() && frame.final_snapshot_due()) run.snapshot(t);
  run.finish(t, start_time, step, ppe, monitor, wall_contact, initial_fluid, initial_fluid_volume);
  return frame.result;
}

template RunResult run_fluid<2>(const CaseSpec&, const RunOptions&, Scene<2>&, PhaseTimer&);
template RunResult run_fluid<3>(const CaseSpec&, const RunOptions&, Scene<3>&, PhaseTimer&);

}  // namespace isph
