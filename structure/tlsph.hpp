#pragma once
// The TLSPH structure solver: reference configuration (neighbours, kernel gradients and the
// correction L = K^{-T}, built once), the stress and acceleration loops, and the time
// integrators (classical RK4, Eqs. 43-45, and velocity-Verlet as the second-order scheme).
#include <string>
#include <vector>

#include "core/parallel.hpp"
#include "core/types.hpp"
#include "kernels/smoothing_kernel.hpp"
#include "sim/prescribed_motion.hpp"
#include "structure/tlsph_functors.hpp"

namespace isph {

enum class StructureIntegrator { rk4, verlet };
StructureIntegrator structure_integrator_from_name(const std::string& name);

// An applied load: a per-particle acceleration at full load, ramped linearly over ramp_time.
template <int D>
struct LoadField {
  std::vector<Vec<D>> acc;
  Real ramp_time = 0;
  Real factor(Real t) const { return ramp_time > 0 && t < ramp_time ? t / ramp_time : 1.0; }
};

template <int D>
struct TlsphSetup {
  std::vector<Vec<D>> X;        // reference positions
  std::vector<Vec<D>> v;        // initial velocities
  std::vector<Real> volume;
  std::vector<int> material;
  std::vector<int> body;        // particles interact only within their body
  std::vector<unsigned char> fixed;
  std::vector<Index> motion;    // clamped particles: index in `motions` (-1: the clamp stands still)
  std::vector<RigidMotion<D>> motions;
  std::vector<ElasticMaterial> materials;
  std::vector<LoadField<D>> loads;
  SmoothingKernel<D> kernel;
  bool correction = true;
  StructureIntegrator integrator = StructureIntegrator::rk4;
  Vec<D> gravity = Vec<D>::zero();
  Real damping = 0;
  Real hourglass = 0;
};

// The stress and acceleration loops as stages, so that tests and the device backend can call
// them on any view (host or device memory).
template <int D>
void tlsph_stress(const Exec& exec, const TlsphView<D>& view);
template <int D>
void tlsph_acceleration(const Exec& exec, const TlsphView<D>& view);

template <int D>
class TlsphSolver {
 public:
  TlsphSolver(TlsphSetup<D> setup, Exec exec = {});

  // Largest step for Courant number `courant`: courant * h / c_p, c_p the P-wave speed.
  Real stable_dt(Real courant) const;
  // Advances positions and velocities from t to t + dt with the chosen integrator.
  void step(Real t, Real dt);
  // Recomputes F, P and the strain energy at the current state (for output).
  void update_stress();
  // The fluid's interaction acceleration alpha(f->s) (Eq. 48), one per particle, added to the
  // acceleration until it is set again.
  void set_interaction(const std::vector<Vec<D>>& acc);
  // Power of the interaction acceleration on the current velocities.
  Real interaction_power() const;
  // Keeps the current state (positions, velocities, integrator state) and goes back to it, so that a
  // coupled step can be repeated with another interaction field.
  void save_state();
  void restore_state();

  Index size() const { return n_; }
  Index pairs() const { return static_cast<Index>(nbr_.size()); }
  long long pair_evaluations() const { return pair_evaluations_; }
  const std::vector<Vec<D>>& reference() const { return X_; }
  const std::vector<Vec<D>>& position() const { return x_; }
  const std::vector<Vec<D>>& velocity() const { return v_; }
  const std::vector<Mat<D>>& deformation_gradient() const { return F_; }
  const std::vector<unsigned char>& fixed() const { return fixed_; }
  Real density(Index a) const { return mass_[a] / volume_[a]; }
  const std::vector<Index>& neighbour_offset() const { return nbr_offset_; }
  const std::vector<Index>& neighbours() const { return nbr_; }
  // Cauchy stress sigma = F S F^T / det F of particle a (from the last update_stress()).
  Mat<D> cauchy_stress(Index a) const;

  Real kinetic_energy() const;
  Real strain_energy() const;                 // from the last update_stress()
  Real potential_energy() const;              // gravity, relative to the reference configuration
  Real external_power(Real t) const;          // power of the applied loads at time t
  TlsphView<D> view();                        // host view of the current state

 private:
  void evaluate(Real t);  // acc at the current (x, v)
  void step_rk4(Real t, Real dt);
  void step_verlet(Real t, Real dt);
  void prescribe_clamps(Real t);  // moving clamps: x and v at time t

  Exec exec_;
  Index n_ = 0;
  SmoothingKernel<D> kernel_;
  StructureIntegrator integrator_;
  Vec<D> gravity_;
  Real damping_, hourglass_;
  std::vector<ElasticMaterial> materials_;
  std::vector<LoadField<D>> loads_;
  std::vector<Vec<D>> load_acc_, interaction_;
  std::vector<Vec<D>> X_, x_, v_, acc_;
  std::vector<Real> volume_, mass_;
  std::vector<int> material_;
  std::vector<unsigned char> fixed_;
  std::vector<Index> motion_;
  std::vector<RigidMotion<D>> motions_;
  std::vector<Index> nbr_offset_, nbr_;
  std::vector<Vec<D>> grad_, cgrad_;
  std::vector<Real> hg_weight_;
  std::vector<Vec<D>> rcgrad_, cgrad_sum_;
  std::vector<Mat<D>> L_, F_, PL_, H_;
  std::vector<Real> psi_;
  std::vector<Vec<D>> x0_, v0_, x_sum_, v_sum_;  // integrator scratch
  bool verlet_started_ = false;
  std::vector<Vec<D>> saved_x_, saved_v_, saved_acc_;
  bool saved_verlet_started_ = false;
  long long pair_evaluations_ = 0;
};

}  // namespace isph
