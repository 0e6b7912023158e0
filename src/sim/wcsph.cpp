#include "sim/wcsph.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/enum_names.hpp"
#include "sim/coupling.hpp"
#include "sim/fluid_functors.hpp"

namespace isph {

template <int D>
WcsphSolver<D>::WcsphSolver(FluidSetup<D> s)
    : particles_(s),
      exec_(particles_.exec()),
      density_(s.density),
      viscosity_(s.viscosity),
      reference_velocity_(s.reference_velocity),
      kernel_(s.fluid_kernel()),
      gravity_(s.gravity),
      settings_(s.settings),
      advection_courant_(s.settings.wcsph.advection_courant),
      acoustic_courant_(s.settings.wcsph.acoustic_courant),
      limiter_(s.settings.wcsph.riemann_limiter),
      dual_(s.settings.wcsph.time_stepping == WcsphTimeStepping::dual_criteria),
      kernel_correction_(s.kernel_correction) {
  ParticleSet<D>& ps = particles_;
  const Index n = ps.size();
  sound_speed_ =
      s.settings.wcsph.sound_speed > 0 ? s.settings.wcsph.sound_speed : 10 * std::sqrt(2.0) * reference_velocity_;
  full_sum_ = lattice_kernel_sum(kernel_, s.dx);
  rho_ = ps.array(density_);
  drho_dt_ = ps.array(Real{0});
  for (auto* v : {&acceleration_, &viscous_}) *v = ps.array(Vec<D>::zero());
  for (auto* v : {&L_, &Bhat_}) *v = ps.array(Mat<D>::identity());
  grad_u_ = ps.array(Mat<D>::zero());
  for (auto* v : {&rho_, &drho_dt_}) ps.attach(*v);
  for (auto* v : {&acceleration_, &viscous_}) ps.attach(*v);
  for (auto* v : {&L_, &Bhat_, &grad_u_}) ps.attach(*v);
  if (ps.has_structure()) {
    impedance_ = ps.array(Mat<D>::zero());
    ps.attach(impedance_);
  }

  // The fluid starts in hydrostatic equilibrium below the highest fluid particle of its column (the
  // lattice column through it, along gravity), p = rho0 |g| depth, rho from Eq. 2.
  const Real g_norm = std::sqrt(norm2(gravity_));
  if (g_norm > 0) {
    const Vec<D> up = (-1.0 / g_norm) * gravity_;
    auto column = [&](const Vec<D>& x) {
      std::array<long, D> key{};
      const Vec<D> across = x - dot(x, up) * up;
      for (int d = 0; d < D; ++d) key[d] = std::lround(across[d] / s.dx);
      return key;
    };
    std::map<std::array<long, D>, Real> top;
    for (Index a = 0; a < n; ++a) {
      if (particles_.kind[a] != FluidKind::fluid) continue;
      auto [it, added] = top.emplace(column(particles_.position[a]), dot(particles_.position[a], up));
      if (!added) it->second = std::max(it->second, dot(particles_.position[a], up));
    }
    for (Index a = 0; a < n; ++a) {
      if (particles_.kind[a] != FluidKind::fluid) continue;
      const Real depth = top[column(particles_.position[a])] + 0.5 * s.dx - dot(particles_.position[a], up);
      particles_.pressure[a] = density_ * g_norm * depth;
      rho_[a] = density_ + particles_.pressure[a] / (sound_speed_ * sound_speed_);
    }
  }
}

template <int D>
Real WcsphSolver<D>::time_step() const {
  const Real h = kernel_.h;
  const Real u = std::max(particles_.max_speed(), reference_velocity_);
  const Real acoustic = acoustic_courant_ * h / (sound_speed_ + u);  // Eq. 10
  Real dt = dual_ ? advection_courant_ * h / u : acoustic;           // Eq. 9
  if (viscosity_ > 0) dt = std::min(dt, advection_courant_ * h * h / viscosity_);
  if (settings_.max_dt > 0) dt = std::min(dt, settings_.max_dt);
  return dt;
}

template <int D>
FluidStepReport WcsphSolver<D>::step(Real dt, PhaseTimer& timer, const AcousticHook& hook) {
  configure(dt, timer);
  const Real u = std::max(particles_.max_speed(), reference_velocity_);
  const Real acoustic = acoustic_courant_ * kernel_.h / (sound_speed_ + u);
  const long long count = dual_ ? std::max(1LL, static_cast<long long>(std::ceil(dt / acoustic - 1e-9))) : 1;
  const Real h = dt / static_cast<Real>(count);
  const Real t0 = particles_.time;
  for (long long k = 0; k < count; ++k) {
    particles_.time = t0 + k * h;
    acoustic_step(h, timer, hook);
  }
  particles_.time = t0 + dt;
  ++advection_steps_;
  FluidStepReport report;
  report.ppe_solver = "none";
  return report;
}

template <int D>
void WcsphSolver<D>::configure(Real dt, PhaseTimer& timer) {
  const Index n = particles_.size();
  if (particles_.has_moving_walls()) timer.time("wall_motion", [&] { particles_.prescribe_walls(dt); });
  timer.time("neighbours", [&] { particles_.find_neighbours(); });
  const FluidView<D> v = particles_.view();
  if (dual_)
    timer.time("density", [&] {
      parallel_for(exec_, n,
                   DensityReinitialisation<D>{.v = v,
                                              .density = density_,
                                              .full_sum = full_sum_,
                                              .free_surface = settings_.free_surface,
                                              .rho = rho_.data()});
      parallel_for(exec_, n,
                   EquationOfState<D>{.kind = particles_.kind.data(),
                                      .drho_dt = nullptr,
                                      .dt = 0.0,
                                      .density = density_,
                                      .sound_speed = sound_speed_,
                                      .rho = rho_.data(),
                                      .p = particles_.pressure.data()});
      forces_current_ = false;
    });
  if (viscosity_ > 0)
    timer.time("viscosity", [&] {
      if (kernel_correction_) parallel_for(exec_, n, LaplacianRenormalisation<D>{v.op, L_.data(), Bhat_.data()});
      parallel_for(exec_, n,
                   VelocityGradient<D>{.v = v,
                                       .L = L_.data(),
                                       .u = particles_.velocity.data(),
                                       .no_slip = true,
                                       .smagorinsky = 0.0,
                                       .grad = grad_u_.data(),
                                       .eddy_viscosity = nullptr});
      const ViscousAcceleration<D> viscous{v,       Bhat_.data(), grad_u_.data(), particles_.velocity.data(),
                                           nullptr, viscosity_,   viscous_.data()};
      parallel_for(exec_, n, viscous);
      if (particles_.has_moving_walls()) particles_.record_viscous_wall_power(viscous);  // held with the acceleration
      if (particles_.has_structure()) particles_.record_viscous_force(viscous, FluidKind::structure);
    });
  if (!forces_current_) timer.time("pressure_force", [&] { evaluate_forces(); });
}

template <int D>
void WcsphSolver<D>::evaluate_forces() {
  const Index n = particles_.size();
  const FluidView<D> v = particles_.view();
  parallel_for(exec_, n,
               BoundaryPressure<D>{.v = v,
                                   .gravity = gravity_,
                                   .density = density_,
                                   .sound_speed = sound_speed_,
                                   .p = particles_.pressure.data(),
                                   .rho = rho_.data()});
  RiemannInteraction<D> momentum = riemann();
  momentum.acceleration = acceleration_.data();
  momentum.boundary_force = particles_.boundary_force.data();
  momentum.impedance = impedance_.empty() ? nullptr : impedance_.data();
  parallel_for(exec_, n, momentum);
  forces_current_ = true;
}

template <int D>
RiemannInteraction<D> WcsphSolver<D>::riemann() const {
  return {.v = particles_.view(),
          .u = particles_.velocity.data(),
          .rho = rho_.data(),
          .p = particles_.pressure.data(),
          .density = density_,
          .sound_speed = sound_speed_,
          .limiter = limiter_,
          .drho_dt = nullptr,
          .acceleration = nullptr,
          .boundary_force = nullptr,
          .impedance = nullptr};
}

template <int D>
void WcsphSolver<D>::structure_impedance(std::span<Mat<D>> impedance) const {
  parallel_for(
      exec_, particles_.size(),
      ScatterToStructure<D, Mat<D>>{particles_.structure_index.data(), impedance_.data(), false, impedance.data()});
}

template <int D>
void WcsphSolver<D>::acoustic_step(Real dt, PhaseTimer& timer, const AcousticHook& hook) {
  const Index n = particles_.size();
  auto kick = [&] {
    parallel_for(exec_, n,
                 VerletKick<D>{.kind = particles_.kind.data(),
                               .acceleration = acceleration_.data(),
                               .viscous = viscous_.data(),
                               .gravity = gravity_,
                               .half_dt = 0.5 * dt,
                               .u = particles_.velocity.data()});
  };
  timer.time("integration", kick);
  if (hook) hook(particles_.time, dt);
  timer.time("integration", [&] {
    parallel_for(exec_, n,
                 VerletDrift<D>{.kind = particles_.kind.data(),
                                .u = particles_.velocity.data(),
                                .wall_velocity = particles_.wall_velocity.data(),
                                .dt = dt,
                                .period = particles_.period(),
                                .x = particles_.position.data()});
  });
  timer.time("density", [&] {
    RiemannInteraction<D> continuity = riemann();
    continuity.drho_dt = drho_dt_.data();
    parallel_for(exec_, n, continuity);
    parallel_for(exec_, n,
                 EquationOfState<D>{.kind = particles_.kind.data(),
                                    .drho_dt = drho_dt_.data(),
                                    .dt = dt,
                                    .density = density_,
                                    .sound_speed = sound_speed_,
                                    .rho = rho_.data(),
                                    .p = particles_.pressure.data()});
  });
  timer.time("pressure_force", [&] { evaluate_forces(); });
  timer.time("integration", kick);
  if (particles_.has_moving_walls()) particles_.wall_work += dt * particles_.moving_wall_power();
  ++acoustic_steps_;
}

template <int D>
void WcsphSolver<D>::add_snapshot_fields(const std::vector<Index>& slot, std::vector<SnapshotField>& fields) const {
  const std::size_t n = slot.size();
  SnapshotField density{"density", 1, std::vector<double>(n)};
  SnapshotField acceleration{"pressure_acceleration", 3, std::vector<double>(3 * n, 0.0)};
  SnapshotField boundary_force{"boundary_force", 3, std::vector<double>(3 * n, 0.0)};
  for (std::size_t k = 0; k < n; ++k) {
    const Index a = slot[k];
    density.data[k] = rho_[a];
    for (int d = 0; d < D; ++d) {
      acceleration.data[3 * k + d] = acceleration_[a][d];
      boundary_force.data[3 * k + d] = particles_.boundary_force[a][d];
    }
  }
  fields.insert(fields.end(), {density, acceleration, boundary_force});
  if (impedance_.empty()) return;
  SnapshotField impedance{"impedance", D * D, std::vector<double>(D * D * n)};
  for (std::size_t k = 0; k < n; ++k)
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) impedance.data[D * D * k + D * i + j] = impedance_[slot[k]](i, j);
  fields.push_back(std::move(impedance));
}

