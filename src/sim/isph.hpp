#pragma once
// The ISPH fluid solver: one projection step of seed 001 §2.1 (Algorithm 1, fluid part) over a
// particle set of fluid, wall and structure particles (structures are moving boundaries here; their
// dynamics is TLSPH's, structure/). The step reads like the algorithm; every particle loop
// is a functor (sim/fluid_functors.hpp, poisson/, shifting/) run by the common launcher.
#include <memory>
#include <string>
#include <vector>

#include "core/neighbour_search.hpp"
#include "io/case.hpp"
#include "kernels/smoothing_kernel.hpp"
#include "poisson/free_surface.hpp"
#include "poisson/linear_solver.hpp"
#include "shifting/particle_shifting.hpp"
#include "sim/phase_timer.hpp"
#include "sim/prescribed_motion.hpp"

namespace isph {

// Everything the solver needs, built by build_scene (sim/scene.cpp).
template <int D>
struct FluidSetup {
  std::vector<Vec<D>> x, u;
  std::vector<Real> volume;
  std::vector<FluidKind> kind;
  std::vector<Vec<D>> wall_velocity;  // prescribed velocity (walls), zero for fluid
  std::vector<Vec<D>> wall_normal;    // walls, structures: unit normal into the fluid (zero when deep inside)
  std::vector<Real> wall_depth;       // walls, structures: distance below the surface
  std::vector<Index> structure_index; // structure particles: index in the TLSPH solver; -1 for others
  std::vector<Index> id;              // stable id (output order)
  std::vector<Index> motion;          // walls: index in `motions`; -1 for fixed walls and the others
  std::vector<RigidMotion<D>> motions;  // prescribed motions of wall bodies
  Real density = 0;
  Real viscosity = 0;                 // kinematic [m^2/s]
  Real dx = 0;
  SmoothingKernel<D> kernel;
  bool kernel_correction = true;
  Periodicity<D> period;
  Vec<D> gravity = Vec<D>::zero();
  Real reference_velocity = 0;        // floor on U in Eq. 49 (resolved from the case)
  FluidSpec settings;
  bool fsi_shifting = true;           // the FSI shifting layer (Eqs. 27-30)
  std::string interaction_force = "pairwise";  // pairwise | gradient (Eq. 48 literally; structure/interaction.hpp)
};

// Penetration diagnostics of a coupled step (structure/interaction.hpp).
template <int D>
struct InteractionReport {
  Index fluid_inside = 0;                // fluid particles inside a structure
  Real min_distance = 0;                 // smallest fluid-structure particle distance (inf: none in reach)
};

struct FluidStepReport {
  SolveReport ppe;
  std::string ppe_solver;  // the backend that produced the pressure
  bool ppe_failed = false; // no backend converged
};

template <int D>
class IsphSolver {
 public:
  explicit IsphSolver(FluidSetup<D> setup);

  // Eq. 49 with the fluid's fastest particle (at least the reference velocity), the viscous limit
  // viscous_number h^2 / nu_max, and max_dt.
  Real time_step() const;

  // One projection step of length dt: predictor, free surface, PPE, projection, shifting.
  FluidStepReport step(Real dt, PhaseTimer& timer);
  // The same step in three parts, for the coupled step, which solves the PPE again after changing the
  // structure's acceleration (set_structure_acceleration):
  //   begin_step: drift to r*, neighbours, predictor, free surface, PPE assembly;
  //   solve_pressure: the PPE (the pressure is kept only when a solver converged);
  //   end_step: projection, position update, shifting.
  void begin_step(Real dt, PhaseTimer& timer);
  void solve_pressure(FluidStepReport& report, PhaseTimer& timer);
  void end_step(Real dt, PhaseTimer& timer);

  Index size() const { return static_cast<Index>(x_.size()); }
  Index fluid_count() const { return fluid_count_; }
  Index wall_count() const { return wall_count_; }
  const std::vector<Vec<D>>& position() const { return x_; }
  const std::vector<Vec<D>>& velocity() const { return u_; }
  const std::vector<Real>& pressure() const { return p_; }
  const std::vector<FluidKind>& kind() const { return kind_; }
  const std::vector<Index>& id() const { return id_; }
  const std::vector<Index>& structure_index() const { return structure_index_; }  // -1: not a structure particle
  const std::vector<SurfaceClass>& surface_class() const { return cls_; }
  const std::vector<Real>& position_divergence() const { return div_r_; }
  const std::vector<Vec<D>>& shift() const { return shift_; }
  const std::string& ppe_solver_name() const { return solver_name_; }
  Real time() const { return time_; }
  // Work done on the fluid by the moving walls' pressure, integrated over the steps (their viscous
  // traction is not counted).
  Real wall_work() const { return wall_work_; }

