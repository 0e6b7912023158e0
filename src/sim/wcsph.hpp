#pragma once
// The weakly compressible comparator (seed 002, Zhang, Rezavand & Hu 2021): the same particles, walls,
// viscosity operator, probes and structure coupling as the ISPH model, with the pressure from an
// equation of state instead of a Poisson equation.
//
//   equation of state   p = c^2 (rho - rho0)                                              (Eq. 2)
//   continuity, momentum with a low-dissipation Riemann solver between particles      (Eqs. 3-4, 6)
//   viscosity           the ISPH model's renormalised Laplacian (ViscousAcceleration), held over an
//                       advection step (seed 002 §2.2 computes the viscous force there too)
//   walls, structures   pressure extrapolated from the fluid (Adami et al. 2012; wcsph_functors.hpp)
//
// Time stepping (seed 002 §2.2), selected by fluid.wcsph.time_stepping:
//   dual_criteria:    an advection step dt_ad = CFL_ad min(h/U, h^2/nu) (Eq. 9) rebuilds the neighbour
//                     list, reinitialises the density (Eqs. 11-12) and computes the viscous force; inside
//                     it, n = ceil(dt_ad/dt_ac) acoustic steps of equal length, dt_ac <= CFL_ac h/(c + U)
//                     (Eq. 10, CFL_ac = 0.6), reuse the list. The kernel values are evaluated at the
//                     current positions in every acoustic step: frozen with the list (as the seed keeps
//                     its "particle-interaction configuration"), they gave displaced particles no
//                     restoring force, and still water grew currents of 0.6 m/s within 1 s (measured);
//   single_criterion: the conventional scheme: every step is an acoustic step with CFL_ac = 0.25 that
//                     rebuilds the neighbour list, without density reinitialisation.
// U is the fastest fluid particle, at least the reference velocity (as in the ISPH model's Eq. 49), and
// c = fluid.wcsph.sound_speed, by default 10 U_max with U_max = 2 sqrt(g H) (seed 002 §3.1), i.e.
// sqrt(2) times the reference velocity sqrt(2 g H).
//
// Each acoustic step is a velocity-Verlet step (Eqs. 13-15) that evaluates the pressure force once:
//   v^{n+1/2} = v^n + dt/2 a^n;  r^{n+1} = r^n + dt v^{n+1/2};  rho^{n+1} = rho^n + dt drho/dt(v^{n+1/2});
//   boundary pressure; a^{n+1} = a(rho^{n+1}, v^{n+1/2});  v^{n+1} = v^{n+1/2} + dt/2 a^{n+1}.
// A coupled structure advances over each acoustic step under the pressure force of the step's start
// (an explicit, staggered coupling: the fluid's compressibility keeps it stable at these small steps).
#include <functional>
#include <span>
#include <vector>

#include "sim/particle_set.hpp"
#include "sim/wcsph_functors.hpp"

namespace isph {

template <int D>
class WcsphSolver final : public FluidModel<D> {
 public:
  explicit WcsphSolver(FluidSetup<D> setup);

  ParticleSet<D>& particles() override { return particles_; }
  const ParticleSet<D>& particles() const override { return particles_; }

  // One advection step (dual criteria) or one acoustic step (single criterion).
  Real time_step() const override;
  // Density, the pressure acceleration and the force on walls and structures (a restart's state).
  void add_snapshot_fields(const std::vector<Index>& slot, std::vector<SnapshotField>& fields) const override;
  void restore_fields(const SnapshotData& snapshot) override;

  // Called for every acoustic step [t, t + dt] before the fluid moves: a coupled structure advances and
  // hands its motion to the fluid (move_structure, set_structure_acceleration).
  using AcousticHook = std::function<void(Real t, Real dt)>;
  // Advances by dt (a time_step() or less).
  FluidStepReport step(Real dt, PhaseTimer& timer, const AcousticHook& hook = {});
  // That step with a structure advanced at each acoustic step (StructureCoupling::explicit_step), and its
  // contact with the fluid recorded after it.
  FluidStepReport step(Real t, Real dt, StructureCoupling<D>* structure, PhaseTimer& timer) override;
  // The time stepping's counts (summary.json performance.wcsph).
  void add_performance(JsonObject& performance) const override;

  // The pressure force per unit volume on the structure particles at the last force evaluation,
  // indexed as in the TLSPH solver, and its sum.
  Vec<D> structure_pressure_force(std::span<Vec<D>> force_density) const {
    return particles_.gather_structure_force(force_density);
  }
  // The fluid's impedance Z_s = -df_s/dv_s on each structure particle at the last force evaluation
  // (RiemannInteraction), indexed as in the TLSPH solver.
  void structure_impedance(std::span<Mat<D>> impedance) const;

  Real sound_speed() const { return sound_speed_; }
  long long advection_steps() const { return advection_steps_; }
  long long acoustic_steps() const { return acoustic_steps_; }

 private:
  // Neighbours, kernel cache, density reinitialisation (dual criteria) and the viscous force.
  void configure(Real dt, PhaseTimer& timer);
  // Boundary pressure, then the pressure force on every particle (acceleration_, boundary_force_).
  void evaluate_forces();
  // The pair interactions at the current state, without outputs: the caller sets the pass's.
  RiemannInteraction<D> riemann() const;
  void acoustic_step(Real dt, PhaseTimer& timer, const AcousticHook& hook);

  ParticleSet<D> particles_;
  Exec exec_;
  Real density_, viscosity_, reference_velocity_;
  SmoothingKernel<D> kernel_;  // the fluid's
  Vec<D> gravity_;
  FluidSpec settings_;
  // work arrays (they follow the particles)
  StateVector<Real> rho_, drho_dt_;
  StateVector<Vec<D>> acceleration_, viscous_;  // pressure acceleration (a^n of Verlet), viscous acceleration
  StateVector<Mat<D>> L_, Bhat_, grad_u_;
  StateVector<Mat<D>> impedance_;  // boundary particles' Z (with a structure only)
  Real sound_speed_, full_sum_;
  Real advection_courant_, acoustic_courant_, limiter_;
  bool dual_, kernel_correction_, forces_current_ = false;
  long long advection_steps_ = 0, acoustic_steps_ = 0;
};

}  // namespace isph
