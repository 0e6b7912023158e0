// Compiled by nvcc when the CUDA backend is built (see ISPH_LOOP_SOURCES in CMakeLists.txt), so
// the stage functions below launch the same functors on either device.
#include "structure/tlsph.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "core/neighbour_search.hpp"
#include "core/ordered_sum.hpp"
#include "kernels/operators.hpp"

namespace isph {

template <int D>
void tlsph_stress(const Exec& exec, const TlsphView<D>& view) {
  const auto over_strained = [&](const auto& f) {
    parallel_for_listed(exec, view.n, view.strained, view.strained_count, f);
  };
  over_strained(TlsphStress<D>{view});
  if (view.cell_quadrature) {
    over_strained(TlsphStrainGradient<D>{view});
    over_strained(TlsphGradientStress<D>{view});
  }
  if (view.hourglass > 0 && view.quadratic) over_strained(TlsphHourglass<D>{view});
}

template <int D>
void tlsph_acceleration(const Exec& exec, const TlsphView<D>& view) {
  parallel_for_listed(exec, view.n, view.moving, view.moving_count, TlsphAcceleration<D>{view});
}

template <int D>
TlsphSolver<D>::TlsphSolver(TlsphSetup<D> s, Exec exec)
    : exec_(exec),
      n_(static_cast<Index>(s.X.size())),
      kernels_(s.kernels),
      level_(s.level.empty() ? std::vector<unsigned char>(s.X.size(), 0) : s.level),
      integrator_(s.integrator),
      gravity_(s.gravity),
      damping_(s.damping),
      hourglass_(s.hourglass),
      quadratic_(s.gradient == StructureGradient::quadratic),
      cell_quadrature_(s.quadrature == StructureQuadrature::cell),
      materials_(s.materials.begin(), s.materials.end()),
      loads_(std::move(s.loads)),
      X_(s.X.begin(), s.X.end()),
      v_(s.v.begin(), s.v.end()),
      volume_(s.volume.begin(), s.volume.end()),
      material_(s.material.begin(), s.material.end()),
      fixed_(s.fixed.begin(), s.fixed.end()),
      motion_(s.motion.begin(), s.motion.end()),
      motions_(std::move(s.motions)) {
  if (exec_.device == Device::cuda && cuda_devices() == 0)
    throw std::runtime_error(
        "the structure solver was asked to run on a CUDA device, and none is visible to this process");
  if (loads_.size() > 8) throw std::invalid_argument("at most 8 loads are supported");
  x_ = X_;
  if (motion_.empty()) motion_.assign(n_, -1);
  acc_.assign(n_, Vec<D>::zero());
  contact_offset_.assign(static_cast<std::size_t>(n_) + 1, 0);
  mass_.resize(n_);
  for (Index a = 0; a < n_; ++a) {
    mass_[a] = materials_[material_[a]].density * volume_[a];
    if (fixed_[a]) v_[a] = Vec<D>::zero();
  }
  prescribe_clamps(Exec{}, 0);  // the clamps' velocity at t = 0 (the state is still in host memory)
  load_acc_.reserve(loads_.size() * n_);
  for (const auto& l : loads_) load_acc_.insert(load_acc_.end(), l.acc.begin(), l.acc.end());

  // Reference configuration (on the host): neighbours within the same body and the pair gradients
  // c_ab (Eq. 35-36: L_a g_ab, or exact for quadratic fields).
  // (a body's particles share one spacing, so each pair has its body's kernel).
  CellList<D> reference_cells;
  reference_cells.build(s.X, kernels_.largest_support());
  const NeighbourList list = neighbour_list(reference_cells, n_, s.body.data(), kernels_.reach(level_.data()));
  nbr_offset_.assign(list.offset.begin(), list.offset.end());
  nbr_.assign(list.index.begin(), list.index.end());
  cgrad_.resize(nbr_.size());
  hg_weight_.resize(nbr_.size());
  const OperatorView<D> reference{n_,
                                  X_.data(),
                                  volume_.data(),
                                  nbr_offset_.data(),
                                  nbr_.data(),
                                  kernels_,
                                  {},
                                  kernels_.levels > 1 ? level_.data() : nullptr};
  std::vector<Mat<D>> L(n_, Mat<D>::identity());
  if (s.gradient != StructureGradient::uncorrected)
    parallel_for(Exec{}, n_, GradientCorrection<D>{reference, L.data()});
  for (Index a = 0; a < n_; ++a)
    for (Index k = nbr_offset_[a]; k < nbr_offset_[a + 1]; ++k)
      cgrad_[k] = L[a] * (volume_[nbr_[k]] * reference.gradient(a, nbr_[k], X_[a] - X_[nbr_[k]]));
  if (s.gradient == StructureGradient::quadratic)
    parallel_for(Exec{}, n_, QuadraticCorrection<D>{reference, cgrad_.data()});
  // Per pair (a, b): the hourglass weight and the reverse pair's gradient c_ba; per particle S_a.
  rcgrad_.resize(nbr_.size());
  cgrad_sum_.assign(n_, Vec<D>::zero());
  hg_moment_.assign(n_, Mat<D>::zero());
  for (Index a = 0; a < n_; ++a)
    for (Index k = nbr_offset_[a]; k < nbr_offset_[a + 1]; ++k) {
      const Index b = nbr_[k];
      const Vec<D> Xab = X_[a] - X_[b];
      hg_weight_[k] = volume_[b] * reference.kernel(a, b).value(std::sqrt(norm2(Xab))) / norm2(Xab);
      hg_moment_[a] = hg_moment_[a] + hg_weight_[k] * outer(Xab, Xab);
      cgrad_sum_[a] += cgrad_[k];
      const auto first = nbr_.begin() + nbr_offset_[b], last = nbr_.begin() + nbr_offset_[b + 1];
      rcgrad_[k] = cgrad_[std::find(first, last, a) - nbr_.begin()];  // the list is symmetric
    }
  list_strained_particles();
  F_.assign(n_, Mat<D>::identity());
  stress_.assign(n_, Mat<D>::zero());
  if (cell_quadrature_) {
    strain_.assign(n_, Mat<D>::zero());
    gradient_stress_.assign(static_cast<std::size_t>(D) * n_, Mat<D>::zero());
  }
  psi_.assign(n_, 0);
  cell_moment_.resize(n_);
  for (Index a = 0; a < n_; ++a) cell_moment_[a] = std::pow(volume_[a], 2.0 / D) / 12;
  for (auto* v : {&x0_, &v0_, &x_sum_, &v_sum_, &saved_x_, &saved_v_}) v->assign(n_, Vec<D>::zero());
  if (exec_.device == Device::cuda) {
    make_state_device_visible();
    graph_ = std::make_unique<LaunchGraph>();
  }
  update_stress();
}

// A free particle's acceleration reads its neighbours' stress; the stress of a particle reads its
// neighbours' places, the quadratic hourglass pass their F, and the cell quadrature's two passes the
// strain two links away: the stress is needed up to `reach` links from a free particle.
template <int D>
void TlsphSolver<D>::list_strained_particles() {
  strained_.clear();
  moving_.clear();
  if (!motions_.empty()) return;  // clamps that move: every particle, for the clamps' work
  const int reach = 1 + (hourglass_ > 0 && quadratic_) + 2 * cell_quadrature_;
  std::vector<unsigned char> near(fixed_.begin(), fixed_.end());
  for (auto& f : near) f = !f;  // the free particles
  for (int round = 0; round < reach; ++round) {
    std::vector<unsigned char> next = near;
    for (Index a = 0; a < n_; ++a)
      for (Index k = nbr_offset_[a]; k < nbr_offset_[a + 1] && !next[a]; ++k) next[a] = near[nbr_[k]];
    near.swap(next);
  }
  for (Index a = 0; a < n_; ++a) {
    if (near[a]) strained_.push_back(a);
    if (!fixed_[a]) moving_.push_back(a);
  }
  if (static_cast<Index>(strained_.size()) == n_) strained_.clear();  // every particle: no list
  if (static_cast<Index>(moving_.size()) == n_) moving_.clear();
}

template <int D>
void TlsphSolver<D>::make_state_device_visible() {
  make_device_visible(materials_);
  make_device_visible(volume_), make_device_visible(cell_moment_), make_device_visible(hg_weight_),
      make_device_visible(psi_);
  make_device_visible(material_), make_device_visible(motion_), make_device_visible(mass_);
  make_device_visible(fixed_);
  make_device_visible(block_sums_), make_device_visible(power_record_), make_device_visible(clamp_record_);
  make_device_visible(nbr_offset_), make_device_visible(nbr_);
  make_device_visible(strained_), make_device_visible(moving_);
  make_device_visible(obstacle_point_), make_device_visible(obstacle_radius_);
  make_device_visible(contact_offset_), make_device_visible(contact_point_), make_device_visible(contact_radius_);
  for (auto* v : {&load_acc_, &interaction_, &X_, &x_, &v_, &acc_, &cgrad_, &rcgrad_, &cgrad_sum_, &x0_, &v0_, &x_sum_,
                  &v_sum_, &saved_x_, &saved_v_})
    make_device_visible(*v);
  for (auto* m : {&F_, &stress_, &strain_, &gradient_stress_, &hg_moment_}) make_device_visible(*m);
}

template <int D>
TlsphView<D> TlsphSolver<D>::view() {
  TlsphView<D> s{};
  s.n = n_;
  s.X = X_.data();
  s.nbr_offset = nbr_offset_.data();
  s.nbr = nbr_.data();
  s.cgrad = cgrad_.data();
  s.hg_weight = hg_weight_.data();
  s.hg_moment = hg_moment_.data();
  s.rcgrad = rcgrad_.data();
  s.cgrad_sum = cgrad_sum_.data();
  s.volume = volume_.data();
  s.cell_moment = cell_moment_.data();
  s.material = material_.data();
  s.materials = materials_.data();
  s.fixed = fixed_.data();
  s.strained = strained_.empty() ? nullptr : strained_.data();
  s.strained_count = static_cast<Index>(strained_.size());
  s.moving = moving_.empty() ? nullptr : moving_.data();
  s.moving_count = static_cast<Index>(moving_.size());
  s.clamps_move = !motions_.empty();
  s.x = x_.data();
  s.v = v_.data();
  s.load_acc = load_acc_.data();
  s.loads = static_cast<int>(loads_.size());
  s.gravity = gravity_;
  s.interaction = interaction_.empty() ? nullptr : interaction_.data();
  s.obstacles = obstacles();
  s.damping = damping_;
  s.hourglass = hourglass_;
  s.quadratic = quadratic_;
  s.cell_quadrature = cell_quadrature_;
  s.F = F_.data();
  s.stress = stress_.data();
  s.psi = psi_.data();
  s.strain = strain_.data();
  s.gradient_stress = gradient_stress_.data();
  s.acc = acc_.data();
  return s;
}

// The smallest over the particles of courant h / c_p, with each particle's own h and material.
template <int D>
Real TlsphSolver<D>::stable_dt(Real courant) const {
  Real dt = std::numeric_limits<Real>::max();
  for (Index a = 0; a < n_; ++a) {
    const ElasticMaterial& m = materials_[material_[a]];
    dt = std::min(dt, courant * kernels_.kernel[level_[a]].h / std::sqrt((m.lambda + 2 * m.mu) / m.density));
  }
  return dt;
}

template <int D>
void TlsphSolver<D>::update_stress() {
  tlsph_stress(waiting_exec(), view());
  pair_evaluations_ += stress_passes() * static_cast<long long>(pairs());
}

template <int D>
void TlsphSolver<D>::own_acceleration(Real t, StateVector<Vec<D>>& acc) {
  TlsphView<D> s = view();
  for (std::size_t l = 0; l < loads_.size(); ++l) s.load_factor[l] = loads_[l].factor(t);
  s.interaction = nullptr;
  s.acc = acc.data();
  tlsph_stress(waiting_exec(), s);
  tlsph_acceleration(waiting_exec(), s);
  pair_evaluations_ += evaluation_passes() * static_cast<long long>(pairs());
}

template <int D>
void TlsphSolver<D>::evaluate(const Exec& exec, Real t) {
  TlsphView<D> s = view();
  for (std::size_t l = 0; l < loads_.size(); ++l) s.load_factor[l] = loads_[l].factor(t);
  tlsph_stress(exec, s);
  tlsph_acceleration(exec, s);
}

template <int D>
bool TlsphSolver<D>::queues_steps() const {
  return exec_.device == Device::cuda && integrator_ == StructureIntegrator::rk4 && motions_.empty();
}

template <int D>
void TlsphSolver<D>::step(Real t, Real dt) {
  if (integrator_ == StructureIntegrator::verlet) {
    step_verlet(t, dt);
    return;
  }
  step_rk4(queues_steps() ? graph_->exec() : waiting_exec(), t, dt, clamp_record(1));
  if (queues_steps()) graph_->synchronize();
  add_clamp_work(1, dt);
}

template <int D>
Real TlsphSolver<D>::advance(Real t, Real dt, int count, InteractionSchedule<D> schedule) {
  if (schedule.varies() && interaction_.empty())
    throw std::logic_error("TlsphSolver::advance: a varying interaction before any interaction field");
  const Real h = dt / count;
  const bool queued = queues_steps();
  const Exec exec = queued ? graph_->exec() : waiting_exec();
  const bool with_power = !interaction_.empty();
  // The power at the start (slot 2k) and the end (2k + 1) of step k. Under a field that does not vary a
  // step starts with the power its predecessor ended with, so only the first start is evaluated.
  resize_for_overwrite(power_record_, 2 * static_cast<std::size_t>(count));
  Real* const clamp_slots = integrator_ == StructureIntegrator::rk4 ? clamp_record(count) : nullptr;
  const auto record_power = [&](int slot) {
    if (with_power) ordered_sum_into(exec, n_, interaction_power_term(), block_sums_, power_record_.data() + slot);
  };
  for (int k = 0; k < count; ++k) {
    if (schedule.varies())
      parallel_for(exec, n_,
                   SetInteraction<D>{.from = schedule.from,
                                     .to = schedule.to ? schedule.to : interaction_.data(),
                                     .s = (k + 0.5) / count,
                                     .impedance = schedule.impedance,
                                     .reference_velocity = schedule.reference_velocity,
                                     .v = v_.data(),
                                     .interaction = interaction_.data(),
                                     .acc = verlet_started_ ? acc_.data() : nullptr});
    if (schedule.varies() || k == 0) record_power(2 * k);
    if (integrator_ == StructureIntegrator::rk4)
      step_rk4(exec, t + k * h, h, clamp_slots ? clamp_slots + 6 * k : nullptr);
    else
      step_verlet(t + k * h, h);
    record_power(2 * k + 1);
  }
  if (queued) graph_->synchronize();
  if (clamp_slots) add_clamp_work(count, h);
  Real work = 0;
  if (with_power)
    for (int k = 0; k < count; ++k) {
      const Real start = schedule.varies() || k == 0 ? power_record_[2 * k] : power_record_[2 * k - 1];
      work += 0.5 * h * (start + power_record_[2 * k + 1]);  // the trapezoidal rule
    }
  return work;
}

namespace {
constexpr Real kRk4Sum[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};  // each stage's weight in the step (Eqs. 43-45)
}  // namespace

template <int D>
void TlsphSolver<D>::rk4_launches(const Exec& exec, Real t, Real dt, Real* clamp_record) {
  parallel_for(exec, n_,
               StartRungeKutta<D>{.x = x_.data(),
                                  .v = v_.data(),
                                  .x0 = x0_.data(),
                                  .v0 = v0_.data(),
                                  .x_sum = x_sum_.data(),
                                  .v_sum = v_sum_.data()});
  constexpr Real w_next[4] = {0.5, 0.5, 1.0, 1.0};  // the last unused: that stage writes the result
  constexpr Real t_stage[4] = {0.0, 0.5, 0.5, 1.0};
  const bool clamps_move = !motions_.empty();
  if (clamps_move) ordered_sum_into(exec, n_, clamped_energy_term(), block_sums_, clamp_record);
  for (int k = 0; k < 4; ++k) {
    prescribe_clamps(exec, t + t_stage[k] * dt);
    evaluate(exec, t + t_stage[k] * dt);
    if (clamps_move) ordered_sum_into(exec, n_, clamp_power_term(), block_sums_, clamp_record + 1 + k);
    parallel_for(exec, n_,
                 RungeKuttaStage<D>{.n = n_,
                                    .x0 = x0_.data(),
                                    .v0 = v0_.data(),
                                    .acc = acc_.data(),
                                    .fixed = fixed_.data(),
                                    .x = x_.data(),
                                    .v = v_.data(),
                                    .x_sum = x_sum_.data(),
                                    .v_sum = v_sum_.data(),
                                    .dt = dt,
                                    .w_sum = kRk4Sum[k],
                                    .w_next = w_next[k],
                                    .last = k == 3});
  }
  prescribe_clamps(exec, t + dt);
  if (clamps_move) ordered_sum_into(exec, n_, clamped_energy_term(), block_sums_, clamp_record + 5);
}

template <int D>
Real* TlsphSolver<D>::clamp_record(int steps) {
  if (motions_.empty()) return nullptr;
  resize_for_overwrite(clamp_record_, 6 * static_cast<std::size_t>(steps));
  return clamp_record_.data();
}

// The clamps' work: the stages' powers by RK4's own quadrature, then the change of the clamped
// particles' kinetic energy, which the clamps also supply; added in the order of the steps.
template <int D>
void TlsphSolver<D>::add_clamp_work(int steps, Real dt) {
  if (motions_.empty()) return;
  for (int s = 0; s < steps; ++s) {
    const Real* record = clamp_record_.data() + 6 * s;
    for (int k = 0; k < 4; ++k) clamp_work_ += kRk4Sum[k] * dt * record[1 + k];
    clamp_work_ += record[5] - record[0];
  }
}

template <int D>
bool TlsphSolver<D>::replayable(Real t) const {
  // A graph replays fixed arguments: no ramping load, no moving clamp.
  bool fixed_arguments = use_graphs_ && motions_.empty();
  for (const auto& l : loads_) fixed_arguments = fixed_arguments && l.factor(t) == 1;
  return fixed_arguments;
}

template <int D>
void TlsphSolver<D>::step_rk4(const Exec& exec, Real t, Real dt, Real* clamp_record) {
  pair_evaluations_ += 4 * evaluation_passes() * static_cast<long long>(pairs());
  replayed_graph_ = false;
  if (exec.device == Device::cpu || exec.wait || !replayable(t)) {
    rk4_launches(exec, t, dt, clamp_record);
    return;
  }
  // The arrays stay in place from step to step; only the interaction field is allocated late (its
  // first set_interaction), and the obstacle candidates move when they outgrow their allocation.
  if (!graph_->recorded() || dt != recorded_dt_ || interaction_.data() != recorded_interaction_ ||
      contact_point_.data() != recorded_contact_point_ || contact_radius_.data() != recorded_contact_radius_) {
    graph_->synchronize();  // the stream is captured empty
    // By value: the debug device calls the recorded function again at each replay.
    graph_->record([this, t, dt](const Exec& capture) { rk4_launches(capture, t, dt, nullptr); });  // no clamp moves
    recorded_dt_ = dt;
    recorded_interaction_ = interaction_.data();
    recorded_contact_point_ = contact_point_.data();
    recorded_contact_radius_ = contact_radius_.data();
  }
  graph_->replay();
  replayed_graph_ = true;
}

template <int D>
void TlsphSolver<D>::step_verlet(Real t, Real dt) {
  const Exec exec = waiting_exec();
  if (!verlet_started_) {
    evaluate(exec, t);
    pair_evaluations_ += evaluation_passes() * static_cast<long long>(pairs());
    verlet_started_ = true;
  }
  const bool clamps_move = !motions_.empty();
  const Real clamped_energy = clamps_move ? clamped_kinetic_energy() : 0;
  if (clamps_move) clamp_work_ += 0.5 * dt * clamp_power();  // the trapezoidal rule, with the end's below
  parallel_for(
      exec, n_,
      VerletKickDrift<D>{
          .acc = acc_.data(), .fixed = fixed_.data(), .x = x_.data(), .v = v_.data(), .kick = 0.5 * dt, .drift = dt});
  prescribe_clamps(exec, t + dt);
  evaluate(exec, t + dt);
  pair_evaluations_ += evaluation_passes() * static_cast<long long>(pairs());
  parallel_for(
      exec, n_,
      VerletKickDrift<D>{
          .acc = acc_.data(), .fixed = fixed_.data(), .x = x_.data(), .v = v_.data(), .kick = 0.5 * dt, .drift = 0.0});
  if (clamps_move) clamp_work_ += 0.5 * dt * clamp_power() + clamped_kinetic_energy() - clamped_energy;
}

template <int D>
void TlsphSolver<D>::prescribe_clamps(const Exec& exec, Real t) {
  if (motions_.empty()) return;
  parallel_for(
      exec, n_,
      PrescribeClamps<D>{
          .motion = motion_.data(), .pose = poses_at(motions_, t), .X = X_.data(), .x = x_.data(), .v = v_.data()});
}

template <int D>
Index TlsphSolver<D>::first_runaway(Real limit) const {
  return first_particle(waiting_exec(), n_, RunawayParticle<D>{x_.data(), X_.data(), v_.data(), limit * limit});
}

template <int D>
Real TlsphSolver<D>::clamp_power() const {
  return ordered_sum(waiting_exec(), n_, clamp_power_term(), block_sums_);
}

template <int D>
Real TlsphSolver<D>::clamped_kinetic_energy() const {
  return ordered_sum(waiting_exec(), n_, clamped_energy_term(), block_sums_);
}

template <int D>
Mat<D> TlsphSolver<D>::cauchy_stress(Index a) const {
  const Mat<D>& F = F_[a];
  return (1.0 / determinant(F)) *
         (F * second_piola_stress(F, green_strain(F), materials_[material_[a]]) * transpose(F));
}

template <int D>
Real TlsphSolver<D>::kinetic_energy() const {
  return ordered_sum(waiting_exec(), n_, KineticEnergyTerm<D>{nullptr, mass_.data(), v_.data()}, block_sums_);
}

template <int D>
Real TlsphSolver<D>::strain_energy() const {
  return ordered_sum(waiting_exec(), n_, StrainEnergyTerm{volume_.data(), psi_.data()}, block_sums_);
}

template <int D>
typename TlsphSolver<D>::ObstacleContact TlsphSolver<D>::obstacle_contact() const {
  using Measure = typename ObstacleOverlap<D>::Measure;
  const auto overlap = [&](Measure m) {
    return ObstacleOverlap<D>{.obstacles = obstacles(),
                              .materials = materials_.data(),
                              .material = material_.data(),
                              .volume = volume_.data(),
                              .x = x_.data(),
                              .measure = m};
  };
  ObstacleContact c;
  c.energy = ordered_sum(waiting_exec(), n_, overlap(Measure::energy), block_sums_);
  c.deepest = parallel_reduce(waiting_exec(), n_, Real{0}, overlap(Measure::deepest), MaxOf{});
  c.pairs = static_cast<Index>(ordered_sum(waiting_exec(), n_, overlap(Measure::pairs), block_sums_));  // exact
  return c;
}

template <int D>
Real TlsphSolver<D>::potential_energy() const {
  return ordered_sum(waiting_exec(), n_, GravityEnergyTerm<D>{mass_.data(), gravity_, x_.data(), X_.data()},
                     block_sums_);
}

template <int D>
void TlsphSolver<D>::set_interaction(std::span<const Vec<D>> acc) {
  if (static_cast<Index>(acc.size()) != n_) throw std::invalid_argument("set_interaction: one value per particle");
  interaction_.resize(acc.size());  // allocated once, filled below: a recorded graph keeps addressing it
  // Velocity-Verlet's next opening kick reuses acc_, evaluated with the old field: it is moved to the new
  // field exactly, without a new evaluation. Values in ordinary host memory are copied on the host.
  parallel_for(exec_reading(acc.data()), n_,
               SetInteraction<D>{.from = nullptr,
                                 .to = acc.data(),
                                 .s = 0,
                                 .impedance = nullptr,
                                 .reference_velocity = nullptr,
                                 .v = nullptr,
                                 .interaction = interaction_.data(),
                                 .acc = verlet_started_ ? acc_.data() : nullptr});
}

template <int D>
void TlsphSolver<D>::set_obstacles(std::span<const Vec<D>> point, std::span<const Real> radius, Real reach) {
  if (point.size() != radius.size()) throw std::invalid_argument("set_obstacles: one radius per point");
  const Index m = static_cast<Index>(point.size());
  resize_for_overwrite(obstacle_point_, m);
  resize_for_overwrite(obstacle_radius_, m);
  parallel_for(exec_reading(point.data()), m, CopyElements<Vec<D>>{point.data(), obstacle_point_.data()});
  parallel_for(exec_reading(radius.data()), m, CopyElements<Real>{radius.data(), obstacle_radius_.data()});
  if (m > 0) obstacle_cells_.build(obstacle_point_.data(), m, reach);  // keeps addressing obstacle_point_
  find_obstacle_candidates();
}

template <int D>
void TlsphSolver<D>::find_obstacle_candidates() {
  const Exec exec = waiting_exec();
  const bool any = !obstacle_point_.empty();
  const CellListView<D> near = obstacle_cells_.view();
  parallel_for(
      exec, n_,
      CountObstacleCandidates<D>{
          .near = near, .any = any, .fixed = fixed_.data(), .x = x_.data(), .count = contact_offset_.data() + 1});
  inclusive_scan(exec, contact_offset_.data() + 1, n_);  // contact_offset_[0] stays 0
  const Index candidates = contact_offset_[n_];          // one value back from the device
  resize_for_overwrite(contact_point_, candidates);
  resize_for_overwrite(contact_radius_, candidates);
  parallel_for(exec, n_,
               FillObstacleCandidates<D>{.near = near,
                                         .any = any,
                                         .fixed = fixed_.data(),
                                         .x = x_.data(),
                                         .obstacle_radius = obstacle_radius_.data(),
                                         .offset = contact_offset_.data(),
                                         .point = contact_point_.data(),
                                         .radius = contact_radius_.data()});
}

template <int D>
void TlsphSolver<D>::save_state() {
  parallel_for(waiting_exec(), n_, CopyMotion<D>{x_.data(), v_.data(), saved_x_.data(), saved_v_.data()});
  saved_clamp_work_ = clamp_work_;
}

template <int D>
void TlsphSolver<D>::restore_state() {
  parallel_for(waiting_exec(), n_, CopyMotion<D>{saved_x_.data(), saved_v_.data(), x_.data(), v_.data()});
  clamp_work_ = saved_clamp_work_;
  // The state is repeated under another interaction field: Verlet's opening kick needs the
  // acceleration at the restored state with the current field, so it is evaluated afresh.
  verlet_started_ = false;
}

template <int D>
void TlsphSolver<D>::set_motion(std::span<const Vec<D>> x, std::span<const Vec<D>> v, std::span<const Vec<D>> acc) {
  std::copy(x.begin(), x.end(), x_.begin());
  std::copy(v.begin(), v.end(), v_.begin());
  std::copy(acc.begin(), acc.end(), acc_.begin());
  verlet_started_ = !acc.empty();
  update_stress();
}

template <int D>
Real TlsphSolver<D>::interaction_power() const {
  if (interaction_.empty()) return 0;
  return ordered_sum(waiting_exec(), n_, interaction_power_term(), block_sums_);
}

template <int D>
Real TlsphSolver<D>::external_power(Real t) const {
  Real p = 0;
  for (std::size_t l = 0; l < loads_.size(); ++l)  // load l's field is load_acc_[l n, (l + 1) n)
    p += ordered_sum(waiting_exec(), n_,
                     PowerTerm<D>{.clamped_by = nullptr,
                                  .mass = mass_.data(),
                                  .acc = load_acc_.data() + l * n_,
                                  .v = v_.data(),
                                  .factor = loads_[l].factor(t)},
                     block_sums_);
  return p;
}

template void tlsph_stress<2>(const Exec&, const TlsphView<2>&);
template void tlsph_stress<3>(const Exec&, const TlsphView<3>&);
template void tlsph_acceleration<2>(const Exec&, const TlsphView<2>&);
template void tlsph_acceleration<3>(const Exec&, const TlsphView<3>&);
template class TlsphSolver<2>;
template class TlsphSolver<3>;

}  // namespace isph