  Real kinetic_energy() const;
  Real potential_energy() const;  // -sum m g · x
  Real max_speed() const;         // fastest fluid particle
  // Shepard (kernel-normalised) interpolation at a point: pressure over fluid and wall particles,
  // velocity over fluid particles. Zero where no particle is in reach.
  Real interpolate_pressure(const Vec<D>& point) const;
  Vec<D> interpolate_velocity(const Vec<D>& point) const;
  // Largest x of the fluid particles below `height` on the vertical axis (D - 1); -inf if none.
  Real front(Real height) const;
  // First fluid particle with a non-finite position, velocity or pressure, or -1.
  Index first_non_finite() const;

  // Structure particles follow the TLSPH solver: positions, velocities and deformation gradients,
  // indexed as in the TLSPH solver. The surface normals turn with F: n = F^{-T} N / |F^{-T} N|.
  void move_structure(const std::vector<Vec<D>>& x, const std::vector<Vec<D>>& v, const std::vector<Mat<D>>& F);
  // The structure's acceleration over the current step, a_s in the PPE rows of structure particles
  // (g - a_s, PpeRowFill); between begin_step and solve_pressure it updates the assembled right-hand side.
  void set_structure_acceleration(const std::vector<Vec<D>>& a);
  // After solve_pressure: the pressure force per unit volume on the structure particles (Eq. 48 times
  // rho_s, or its pairwise form), indexed as in the TLSPH solver, and its sum (the force on the structure).
  Vec<D> structure_pressure_force(std::vector<Vec<D>>& force_density);
  // Fluid particles inside a structure, and the smallest fluid-structure particle distance (inf if none
  // is within the kernel support).
  InteractionReport<D> structure_contact();

 private:
  FluidView<D> view() const;
  void find_neighbours();
  void sort_by_cell();
  void compress_matrix();
  void prescribe_walls(Real dt);
  Real moving_wall_power();

  // particle state (permuted together by sort_by_cell)
  std::vector<Vec<D>> x_, u_;
  std::vector<Real> p_, volume_, wall_depth_;
  std::vector<FluidKind> kind_;
  std::vector<Vec<D>> wall_velocity_, wall_acceleration_, wall_normal_, reference_normal_;
  std::vector<Index> id_, structure_index_, motion_;
  std::vector<Vec<D>> reference_x_;  // initial positions (moving walls follow their motion from them)
  // work arrays
  std::vector<Vec<D>> x_old_, u_star_, u_new_, grad_p_, surface_normal_, shift_;
  std::vector<Mat<D>> L_, Bhat_, grad_u_;
  std::vector<Real> div_r_, alpha_, div_u_star_, eddy_viscosity_, pressure_volume_;
  std::vector<SurfaceClass> detected_, cls_;
  std::vector<Vec<D>> wall_moment_, boundary_force_;
  std::vector<Mat<D>> L_structure_;
  std::vector<unsigned char> inside_;
  std::vector<Real> structure_distance_;
  std::vector<double> rhs_, p_trial_;
  CsrMatrix full_matrix_, matrix_;  // as assembled; without zeros, columns sorted
  CellList<D> cells_;
  NeighbourList neighbours_;

  Index fluid_count_ = 0, wall_count_ = 0;
  long long steps_ = 0;
  Real time_ = 0, wall_work_ = 0;
  std::vector<RigidMotion<D>> motions_;
  int solves_since_assembly_ = 0;  // PPE solves with the assembled matrix (the later ones reuse its set-up)
  Real density_, viscosity_, dx_, reference_velocity_;
  SmoothingKernel<D> kernel_;
  bool kernel_correction_;
  Periodicity<D> period_;
  Vec<D> gravity_;
  FluidSpec settings_;
  SurfaceThresholds thresholds_;
  ShiftingType shifting_;
  bool extrapolate_surface_;
  bool fsi_shifting_;
  bool pairwise_force_;
  bool has_structure_;
  std::unique_ptr<LinearSolver> solver_, fallback_;
  std::string solver_name_;
  Exec exec_{};
};

ShiftingType shifting_type_from_name(const std::string& name);

}  // namespace isph
