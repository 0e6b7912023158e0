#pragma once
// The case description: what a case file (TOML) says, after validation and defaults.
// The loader (case_loader.cpp) fills these structs; nothing downstream reads TOML.
// Every key below is documented in docs/CASES.md; units are SI.
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace isph {

// A geometric primitive. In 2D: "rectangle" (min, max) or "circle" (center, radius).
// In 3D: "box" (min, max) or "sphere" (center, radius). Unused components stay zero.
struct Shape {
  std::string type;                 // rectangle | circle | box | sphere
  std::array<double, 3> min{};      // rectangle / box
  std::array<double, 3> max{};
  std::array<double, 3> center{};   // circle / sphere
  double radius = 0.0;
  bool contains(const std::array<double, 3>& p, int dimension) const;
};

enum class ParticleKind : int { fluid = 0, wall = 1, structure = 2 };

struct MaterialSpec {
  std::string name;
  std::string model = "saint_venant_kirchhoff";  // only model for structures today
  double density = 0.0;                           // [kg/m^3], > 0
  double youngs_modulus = 0.0;                    // [Pa], > 0 (or derived from bulk_modulus)
  double poisson_ratio = 0.0;                     // in (-1, 0.5)
  std::string plane = "strain";                   // 2D only: "strain" | "stress"
};

// Prescribed initial velocity of a body.
//  "uniform": velocity = value.
//  "cantilever_mode": the first bending mode of a clamped-free beam (Gray et al. 2001, seed 001
//    Eqs. 51-52): v = tip_velocity * f(s)/f(length) along `direction`, with s the distance from
//    `root` along `axis`, f(s) = (cos kL + cosh kL)(cosh ks - cos ks) + (sin kL - sinh kL)(sinh ks - sin ks),
//    k = kL / length.
struct InitialVelocitySpec {
  std::string type = "none";                 // none | uniform | cantilever_mode
  std::array<double, 3> value{};             // uniform
  double kL = 1.875;                         // cantilever_mode
  double tip_velocity = 0.0;                 // [m/s]
  double length = 0.0;                       // [m]
  std::array<double, 3> root{};              // point on the clamped end
  std::array<double, 3> axis{1, 0, 0};       // beam axis (unit)
  std::array<double, 3> direction{0, 1, 0};  // direction of the velocity (unit)
};

// A body: a primitive filled on a lattice of spacing dx (cell-centred: the lattice points
// inside the shape, with the lattice anchored at `lattice_origin`).
struct BodySpec {
  std::string name;
  ParticleKind kind = ParticleKind::structure;
  std::string material;                      // name in the material table
  Shape shape;
  std::vector<Shape> clamps;                 // particles of this body inside any clamp are fixed
  std::array<double, 3> lattice_origin{};    // lattice points at origin + (i + 1/2) dx
  InitialVelocitySpec initial_velocity;
};

// An applied load. "edge" and "point": a total force shared equally by the body's particles inside
// `region` ("point" takes the single particle nearest region.center). "body": an acceleration on
// every particle of the body. Loads ramp linearly from 0 to full over ramp_time (0 = at once).
struct LoadSpec {
  std::string type;                          // edge | point | body
  std::string body;
  Shape region;                              // edge: region; point: region.center is used
  std::array<double, 3> force{};             // edge/point: total force [N per unit depth in 2D]
  std::array<double, 3> acceleration{};      // body: [m/s^2]
  double ramp_time = 0.0;                    // [s]
};

// A probe. "displacement" follows the structure particle nearest `point` in the reference
// configuration and reports u at `point` (fields ux, uy[, uz]).
struct ProbeSpec {
  std::string name;
  std::string type = "displacement";
  std::array<double, 3> point{};
};

struct KernelSpec {
  std::string type = "cubic_spline";         // cubic_spline | wendland_c2
  double h_factor = 1.2;                     // h = h_factor * dx (seed 001 uses 1.2)
  bool correction = true;                    // kernel gradient correction (shape tensor K)
};

struct StructureSpec {
  std::string integrator = "rk4";            // rk4 | verlet
  double courant = 0.5;                      // dt = courant * h / c_p (c_p: P-wave speed)
  double damping = 0.0;                      // mass-proportional damping rate [1/s]
  double hourglass = 5.0;                    // hourglass control coefficient alpha (0 = off); docs/VALIDATION.md
};

struct OutputSpec {
  double interval = 0.0;                     // probes and energies every `interval` [s] (0: every 100 steps)
  double snapshot_interval = 0.0;            // HDF5 snapshot every ... [s] (0: first and last only)
  bool snapshots = true;
};

struct StagesSpec {
  bool structure = true;
  bool fluid = false;
};

struct CaseSpec {
  std::string name;                          // default: file stem
  std::string source_path;
  int dimension = 2;
  double dx = 0.0;
  double end_time = 0.0;
  std::array<double, 3> gravity{};
  KernelSpec kernel;
  StructureSpec structure;
  OutputSpec output;
  StagesSpec stages;
  std::vector<MaterialSpec> materials;
  std::vector<BodySpec> bodies;
  std::vector<LoadSpec> loads;
  std::vector<ProbeSpec> probes;
  std::string resolved_toml;                 // the configuration as run (written to case.resolved.toml)
};

}  // namespace isph
