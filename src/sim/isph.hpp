#pragma once
// The ISPH fluid solver: one projection step of seed 001 §2.1 (Algorithm 1, fluid part) over a
// particle set of fluid, wall and structure particles (structures are moving boundaries here; their
// dynamics is TLSPH's, structure/). The step reads like the algorithm; every particle loop
// is a functor (sim/fluid_functors.hpp, poisson/, shifting/) run by the common launcher.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "poisson/free_surface.hpp"
#include "poisson/linear_solver.hpp"
#include "shifting/particle_shifting.hpp"
#include "sim/particle_set.hpp"

namespace isph {

template <int D>
class IsphSolver final : public FluidModel<D> {
 public:
  explicit IsphSolver(FluidSetup<D> setup);

  ParticleSet<D>& particles() override { return particles_; }
  const ParticleSet<D>& particles() const override { return particles_; }

  // Eq. 49 with the fluid's fastest particle (at least the reference velocity), the viscous limit
  // viscous_number h^2 / nu_max, and max_dt.
  Real time_step() const override;
  // Pressure-solve fields: surface class, div r and the last shift.
  void add_snapshot_fields(const std::vector<Index>& slot, std::vector<SnapshotField>& fields) const override;

  // One projection step of length dt: predictor, free surface, PPE, projection, shifting.
  FluidStepReport step(Real dt, PhaseTimer& timer);
  // That step, or with a structure the coupled step that iterates on the interface (StructureCoupling::step).
  FluidStepReport step(Real t, Real dt, StructureCoupling<D>* structure, PhaseTimer& timer) override;
  std::string pressure_solver() const override { return solver_name_; }
  // The same step in three parts, for the coupled step, which solves the PPE again after changing the
  // structure's acceleration (set_structure_acceleration):
  //   begin_step: drift to r*, neighbours, predictor, free surface, PPE assembly;
  //   solve_pressure: the PPE (the pressure is kept only when a solver converged), to the case's
  //                   tolerance or, where `tolerance` > 0, to that one (an interface iteration's interim
  //                   pressure);
  //   end_step: projection, position update, shifting.
  void begin_step(Real dt, PhaseTimer& timer);
  void solve_pressure(FluidStepReport& report, PhaseTimer& timer, double tolerance = 0);
  void end_step(Real dt, PhaseTimer& timer);

  const StateVector<SurfaceClass>& surface_class() const { return cls_; }
  const StateVector<Real>& position_divergence() const { return div_r_; }
  const StateVector<Vec<D>>& shift() const { return shift_; }
  const std::string& ppe_solver_name() const { return solver_name_; }
  // After begin_step: the assembled PPE (zeros dropped, columns sorted) and its right-hand side; the
  // pressure of the last step is the solve's start (bench/ppe_capture.cpp writes the three).
  const CsrMatrix& ppe_matrix() const { return matrix_; }
  std::span<const double> ppe_rhs() const { return {rhs_.data(), rhs_.size()}; }

  // The structure's acceleration over the current step in the PPE rows of structure particles (g - a_s,
  // PpeRowFill): a_s itself, or with the structure's inertia in the rows, the part a~_s of it that the
  // pressure does not give. Between begin_step and solve_pressure it updates the assembled right-hand side.
  void set_structure_acceleration(std::span<const Vec<D>> a);
  // After begin_step: the direction of each structure particle's PPE row moment (TLSPH's indexing; zero
  // for a dry particle, whose row is p = 0). The rows read the structure's acceleration only along it.
  void structure_row_directions(std::span<Vec<D>> direction) const;
  // The structure's inertia in its PPE rows from the next begin_step on (PpeRowFill): 1/rho_s per
  // structure particle (TLSPH's indexing; device-visible on the cuda device; kept by pointer) and the
  // chord acceleration's response beta to the pressure force; beta = 0 leaves it out.
  void set_structure_inertia(std::span<const Real> inverse_density, Real beta) {
    structure_inverse_density_ = inverse_density.data();
    added_mass_ = beta;
  }
  // After solve_pressure: the pressure force per unit volume on the structure particles (Eq. 48 times
  // rho_s, or its pairwise form), indexed as in the TLSPH solver, and its sum (the force on the structure).
  Vec<D> structure_pressure_force(std::span<Vec<D>> force_density);

 private:
  // The stages of begin_step and end_step (docs: the equations at each definition).
  void drift_and_find_neighbours(Real dt);
  void predict_velocity(const FluidView<D>& v, Real dt);
  Index detect_free_surface(const FluidView<D>& v, const FluidView<D>& pv);
  void assemble_ppe(const FluidView<D>& pv, Real dt, Index pinned);
  void project_and_advance(const FluidView<D>& v, const FluidView<D>& pv, Real dt);
  void shift_particles(const FluidView<D>& pv, Real dt);
  void compress_matrix();
  MatrixReuse matrix_reuse() const;
  std::span<const Index> rows_since_setup(MatrixReuse reuse);
  // Keeps the particles' order and rows at the preconditioner's set-up, by stable id.
  void remember_setup_rows();
  // p_trial_ = p_, the solver's start (the last pressure), copied where the particles are.
  void warm_start();
  // The pressure force per unit volume on the boundary particles of one kind, into boundary_force_.
  void boundary_pressure_force(bool pairwise, FluidKind target);

  ParticleSet<D> particles_;
  Exec exec_;
  Real density_, viscosity_, reference_velocity_;
  SmoothingKernel<D> kernel_;  // the fluid's
  Vec<D> gravity_;
  FluidSpec settings_;
  // work arrays (in managed memory on the cuda device, like the state; they follow the particles)
  StateVector<Vec<D>> x_old_, u_star_, u_new_, u_collided_, grad_p_, surface_normal_, shift_;
  StateVector<Mat<D>> L_, Bhat_, grad_u_;
  StateVector<Real> div_r_, alpha_, div_u_star_, eddy_viscosity_, pressure_volume_;
  StateVector<SurfaceClass> detected_, cls_;
  StateVector<Vec<D>> wall_moment_;
  StateVector<Mat<D>> L_structure_;
  StateVector<double> rhs_, p_trial_, block_sums_, box_totals_;  // the last two: a closed box's source sums
  CsrMatrix full_matrix_, matrix_;                               // as assembled; without zeros, columns sorted

  int solves_since_assembly_ = 0;  // PPE solves with the assembled matrix (the later ones reuse its set-up)
  // The preconditioner kept across steps (matrix_reuse): steps since its set-up, the particle order it
  // was built for and each particle's row then (by id), the iterations of the first solve with it and of
  // the last step's first solve; row_origin_: rows_since_setup()'s answer.
  int preconditioner_age_ = 0, setup_iterations_ = 0, last_first_iterations_ = 0;
  long long preconditioner_order_ = -1;
  StateVector<Index> setup_row_of_id_, row_origin_;
  const Real* structure_inverse_density_ = nullptr;  // set_structure_inertia
  Real added_mass_ = 0;
  bool kernel_correction_;
  SurfaceThresholds thresholds_;
  Real full_kernel_sum_;  // FluidView::kernel_sum on a regular lattice (PpeRowFill's density term)
  ShiftingType shifting_;
  bool extrapolate_surface_;
  bool fsi_shifting_;
  FsiLayerLaw fsi_shifting_law_;
  bool pairwise_force_;
  bool wall_force_;     // FluidSetup::wall_force
  bool wall_friction_;  // FluidSetup::wall_friction
  std::unique_ptr<LinearSolver> solver_, fallback_;
  std::string solver_name_;
};

}  // namespace isph
