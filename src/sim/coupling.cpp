#include "sim/coupling.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace isph {

namespace {

// The components of a along each structure particle's row direction (zero where it has none).
template <int D>
Eigen::VectorXd along(const StateVector<Vec<D>>& a, const StateVector<Vec<D>>& direction) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(a.size()));
  for (std::size_t s = 0; s < a.size(); ++s) out[static_cast<Eigen::Index>(s)] = dot(a[s], direction[s]);
  return out;
}

// a = x direction, per structure particle.
template <int D>
void from_components(const Eigen::VectorXd& x, const StateVector<Vec<D>>& direction, StateVector<Vec<D>>& a) {
  for (std::size_t s = 0; s < a.size(); ++s) a[s] = x[static_cast<Eigen::Index>(s)] * direction[s];
}

}  // namespace

template <int D>
StructureCoupling<D>::StructureCoupling(TlsphSetup<D> setup, const CouplingSpec& coupling, Real courant, Vec<D> gravity,
                                        Device device)
    : exec_{device},
      solver_(std::move(setup), exec_),
      spec_(coupling),
      stable_dt_(solver_.stable_dt(courant)),
      g_norm_(std::sqrt(norm2(gravity))),
      interpolate_(coupling.substep_interaction == SubstepInteraction::interpolated),
      quasi_newton_(coupling.reuse_steps) {
  const Index n = solver_.size();
  const StateAllocator<Vec<D>> vectors(device == Device::cuda);
  const StateAllocator<Real> scalars(device == Device::cuda);
  for (auto* v : {&force_density_, &interaction_, &a_guess_, &a_new_, &a_rows_, &row_direction_, &own_acceleration_,
                  &x_old_, &v_new_, &last_interaction_})
    *v = StateVector<Vec<D>>(n, Vec<D>::zero(), vectors);
  v_mean_ = StateVector<Vec<D>>(solver_.velocity().begin(), solver_.velocity().end(), vectors);
  impedance_ = StateVector<Mat<D>>(n, Mat<D>::zero(), StateAllocator<Mat<D>>(device == Device::cuda));
  shear_rate_ = StateVector<Real>(n, 0.0, scalars);
  wall_point_ = StateVector<Vec<D>>(vectors);
  wall_radius_ = StateVector<Real>(scalars);
  density_ = StateVector<Real>(n, 0.0, scalars);
  inverse_density_ = StateVector<Real>(n, 0.0, scalars);
  for (Index a = 0; a < n; ++a) {
    density_[a] = solver_.density(a);
    // a clamped particle's acceleration is the clamp's, whatever the pressure: no inertia in its row
    inverse_density_[a] = solver_.fixed()[a] ? 0.0 : 1.0 / density_[a];
  }
}

template <int D>
int StructureCoupling<D>::substep(Real t, Real dt, Real& work, InteractionSchedule<D> schedule) {
  const int count =
      spec_.substeps > 0 ? spec_.substeps : std::max(1, static_cast<int>(std::ceil(dt / stable_dt_ - 1e-9)));
  work += solver_.advance(t, dt, count, schedule);
  return count;
}

template <int D>
Real StructureCoupling<D>::added_mass_factor() const {
  if (!spec_.implicit_added_mass) return 0;
  return interpolate_ && has_last_interaction_ ? 1.0 / 6 : 0.5;
}

template <int D>
Eigen::VectorXd StructureCoupling<D>::predict_interface(Real t, Real dt, Real beta, IsphSolver<D>& fluid,
                                                        PhaseTimer& timer, Real& floor) {
  const Index n = solver_.size();
  Eigen::VectorXd x;
  Index wet = 0;
  timer.time("structure", [&] {
    set_obstacles(fluid.particles());
    solver_.save_state();
    parallel_for(exec_, n, CopyElements<Vec<D>>{solver_.position().data(), x_old_.data()});
    fluid.structure_row_directions(row_direction_);
    solver_.own_acceleration(t, own_acceleration_);
    parallel_for(exec_, n,
                 ChordPrediction<D>{.v = solver_.velocity().data(),
                                    .v_mean = v_mean_.data(),
                                    .own = own_acceleration_.data(),
                                    .alpha = has_last_interaction_ ? last_interaction_.data() : nullptr,
                                    .fixed = solver_.fixed().data(),
                                    .inverse_dt = 1.0 / dt,
                                    .alpha_share = 0.5 - beta,
                                    .out = a_guess_.data()});
    x = along(a_guess_, row_direction_);
    for (Index s = 0; s < n; ++s) wet += norm2(row_direction_[s]) > 0;
  });
  floor = g_norm_ * std::sqrt(static_cast<Real>(wet));
  return x;
}

