#pragma once
// The coupled ISPH-TLSPH step (seed 001 Algorithm 1, §2.3). Structure particles are moving boundary
// particles of the fluid: their velocities enter the PPE source and their rows impose the pressure
// gradient rho (g - a_s) (PpeRowFill), so the pressure is continuous across the interface. The
// structure feels the fluid through alpha(f->s) (Eq. 48, structure/interaction.hpp), held constant over
// n_sub TLSPH substeps (RK4, Eqs. 43-45) that span the fluid step; the reference neighbour lists of
// TLSPH serve every substep (the reuse seed 002 makes of neighbour lists across inner steps).
//
// What the fluid sees of the structure is its motion over whole fluid steps: the velocity
// vbar^{n+1} = (x^{n+1} - x^n)/dt and the acceleration a_s = (vbar^{n+1} - vbar^n)/dt, so that the
// fluid at the interface moves by the structure's displacement in the step. Structural vibrations
// faster than the fluid step (the substeps resolve them) then barely reach the fluid. Handing it the
// end-of-step velocity and (v^{n+1} - v^n)/dt instead lets bending modes above the fluid step's
// Nyquist frequency alias into the pressure: the hydrostatic plate then grows a short-wave bending mode
// that flips sign every step, by 10-40 % per step (measured; docs/VALIDATION.md).
//
// Interface iterations. The fluid's pressure depends on a_s, and a_s on the pressure. Taking a_s from
// the previous step (a staggered scheme) is unstable when the fluid's added mass exceeds the
// structure's mass (Causin, Gerbeau & Nobile 2005, Comput. Methods Appl. Mech. Eng. 194:4506): the
// water column on the hydrostatic plate is 15 times heavier than the plate, and such a run blows up
// within ten steps. So each fluid step solves the fixed point a_s = H(a_s): H solves the PPE with a_s
// (only its right-hand side changes, and the solver keeps its set-up), computes alpha, runs the
// substeps from the start of the step and returns the a_s they produce. The iterates come from the
// interface quasi-Newton method IQN-ILS (Degroote, Bathe & Vierendeels 2009, Comput. Struct.
// 87:793): with residuals r = H(a) - a, the differences of r and of H(a) between iterations (of this
// step and of the last `reuse_steps` steps) form V and W, and
//   a_{k+1} = H(a_k) + W c,   c = argmin |V c + r_k|   (least squares, column-pivoted QR);
// the first iterate of a run, without any columns, is relaxed: a_1 = a_0 + 0.1 r_0. When |r| grows from
// one iteration to the next, the reused columns of earlier steps are dropped: at the Walhorn obstacle's
// impact they led the iterations astray (12 steps without convergence, then non-finite values). The
// iterations stop
// when |r| <= tolerance max(|H(a)|, |g| sqrt(N)) (norms over the N structure particles).
// coupling.max_iterations = 1 gives the staggered scheme.
//
// With the structure's inertia in its PPE rows (coupling.implicit_added_mass, the default; PpeRowFill)
// the pressure already answers the structure's acceleration, and the iterate is only the part a~_s the
// pressure does not give, along each row's direction (structure_row_directions): its first value is
// predicted from the step's start (ChordPrediction). The staggered scheme then holds under heavy water,
// and the shipped FSI cases stop after two iterations, whose second iterate comes from the columns of
// earlier steps; |r| / |a_s| at each step's end is reported (mean/max_interface_residual), and the tip
// and deflection histories stay within 0.13 mm and 1.5 % of converged iterations (docs/VALIDATION.md
// section 12). A restart therefore carries the columns (add_snapshot_fields).
//
// alpha over the substeps: "held" (default) applies the iterate's alpha, the pressure of the step's end,
// to every substep; "interpolated" ramps it linearly from the last step's converged alpha, substep k
// getting alpha^n + (k + 1/2)/n_sub (alpha^{n+1} - alpha^n). The ramp makes alpha^n two thirds of the
// load in the step's chord displacement, and that share of the added mass acts explicitly: a mode whose
// added mass exceeds three times its own mass then flips sign every fluid step and grows
// (docs/VALIDATION.md section 12, with the model and the measured growth).
// The interaction's work over a substep is the trapezoidal rule on the power of that substep's field at
// its two ends (TlsphSolver::advance; on the device the substeps and their powers are queued, and the
// host waits once per fluid step and interface iteration).
//
// The fluid's shear on the structure (ViscousBoundaryForce) is part of alpha, computed with the velocities
// at the step's start; held, it lags the structure's own motion by a step, and FSI1's bar at D/10 shook
// along its axis with it (docs/VALIDATION.md section 36). Where Gamma_s dt exceeds kShearRate somewhere,
// the substeps therefore take alpha - Gamma_s (v - vbar^n), Gamma_s = Z_s / rho_s its resistance.
//
// The weakly compressible model (sim/wcsph.hpp) couples explicitly instead (explicit_step): over each
// of its acoustic steps the structure feels the pressure force of the step's start, held over the
// substeps, and the fluid sees the structure's chord velocity; at those small steps the fluid's
// compressibility keeps the staggered scheme stable. The structure's acceleration is not handed to the
// fluid (its boundary pressure takes g alone): in the boundary pressure of Adami et al. it closes an
// explicit added-mass loop, and the gate blew up within 5 ms with it (measured, 2026-11-22).
// One part of the force is not held: the Riemann solver's dissipation, a resistance Z_s to the
// structure particle's velocity relative to the fluid (RiemannInteraction). Held, it acts one acoustic
// step late on a velocity the substeps have since changed; the structure's particle-scale modes, faster
// than the acoustic step, then gain energy from it (the elastic gate's grew from 0.09 s at every acoustic
// Courant number down to 0.15, and from 0.02 s with the full dissipation; it held at 0.05). So each
// substep's field is alpha_s - Gamma_s (v_s - w_s), Gamma_s = Z_s / rho_s, w_s the chord velocity the
// force was evaluated with: the resistance acts on the substeps' own velocity, stable while
// Gamma_s dt_s is small (docs/VALIDATION.md section 20).
//
// Structure-wall contact (coupling.wall_contact): the fluid's wall particles are the TLSPH solver's
// obstacles (gathered once for fixed walls, at the start of every fluid step where walls move, and held
// over its substeps); at the start of each fluid step every structure particle takes those within the
// kernel support as its candidates, and those that overlap them are pushed
// out by a penalty of the structure's own stiffness (for_each_wall_overlap, structure/tlsph_functors.hpp).
// Without it nothing stops a structure laid on a wall from passing through it (the fluid's pressure
// stops only fluid). The penalty's stored energy is counted with the structure's strain energy.
//
// n_sub comes from the structure's own stability limit each fluid step, ceil(dt / dt_s) with
// dt_s = courant h / c_p, or is fixed by coupling.substeps (the seed's fixed ratio, for comparison).
#include <string>
#include <vector>

