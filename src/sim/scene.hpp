#pragma once
// Scene: the particles, materials, loads and probes a case describes, ready for the solvers.
#include <string>
#include <vector>

#include "io/case.hpp"
#include "sim/particle_set.hpp"
#include "structure/tlsph.hpp"

namespace isph {

template <int D>
struct DisplacementProbe {
  std::string name;
  Index particle;  // nearest structure particle in the reference configuration
  Vec<D> point;    // where u is reported: u_a + (F_a - I)(point - X_a)
};

// The pressure the fluid puts on a structure particle: its row of the pressure Poisson equation.
struct StructurePressureProbe {
  std::string name;
  Index particle;  // nearest structure particle in the reference configuration
};

// A fixed-point probe of the fluid: pressure, velocity, surge front, fastest speed or water level
// (io/case.hpp ProbeSpec).
template <int D>
struct FluidProbe {
  std::string name;
  ProbeType type = ProbeType::pressure;
  Vec<D> point;
};

// The fluid's pressure force on a wall or structure body (io/case.hpp ProbeSpec "force").
struct ForceProbe {
  std::string name;
  Index body;              // index in the case's bodies
  bool all_terms = false;  // with the viscous and contact forces (ParticleSet::body_viscous_force, body_contact_force)
};

template <int D>
struct Scene {
  bool has_structure = false;  // the stages the case runs
  bool has_fluid = false;
  TlsphSetup<D> structure;          // structure particles, sorted by cell
  std::vector<Index> structure_id;  // stable ids (output order)
  std::vector<int> structure_body;  // body index per structure particle
  FluidSetup<D> fluid;              // fluid and wall particles
  Index fluid_particles = 0;
  Index wall_particles = 0;
  std::vector<DisplacementProbe<D>> probes;
  std::vector<StructurePressureProbe> pressure_probes;
  std::vector<FluidProbe<D>> fluid_probes;
  std::vector<ForceProbe> force_probes;
  Real body_extent = 0;               // largest body size, for the divergence test
  Vec<D> domain_lo, domain_hi;        // fluid: a particle leaving this box has escaped
  Vec<D> up = Vec<D>::zero();         // against gravity (unit; zero without gravity)
  std::vector<std::string> warnings;  // what may spoil a run without making the case wrong (printed by check and run)
  Real rim = 0;                       // the highest corner, along `up`, of the box of the set-up's particles and
                                      // walls' paths, less 2h: an escaped particle above it was thrown out over
                                      // the walls
};

// Fills every body on its lattice, applies clamps, initial velocities and loads, and places the
// probes. Throws CaseError listing every problem (an empty body or clamp, a probe outside every
// structure, a stage the case needs but does not enable, ...).
template <int D>
Scene<D> build_scene(const CaseSpec& spec);

// Lamé constants of a material; in 2D plane stress, lambda is the plane-stress value.
ElasticMaterial elastic_material(const MaterialSpec& m, int dimension);

}  // namespace isph