template <int D>
FluidStepReport StructureCoupling<D>::step(Real t, Real dt, IsphSolver<D>& fluid, PhaseTimer& timer) {
  const Index n = solver_.size();
  FluidStepReport report;
  const Real beta = added_mass_factor();
  fluid.set_structure_inertia(inverse_density_, beta);
  fluid.begin_step(dt, timer);
  bool shear_answers = false;
  timer.time("interaction", [&] { shear_answers = set_shear_impedance(fluid.particles(), dt); });
  quasi_newton_.begin_step();
  Real floor = 0;
  Eigen::VectorXd x = predict_interface(t, dt, beta, fluid, timer, floor);  // the iterate: a~_s along the rows
  int iteration = 0, count = 0;
  Real work = 0;
  Vec<D> force = Vec<D>::zero();
  bool converged = false;
  Real residual = 0;  // |H(x) - x| / max(|a_s|, floor) of the last iteration
  while (!converged && iteration < spec_.max_iterations) {
    ++iteration;
    from_components(x, row_direction_, a_rows_);
    fluid.set_structure_acceleration(a_rows_);
    // The first iterate only feeds the quasi-Newton update: its PPE may be solved loosely, and then it
    // cannot end the iterations (docs/CASES.md, coupling.first_ppe_tolerance).
    const bool interim = iteration == 1 && spec_.max_iterations > 1 && spec_.first_ppe_tolerance > 0;
    fluid.solve_pressure(report, timer, interim ? spec_.first_ppe_tolerance : 0.0);
    if (report.ppe_failed) return report;
    timer.time("interaction", [&] {
      force = fluid.structure_pressure_force(force_density_);
      set_interaction();
    });
    Eigen::VectorXd hx;
    Real scale = 0;  // |a_s| along the rows, of the substeps
    timer.time("structure", [&] {
      if (iteration > 1) solver_.restore_state();
      work = 0;
      const bool ramp = interpolate_ && has_last_interaction_;
      const InteractionSchedule<D> schedule{.from = ramp ? last_interaction_.data() : nullptr,
                                            .to = ramp || shear_answers ? interaction_.data() : nullptr,
                                            .impedance = shear_answers ? impedance_.data() : nullptr,
                                            .reference_velocity = shear_answers ? v_mean_.data() : nullptr};
      count = substep(t, dt, work, schedule);
      parallel_for(exec_, n,
                   ChordMotion<D>{.x = solver_.position().data(),
                                  .x_old = x_old_.data(),
                                  .v_mean = v_mean_.data(),
                                  .inverse_dt = 1.0 / dt,
                                  .v_new = v_new_.data(),
                                  .a_new = a_new_.data()});
      scale = along(a_new_, row_direction_).norm();
      if (beta > 0)
        parallel_for(exec_, n,
                     PressureShareRemoved<D>{interaction_.data(), solver_.fixed().data(), beta, a_new_.data()});
      hx = along(a_new_, row_direction_);
    });
    const Real reference = std::max(scale, floor);
    residual = reference > 0 ? (hx - x).norm() / reference : 0;
    converged = !interim && residual <= spec_.tolerance;
    if (converged || spec_.max_iterations == 1) break;
    x = quasi_newton_.next(x, hx);
  }
  if (!converged && spec_.max_iterations > 1) ++unconverged_;
  residual_sum_ += residual;
  max_residual_ = std::max(max_residual_, residual);
  a_guess_.swap(a_new_);                 // the next step starts from this step's acceleration
  last_interaction_.swap(interaction_);  // interaction_ is set afresh before it is read again
  has_last_interaction_ = true;

  fluid.end_step(dt, timer);
  timer.time("structure", [&] {
    solver_.update_stress();
    fluid.particles().move_structure(solver_.position(), v_new_, solver_.deformation_gradient());
    v_mean_.swap(v_new_);
  });
  record_contact(fluid.particles(), timer);
  account_step(work, force, count, iteration);
  return report;
}