#include "io/case.hpp"
#include "io/output.hpp"
#include "sim/interface_quasi_newton.hpp"
#include "sim/isph.hpp"
#include "sim/phase_timer.hpp"
#include "sim/wcsph.hpp"
#include "structure/interaction.hpp"
#include "structure/tlsph.hpp"

namespace isph {

template <int D>
class StructureCoupling {
 public:
  // On the cuda device the structure steps there, and the arrays the fluid's loops read are in managed memory.
  StructureCoupling(TlsphSetup<D> setup, const CouplingSpec& coupling, Real courant, Vec<D> gravity,
                    Device device = Device::cpu);

  // One coupled step from t to t + dt: the fluid step with the interface iterations inside it.
  FluidStepReport step(Real t, Real dt, IsphSolver<D>& fluid, PhaseTimer& timer);
  // One explicit step from t to t + dt under the fluid's last pressure force; the structure's motion
  // over the step goes to the fluid (positions, chord velocity, normals).
  void explicit_step(Real t, Real dt, WcsphSolver<D>& fluid, PhaseTimer& timer);
  // Penetration diagnostics after a fluid step.
  void record_contact(ParticleSet<D>& fluid, PhaseTimer& timer);

  // Continues from a snapshot (after fluid.restore): the structure's positions and the fluid's view of
  // its velocity (the chord velocity) from the fluid particles, and from the snapshot's fields
  // "structure_velocity", "structure_acceleration" and "structure_interaction" TLSPH's own velocity,
  // the last step's a_s and interaction acceleration, the start of the next interface iterations, with
  // the quasi-Newton columns of the earlier steps ("interface_columns"). A snapshot without the first
  // three (written before they existed) gives TLSPH the chord velocity and the iterations a zero
  // start; returns false then.
  bool restore(const SnapshotData& snapshot, ParticleSet<D>& fluid);
  // What a restart needs besides the fluid's fields, per structure particle of the fluid (in the
  // order of `slot`, zero on other particles): TLSPH's velocity, the last step's a_s and interaction,
  // and the quasi-Newton columns.
  void add_snapshot_fields(const ParticleSet<D>& fluid, const std::vector<Index>& slot,
                           std::vector<SnapshotField>& fields) const;
  // The scalars a restart needs: the interaction and clamp work, and how the quasi-Newton columns
  // divide into steps.
  void add_snapshot_attributes(SnapshotAttributes& attributes) const;