// The Verlet step's a^n, the force on walls and structures and their impedance come from the snapshot,
// not from a new evaluation: they were evaluated with v^{n-1/2}, which the snapshot does not hold.
template <int D>
void WcsphSolver<D>::restore_fields(const SnapshotData& snapshot) {
  const SnapshotField& density = snapshot.field("density");
  const auto acceleration = snapshot.fields.find("pressure_acceleration");
  const auto boundary_force = snapshot.fields.find("boundary_force");
  const auto impedance = snapshot.fields.find("impedance");
  const bool forces = acceleration != snapshot.fields.end() && boundary_force != snapshot.fields.end() &&
                      (impedance_.empty() || impedance != snapshot.fields.end());
  const std::vector<long long> row = snapshot.rows_by_id();
  for (Index a = 0; a < particles_.size(); ++a) {
    const auto r = static_cast<std::size_t>(row[particles_.id[a]]);
    rho_[a] = density.data[r];
    if (forces) {
      acceleration_[a] = snapshot_vector<D>(acceleration->second, r);
      particles_.boundary_force[a] = snapshot_vector<D>(boundary_force->second, r);
      if (!impedance_.empty())
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j) impedance_[a](i, j) = impedance->second.data[D * D * r + D * i + j];
    }
  }
  forces_current_ = forces;
}

template <int D>
FluidStepReport WcsphSolver<D>::step(Real /*t: the acoustic steps read the particles' time*/, Real dt,
                                     StructureCoupling<D>* structure, PhaseTimer& timer) {
  if (!structure) return step(dt, timer);
  const FluidStepReport report =
      step(dt, timer, [&](Real t0, Real h) { structure->explicit_step(t0, h, *this, timer); });
  structure->record_contact(particles_, timer);
  return report;
}

template <int D>
void WcsphSolver<D>::add_performance(JsonObject& performance) const {
  JsonObject w;
  w.set("time_stepping", name_of(settings_.wcsph.time_stepping))
      .set("sound_speed", sound_speed_)
      .set("advection_steps", advection_steps_)
      .set("acoustic_steps", acoustic_steps_)
      .set("mean_acoustic_per_advection", advection_steps_ > 0 ? double(acoustic_steps_) / advection_steps_ : 0.0);
  performance.set("wcsph", w);
}

template class WcsphSolver<2>;
template class WcsphSolver<3>;

}  // namespace isph