template <int D>
void StructureCoupling<D>::explicit_step(Real t, Real dt, WcsphSolver<D>& fluid, PhaseTimer& timer) {
  const Index n = solver_.size();
  Vec<D> force = Vec<D>::zero();
  timer.time("interaction", [&] {
    force = fluid.structure_pressure_force(force_density_);
    set_interaction();
    fluid.structure_impedance(impedance_);
    parallel_for(exec_, n, InteractionAcceleration<D, Mat<D>>{impedance_.data(), density_.data(), impedance_.data()});
  });
  Real work = 0;
  int count = 0;
  timer.time("structure", [&] {
    set_obstacles(fluid.particles());
    parallel_for(exec_, n, CopyElements<Vec<D>>{solver_.position().data(), x_old_.data()});
    // The force's dissipative part answers the structure's velocity at each substep (explained above).
    count = substep(t, dt, work,
                    {.to = interaction_.data(), .impedance = impedance_.data(), .reference_velocity = v_mean_.data()});
    solver_.update_stress();
    parallel_for(exec_, n,
                 ChordMotion<D>{.x = solver_.position().data(),
                                .x_old = x_old_.data(),
                                .v_mean = nullptr,
                                .inverse_dt = 1.0 / dt,
                                .v_new = v_new_.data(),
                                .a_new = nullptr});
    fluid.particles().move_structure(solver_.position(), v_new_, solver_.deformation_gradient());
    v_mean_.swap(v_new_);  // the velocity the fluid's next force evaluation sees
  });
  account_step(work, force, count, 1);
}

template <int D>
bool StructureCoupling<D>::restore(const SnapshotData& snapshot, ParticleSet<D>& fluid) {
  const auto own_velocity = snapshot.fields.find("structure_velocity");
  const auto acceleration = snapshot.fields.find("structure_acceleration");
  const auto interaction = snapshot.fields.find("structure_interaction");
  const bool complete = own_velocity != snapshot.fields.end() && acceleration != snapshot.fields.end() &&
                        interaction != snapshot.fields.end();
  const std::vector<long long> row = snapshot.rows_by_id();
  StateVector<Vec<D>> x(x_old_), v(x_old_);
  for (Index a = 0; a < fluid.size(); ++a) {
    const Index s = fluid.structure_index[a];
    if (s < 0) continue;
    x[s] = fluid.position[a];
    v_mean_[s] = fluid.velocity[a];
    v[s] = complete ? snapshot_vector<D>(own_velocity->second, row[fluid.id[a]]) : v_mean_[s];
    a_guess_[s] = complete ? snapshot_vector<D>(acceleration->second, row[fluid.id[a]]) : Vec<D>::zero();
    last_interaction_[s] = complete ? snapshot_vector<D>(interaction->second, row[fluid.id[a]]) : Vec<D>::zero();
  }
  has_last_interaction_ = complete;
  solver_.set_motion(x, v);
  const auto work = snapshot.attributes.find("interaction_work");
  interaction_work_ = work != snapshot.attributes.end() ? work->second : 0;
  const auto clamp_work = snapshot.attributes.find("clamp_work");
  solver_.set_clamp_work(clamp_work != snapshot.attributes.end() ? clamp_work->second : 0);
  restore_quasi_newton(snapshot, fluid, row);
  fluid.move_structure(solver_.position(), v_mean_, solver_.deformation_gradient());
  return complete;
}