  const TlsphSolver<D>& solver() const { return solver_; }
  long long substeps() const { return substeps_; }
  // Iterations, substeps, penetration, distances and the force on the structure, for summary.json.
  JsonObject summary() const;
  // A warning where the interface iterations ended, on average over the steps, further from converged
  // than the structure's acceleration is large (mean |H(a) - a| / |a_s| above 1): the load the structure
  // felt is then not the water's (docs/VALIDATION.md section 25); empty otherwise.
  std::string convergence_warning() const;

 private:
  // Runs the substeps across [t, t + dt] under the schedule's interaction fields; returns their count and
  // adds the interaction work to `work`.
  int substep(Real t, Real dt, Real& work, InteractionSchedule<D> schedule);
  // alpha(f->s) = f_s / rho_s (Eq. 48) from force_density_, handed to the TLSPH solver.
  void set_interaction();
  // The shear's Gamma_s into impedance_, from the fluid's predictor; whether it matters over a step of
  // dt: the largest Gamma_s dt above kShearRate (the shipped gate's water, nu = 1e-6, stays below it).
  static constexpr Real kShearRate = 1e-3;
  bool set_shear_impedance(const ParticleSet<D>& fluid, Real dt);
  // beta of the structure rows (PpeRowFill): 1/2 under a held alpha, 1/6 under a ramped one (the share
  // of alpha^{n+1} in the chord displacement), 0 without coupling.implicit_added_mass.
  Real added_mass_factor() const;
  // The step's start for the interface iterations: the structure's state saved, the rows' directions,
  // and the first iterate predicted from the chord (ChordPrediction). Returns it, and in `floor` the
  // residual's floor, |g| on every wetted particle.
  Eigen::VectorXd predict_interface(Real t, Real dt, Real beta, IsphSolver<D>& fluid, PhaseTimer& timer, Real& floor);
  // The fluid's wall particles as the TLSPH solver's obstacles, and each structure particle's candidates.
  void set_obstacles(const ParticleSet<D>& fluid);
  // The deepest structure-wall overlap at the step's end, for summary().
  void record_overlap();
  // The interface residual at the steps' ends, averaged over the steps (0 before the first).
  Real mean_residual() const { return steps_ > 0 ? residual_sum_ / steps_ : 0.0; }
  // The step's totals for summary(): interaction work, force, substeps, interface iterations.
  void account_step(Real work, const Vec<D>& force, int count, int iterations);
  // The quasi-Newton columns of a snapshot (row: the snapshot's row of each stable id).
  void restore_quasi_newton(const SnapshotData& snapshot, const ParticleSet<D>& fluid,
                            const std::vector<long long>& row);

  Exec exec_;  // the structure's device, waiting for each launch
  TlsphSolver<D> solver_;
  CouplingSpec spec_;
  Real stable_dt_, g_norm_;
  StateVector<Vec<D>> force_density_, interaction_, a_guess_, a_new_, x_old_, v_new_, v_mean_;
  StateVector<Vec<D>> row_direction_, a_rows_;  // each structure row's direction, and the iterate along it
  StateVector<Vec<D>> own_acceleration_;        // the structure's own acceleration at a step's start (ChordPrediction)
  StateVector<Vec<D>> last_interaction_;        // alpha^n (interpolated)
  StateVector<Mat<D>> impedance_;               // the fluid's Gamma_s = Z_s / rho_s (explicit_step; step: the shear's)
  StateVector<Real> shear_rate_;                // the fluid's shear's Gamma_s (step; set_shear_impedance)
  bool interpolate_;
  bool has_last_interaction_ = false;
  StateVector<Real> density_, inverse_density_;
  InterfaceQuasiNewton quasi_newton_;
  long long steps_ = 0, substeps_ = 0, iterations_ = 0, unconverged_ = 0;
  int max_substeps_ = 0, max_iterations_seen_ = 0;
  Real residual_sum_ = 0, max_residual_ = 0;  // the interface residual at each ISPH step's end
  ContactRecord<D> contact_;                  // fluid inside the structure, step by step
  StateVector<Vec<D>> wall_point_;            // the fluid's wall particles as obstacles (set_obstacles)
  StateVector<Real> wall_radius_;
  bool walls_gathered_ = false;  // the fixed walls are the solver's obstacles
  Real max_wall_overlap_ = 0;
  long long steps_with_wall_contact_ = 0;
  Vec<D> force_sum_ = Vec<D>::zero();  // sum over steps of the force on the structure, for its mean
  Real interaction_work_ = 0;
};

}  // namespace isph
