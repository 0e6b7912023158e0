#pragma once
// The probes of probes.csv (docs/CASES.md, "Probes"), each an observer of the run: it names its
// columns, samples its values at every record and, where it accumulates over the steps between two
// records (the force probes' interval means), follows each step and keeps its sums in the snapshots so
// that a restart writes the rows the uninterrupted run would. The time loops (sim/run_fluid.cpp,
// sim/run_structure.cpp) hold one ProbeSet and know no probe type.
//
// Also the samplers of the fluid the probes and the energy books read: Shepard interpolation, the surge
// front, the water level and the fluid's energies (serial host loops: they run at records only).
#include <memory>
#include <string>
#include <vector>

#include "io/output.hpp"
#include "sim/particle_set.hpp"
#include "sim/scene.hpp"
#include "structure/tlsph.hpp"

namespace isph {

// Kinetic energy of the fluid particles, sum m |u|^2 / 2.
template <int D>
Real fluid_kinetic_energy(const ParticleSet<D>& p);
// Potential energy of the fluid particles in gravity, -sum m g . x.
template <int D>
Real fluid_potential_energy(const ParticleSet<D>& p);
// Shepard (kernel-normalised) interpolation at a point, with each particle's kernel against the
// fluid's (the coarser, KernelTable): pressure over fluid and wall particles, velocity over fluid
// particles. Zero where no particle is in reach.
template <int D>
Real interpolate_pressure(const ParticleSet<D>& p, const Vec<D>& point);
template <int D>
Vec<D> interpolate_velocity(const ParticleSet<D>& p, const Vec<D>& point);
// The pressure of the row that stands for TLSPH particle `structure` (its PPE pressure).
template <int D>
Real structure_pressure(const ParticleSet<D>& p, Index structure);
// Largest x of the fluid particles below `height` on the vertical axis (D - 1); -inf if none.
template <int D>
Real surge_front(const ParticleSet<D>& p, Real height);
// The water surface on the vertical line through `point`: the highest height, not below point's, at
// which the fluid fills half of the kernel, sum_b V_b W(|z - x_b|) = 1/2 (docs/CASES.md, probes).
// point's own height where no water reaches the line.
template <int D>
Real water_level(const ParticleSet<D>& p, const Vec<D>& point);

template <int D>
class Probe {
 public:
  virtual ~Probe() = default;
  virtual void add_columns(std::vector<std::string>& columns) const = 0;
  virtual void sample(std::vector<double>& row) = 0;
  // After each fluid step of length dt.
  virtual void after_step(Real /*dt*/) {}
  // What a restart needs to continue the probe, into and out of a snapshot's attributes.
  virtual void save(SnapshotAttributes& /*attributes*/) const {}
  virtual void restore(const SnapshotData& /*state*/) {}
};

// The probes of a run, in the order of their columns.
template <int D>
class ProbeSet {
 public:
  void add(std::unique_ptr<Probe<D>> probe) { probes_.push_back(std::move(probe)); }
  std::vector<std::string> columns() const;
  // The row of probes.csv at time t.
  std::vector<double> sample(double t);
  void after_step(Real dt);
  void save(SnapshotAttributes& attributes) const;
  void restore(const SnapshotData& state);

 private:
  std::vector<std::unique_ptr<Probe<D>>> probes_;
};

// The probes of a run with a fluid: the case's fluid probes in their order, then, with a structure, its
// displacement and pressure probes, then the force probes.
template <int D>
ProbeSet<D> fluid_run_probes(const Scene<D>& scene, const ParticleSet<D>& particles, const TlsphSolver<D>* structure);
// The displacement probes of a structure-only run (their values need the solver's current F:
// TlsphSolver::update_stress before sampling).
template <int D>
ProbeSet<D> structure_run_probes(const Scene<D>& scene, const TlsphSolver<D>& structure);

}  // namespace isph