template <int D>
void StructureCoupling<D>::restore_quasi_newton(const SnapshotData& snapshot, const ParticleSet<D>& fluid,
                                                const std::vector<long long>& row) {
  const auto field = snapshot.fields.find("interface_columns");
  const auto count = snapshot.attributes.find("interface_column_steps");
  if (field == snapshot.fields.end() || count == snapshot.attributes.end()) return;
  const auto c = static_cast<std::size_t>(field->second.components / 2);
  std::vector<InterfaceQuasiNewton::Column> columns(
      c, {Eigen::VectorXd::Zero(solver_.size()), Eigen::VectorXd::Zero(solver_.size())});
  for (Index a = 0; a < fluid.size(); ++a) {
    const Index s = fluid.structure_index[a];
    if (s < 0) continue;
    const double* values = field->second.data.data() + 2 * c * static_cast<std::size_t>(row[fluid.id[a]]);
    for (std::size_t j = 0; j < c; ++j) {
      columns[j].dr[s] = values[j];
      columns[j].dh[s] = values[c + j];
    }
  }
  std::vector<std::vector<InterfaceQuasiNewton::Column>> steps(static_cast<std::size_t>(count->second));
  std::size_t next = 0;
  for (std::size_t j = 0; j < steps.size(); ++j) {
    const auto of_step =
        static_cast<std::size_t>(snapshot.attributes.at("interface_columns_of_step_" + std::to_string(j)));
    for (std::size_t k = 0; k < of_step && next < c; ++k) steps[j].push_back(std::move(columns[next++]));
  }
  quasi_newton_.set_history(std::move(steps));
}

