// Compiled by nvcc when the CUDA backend is built (see ISPH_LOOP_SOURCES in CMakeLists.txt), so
// the stage functions below launch the same functors on either device.
#include "structure/tlsph.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/neighbour_search.hpp"
#include "kernels/operators.hpp"

namespace isph {

StructureIntegrator structure_integrator_from_name(const std::string& name) {
  if (name == "rk4") return StructureIntegrator::rk4;
  if (name == "verlet") return StructureIntegrator::verlet;
  throw std::invalid_argument("unknown structure integrator '" + name + "' (rk4 | verlet)");
}

template <int D>
void tlsph_stress(const Exec& exec, const TlsphView<D>& view) {
  parallel_for(exec, view.n, TlsphStress<D>{view});
}

template <int D>
void tlsph_acceleration(const Exec& exec, const TlsphView<D>& view) {
  parallel_for(exec, view.n, TlsphAcceleration<D>{view});
}

template <int D>
TlsphSolver<D>::TlsphSolver(TlsphSetup<D> s, Exec exec)
    : exec_(exec),
      n_(static_cast<Index>(s.X.size())),
      kernel_(s.kernel),
      integrator_(s.integrator),
      gravity_(s.gravity),
      damping_(s.damping),
      hourglass_(s.hourglass),
      materials_(std::move(s.materials)),
      loads_(std::move(s.loads)),
      X_(std::move(s.X)),
      v_(std::move(s.v)),
      volume_(std::move(s.volume)),
      material_(std::move(s.material)),
      fixed_(std::move(s.fixed)),
      motion_(std::move(s.motion)),
      motions_(std::move(s.motions)) {
  if (exec_.device != Device::cpu)
    throw std::runtime_error("the TLSPH time loop runs on the cpu device only in this version");
  if (loads_.size() > 8) throw std::invalid_argument("at most 8 loads are supported");
  x_ = X_;
  if (motion_.empty()) motion_.assign(n_, -1);
  acc_.assign(n_, Vec<D>::zero());
  mass_.resize(n_);
  for (Index a = 0; a < n_; ++a) {
    mass_[a] = materials_[material_[a]].density * volume_[a];
    if (fixed_[a]) v_[a] = Vec<D>::zero();
  }
  prescribe_clamps(0);  // the clamps' velocity at t = 0
  load_acc_.reserve(loads_.size() * n_);
  for (const auto& l : loads_) load_acc_.insert(load_acc_.end(), l.acc.begin(), l.acc.end());

  // Reference configuration: neighbours within the same body, the correction L (Eq. 35) and the
  // per-pair kernel gradients.
  const NeighbourList list = build_neighbour_list<D>(X_, kernel_.support(), s.body.data());
  nbr_offset_ = list.offset;
  nbr_ = list.index;
  grad_.resize(nbr_.size());
  cgrad_.resize(nbr_.size());
  hg_weight_.resize(nbr_.size());
  L_.resize(n_);
  if (s.correction)
    parallel_for(exec_, n_,
                 GradientCorrection<D>{{n_, X_.data(), volume_.data(), nbr_offset_.data(), nbr_.data(), kernel_}, L_.data()});
  else
    L_.assign(n_, Mat<D>::identity());
  for (Index a = 0; a < n_; ++a)
    for (Index k = nbr_offset_[a]; k < nbr_offset_[a + 1]; ++k) {
      const Index b = nbr_[k];
      const Vec<D> Xab = X_[a] - X_[b];
      grad_[k] = volume_[b] * kernel_.gradient(Xab);
      cgrad_[k] = L_[a] * grad_[k];
      hg_weight_[k] = volume_[b] * kernel_.value(std::sqrt(norm2(Xab))) / norm2(Xab);
    }
  // Hourglass control needs, per pair (a, b), the corrected gradient of the reverse pair (b, a),
  // and per particle the sum of its corrected gradients.
  rcgrad_.resize(nbr_.size());
  cgrad_sum_.assign(n_, Vec<D>::zero());
  for (Index a = 0; a < n_; ++a)
    for (Index k = nbr_offset_[a]; k < nbr_offset_[a + 1]; ++k) {
      const Index b = nbr_[k];
      cgrad_sum_[a] += cgrad_[k];
      const auto first = nbr_.begin() + nbr_offset_[b], last = nbr_.begin() + nbr_offset_[b + 1];
      rcgrad_[k] = cgrad_[std::find(first, last, a) - nbr_.begin()];  // the list is symmetric
    }
  F_.assign(n_, Mat<D>::identity());
  PL_.assign(n_, Mat<D>::zero());
  H_.assign(n_, Mat<D>::zero());
  psi_.assign(n_, 0);
  update_stress();
}

template <int D>
TlsphView<D> TlsphSolver<D>::view() {
  TlsphView<D> s{};
  s.n = n_;
  s.X = X_.data();
  s.nbr_offset = nbr_offset_.data();
  s.nbr = nbr_.data();
  s.grad = grad_.data();
  s.cgrad = cgrad_.data();
  s.hg_weight = hg_weight_.data();
  s.rcgrad = rcgrad_.data();
  s.cgrad_sum = cgrad_sum_.data();
  s.volume = volume_.data();
  s.H = H_.data();
  s.L = L_.data();
  s.material = material_.data();
  s.materials = materials_.data();
  s.fixed = fixed_.data();
  s.x = x_.data();
  s.v = v_.data();
  s.load_acc = load_acc_.data();
  s.loads = static_cast<int>(loads_.size());
  s.gravity = gravity_;
  s.interaction = interaction_.empty() ? nullptr : interaction_.data();
  s.damping = damping_;
  s.hourglass = hourglass_;
  s.F = F_.data();
  s.PL = PL_.data();
  s.psi = psi_.data();
  s.acc = acc_.data();
  return s;
}

template <int D>
Real TlsphSolver<D>::stable_dt(Real courant) const {
  Real c_max = 0;
  for (const auto& m : materials_) c_max = std::max(c_max, std::sqrt((m.lambda + 2 * m.mu) / m.density));
  return courant * kernel_.h / c_max;
}

template <int D>
void TlsphSolver<D>::update_stress() {
  tlsph_stress(exec_, view());
  pair_evaluations_ += (hourglass_ > 0 ? 2 : 1) * static_cast<long long>(pairs());
}

template <int D>
void TlsphSolver<D>::evaluate(Real t) {
  TlsphView<D> s = view();
  for (std::size_t l = 0; l < loads_.size(); ++l) s.load_factor[l] = loads_[l].factor(t);
  tlsph_stress(exec_, s);
  tlsph_acceleration(exec_, s);
  pair_evaluations_ += (hourglass_ > 0 ? 3 : 2) * static_cast<long long>(pairs());
}

template <int D>
void TlsphSolver<D>::step(Real t, Real dt) {
  if (integrator_ == StructureIntegrator::rk4)
    step_rk4(t, dt);
  else
    step_verlet(t, dt);
}

template <int D>
void TlsphSolver<D>::step_rk4(Real t, Real dt) {
  x0_ = x_;
  v0_ = v_;
  x_sum_ = x_;
  v_sum_ = v_;
  constexpr Real w_sum[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
  constexpr Real w_next[4] = {0.5, 0.5, 1.0, 1.0};
  constexpr Real t_stage[4] = {0.0, 0.5, 0.5, 1.0};
  for (int k = 0; k < 4; ++k) {
    prescribe_clamps(t + t_stage[k] * dt);
    evaluate(t + t_stage[k] * dt);
    parallel_for(exec_, n_,
                 RungeKuttaStage<D>{n_, x0_.data(), v0_.data(), acc_.data(), fixed_.data(), x_.data(), v_.data(),
                                    x_sum_.data(), v_sum_.data(), dt, w_sum[k], w_next[k]});
  }
  x_.swap(x_sum_);
  v_.swap(v_sum_);
  prescribe_clamps(t + dt);
}

template <int D>
void TlsphSolver<D>::step_verlet(Real t, Real dt) {
  if (!verlet_started_) {
    evaluate(t);
    verlet_started_ = true;
  }
  parallel_for(exec_, n_, VerletKickDrift<D>{acc_.data(), fixed_.data(), x_.data(), v_.data(), 0.5 * dt, dt});
  prescribe_clamps(t + dt);
  evaluate(t + dt);
  parallel_for(exec_, n_, VerletKickDrift<D>{acc_.data(), fixed_.data(), x_.data(), v_.data(), 0.5 * dt, 0.0});
}

template <int D>
void TlsphSolver<D>::prescribe_clamps(Real t) {
  if (motions_.empty()) return;
  for (Index a = 0; a < n_; ++a) {
    if (motion_[a] < 0) continue;
    x_[a] = motions_[motion_[a]].position(X_[a], t);
    v_[a] = motions_[motion_[a]].velocity(X_[a], t);
  }
}

template <int D>
Mat<D> TlsphSolver<D>::cauchy_stress(Index a) const {
  const Mat<D>& F = F_[a];
  return (1.0 / determinant(F)) * (F * svk_stress(F, materials_[material_[a]]) * transpose(F));
}

template <int D>
Real TlsphSolver<D>::kinetic_energy() const {
  Real e = 0;
#pragma omp parallel for reduction(+ : e)
  for (Index a = 0; a < n_; ++a) e += 0.5 * mass_[a] * norm2(v_[a]);
  return e;
}

template <int D>
Real TlsphSolver<D>::strain_energy() const {
  Real e = 0;
#pragma omp parallel for reduction(+ : e)
  for (Index a = 0; a < n_; ++a) e += volume_[a] * psi_[a];
  return e;
}

template <int D>
Real TlsphSolver<D>::potential_energy() const {
  Real e = 0;
#pragma omp parallel for reduction(+ : e)
  for (Index a = 0; a < n_; ++a) e -= mass_[a] * dot(gravity_, x_[a] - X_[a]);
  return e;
}

template <int D>
void TlsphSolver<D>::set_interaction(const std::vector<Vec<D>>& acc) {
  if (static_cast<Index>(acc.size()) != n_) throw std::invalid_argument("set_interaction: one value per particle");
  interaction_ = acc;
}

template <int D>
void TlsphSolver<D>::save_state() {
  saved_x_ = x_;
  saved_v_ = v_;
  saved_acc_ = acc_;
  saved_verlet_started_ = verlet_started_;
}

template <int D>
void TlsphSolver<D>::restore_state() {
  x_ = saved_x_;
  v_ = saved_v_;
  acc_ = saved_acc_;
  verlet_started_ = saved_verlet_started_;
}

template <int D>
Real TlsphSolver<D>::interaction_power() const {
  Real p = 0;
  if (interaction_.empty()) return p;
#pragma omp parallel for reduction(+ : p)
  for (Index a = 0; a < n_; ++a) p += mass_[a] * dot(interaction_[a], v_[a]);
  return p;
}

template <int D>
Real TlsphSolver<D>::external_power(Real t) const {
  Real p = 0;
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const Real f = loads_[l].factor(t);
    const auto& acc = loads_[l].acc;
#pragma omp parallel for reduction(+ : p)
    for (Index a = 0; a < n_; ++a) p += f * mass_[a] * dot(acc[a], v_[a]);
  }
  return p;
}

template void tlsph_stress<2>(const Exec&, const TlsphView<2>&);
template void tlsph_stress<3>(const Exec&, const TlsphView<3>&);
template void tlsph_acceleration<2>(const Exec&, const TlsphView<2>&);
template void tlsph_acceleration<3>(const Exec&, const TlsphView<3>&);
template class TlsphSolver<2>;
template class TlsphSolver<3>;

}  // namespace isph