template <int D>
void StructureCoupling<D>::add_snapshot_fields(const ParticleSet<D>& fluid, const std::vector<Index>& slot,
                                               std::vector<SnapshotField>& fields) const {
  const std::size_t n = slot.size();
  SnapshotField velocity{"structure_velocity", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField acceleration{"structure_acceleration", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField interaction{"structure_interaction", 3, std::vector<double>(3 * n, 0.0)};
  for (std::size_t k = 0; k < n; ++k) {
    const Index s = fluid.structure_index[slot[k]];
    if (s < 0) continue;
    for (int d = 0; d < D; ++d) {
      velocity.data[3 * k + d] = solver_.velocity()[s][d];
      acceleration.data[3 * k + d] = a_guess_[s][d];
      interaction.data[3 * k + d] = last_interaction_[s][d];
    }
  }
  fields.push_back(std::move(velocity));
  fields.push_back(std::move(acceleration));
  fields.push_back(std::move(interaction));

  // The quasi-Newton columns, all steps' side by side: dr of every column, then dh of every column.
  std::vector<InterfaceQuasiNewton::Column> columns;
  for (const auto& step : quasi_newton_.history()) columns.insert(columns.end(), step.begin(), step.end());
  if (columns.empty()) return;
  const std::size_t c = columns.size();
  SnapshotField history{"interface_columns", static_cast<int>(2 * c), std::vector<double>(2 * c * n, 0.0)};
  for (std::size_t k = 0; k < n; ++k) {
    const Index s = fluid.structure_index[slot[k]];
    if (s < 0) continue;
    for (std::size_t j = 0; j < c; ++j) {
      history.data[2 * c * k + j] = columns[j].dr[s];
      history.data[2 * c * k + c + j] = columns[j].dh[s];
    }
  }
  fields.push_back(std::move(history));
}

template <int D>
void StructureCoupling<D>::add_snapshot_attributes(SnapshotAttributes& attributes) const {
  attributes.emplace_back("interaction_work", interaction_work_);
  attributes.emplace_back("clamp_work", solver_.clamp_work());
  const auto steps = quasi_newton_.history();
  attributes.emplace_back("interface_column_steps", static_cast<double>(steps.size()));
  for (std::size_t j = 0; j < steps.size(); ++j)
    attributes.emplace_back("interface_columns_of_step_" + std::to_string(j), static_cast<double>(steps[j].size()));
}

template <int D>
void StructureCoupling<D>::set_interaction() {
  parallel_for(exec_, solver_.size(),
               InteractionAcceleration<D>{force_density_.data(), density_.data(), interaction_.data()});
  solver_.set_interaction(interaction_);
}

template <int D>
bool StructureCoupling<D>::set_shear_impedance(const ParticleSet<D>& fluid, Real dt) {
  const Index n = solver_.size();
  fluid.gather_structure_impedance(shear_rate_);
  parallel_for(exec_, n, IsotropicRate<D>{shear_rate_.data(), inverse_density_.data(), impedance_.data()});
  return parallel_reduce(exec_, n, Real{0}, ScalarAt{shear_rate_.data()}, MaxOf{}) * dt > kShearRate;
}

template <int D>
void StructureCoupling<D>::set_obstacles(const ParticleSet<D>& fluid) {
  if (!spec_.wall_contact) return;
  if (walls_gathered_ && !fluid.has_moving_walls()) {  // fixed walls: the same points, new candidates
    solver_.find_obstacle_candidates();
    return;
  }
  fluid.gather_walls(wall_point_, wall_radius_);
  solver_.set_obstacles(wall_point_, wall_radius_, solver_.support());
  walls_gathered_ = true;
}

template <int D>
void StructureCoupling<D>::record_overlap() {
  if (!spec_.wall_contact) return;
  const auto contact = solver_.obstacle_contact();
  max_wall_overlap_ = std::max(max_wall_overlap_, contact.deepest);
  steps_with_wall_contact_ += contact.pairs > 0;
}

template <int D>
void StructureCoupling<D>::account_step(Real work, const Vec<D>& force, int count, int iterations) {
  record_overlap();
  interaction_work_ += work;
  force_sum_ += force;
  substeps_ += count;
  max_substeps_ = std::max(max_substeps_, count);
  iterations_ += iterations;
  max_iterations_seen_ = std::max(max_iterations_seen_, iterations);
  ++steps_;
}

template <int D>
void StructureCoupling<D>::record_contact(ParticleSet<D>& fluid, PhaseTimer& timer) {
  timer.time("interaction", [&] { contact_.add(fluid.contact(FluidKind::structure), fluid.time); });
}

template <int D>
JsonObject StructureCoupling<D>::summary() const {
  JsonObject mean_force;
  for (int d = 0; d < D; ++d)
    mean_force.set(d == 0 ? "fx" : d == 1 ? "fy" : "fz", steps_ > 0 ? force_sum_[d] / steps_ : 0.0);
  JsonObject o;
  o.set("substeps_mode", spec_.substeps > 0 ? "fixed" : "stability_limit")
      .set("structure_stable_dt", stable_dt_)
      .set("mean_substeps", steps_ > 0 ? double(substeps_) / steps_ : 0.0)
      .set("max_substeps", max_substeps_)
      .set("mean_interface_iterations", steps_ > 0 ? double(iterations_) / steps_ : 0.0)
      .set("max_interface_iterations", max_iterations_seen_)
      .set("unconverged_steps", unconverged_)
      .set("mean_interface_residual", mean_residual())
      .set("max_interface_residual", max_residual_)
      .set("mean_force_on_structure", mean_force)
      .set("interaction_work", interaction_work_)
      .set("wall_contact", spec_.wall_contact)
      .set("steps_with_wall_contact", steps_with_wall_contact_)
      .set("max_wall_overlap", max_wall_overlap_);
  contact_.write(o, "structure");
  if (const std::string warning = convergence_warning(); !warning.empty()) o.set("warning", warning);
  return o;
}

template <int D>
std::string StructureCoupling<D>::convergence_warning() const {
  const Real mean = mean_residual();
  if (mean <= 1.0) return {};
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "the interface iterations ended with a mean residual |H(a) - a| / |a_s| of %.3g (largest %.3g) "
                "after at most %d iterations per step: the load the structure felt is not the water's; raise "
                "coupling.max_iterations (docs/CASES.md)",
                mean, max_residual_, max_iterations_seen_);
  return buf;
}

template class StructureCoupling<2>;
template class StructureCoupling<3>;

}  // namespace isph
