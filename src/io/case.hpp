#pragma once
// The case description: what a case file (TOML) says, after validation and defaults.
// The loader (case_loader.cpp) fills these structs; nothing downstream reads TOML.
// Every key below is documented in docs/CASES.md; units are SI.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/enum_names.hpp"
#include "core/rigid_motion.hpp"         // MotionSpec
#include "kernels/smoothing_kernel.hpp"  // KernelType
#include "poisson/linear_solver.hpp"     // hypre_available
#include "shifting/shifting_type.hpp"
#include "structure/structure_options.hpp"

namespace isph {

// The options of the fluid and the coupling that a case file chooses by name (docs/CASES.md).
enum class FluidMethod { isph, wcsph };
constexpr EnumName<FluidMethod> kFluidMethodNames[] = {{FluidMethod::isph, "isph"}, {FluidMethod::wcsph, "wcsph"}};
constexpr std::span<const EnumName<FluidMethod>> enum_names(FluidMethod) { return kFluidMethodNames; }

enum class Turbulence { none, sps };
constexpr EnumName<Turbulence> kTurbulenceNames[] = {{Turbulence::none, "none"}, {Turbulence::sps, "sps"}};
constexpr std::span<const EnumName<Turbulence>> enum_names(Turbulence) { return kTurbulenceNames; }

enum class SurfacePressure { extrapolated, zero };
constexpr EnumName<SurfacePressure> kSurfacePressureNames[] = {{SurfacePressure::extrapolated, "extrapolated"},
                                                               {SurfacePressure::zero, "zero"}};
constexpr std::span<const EnumName<SurfacePressure>> enum_names(SurfacePressure) { return kSurfacePressureNames; }

enum class EscapePolicy { remove, stop };
constexpr EnumName<EscapePolicy> kEscapePolicyNames[] = {{EscapePolicy::remove, "remove"},
                                                         {EscapePolicy::stop, "stop"}};
constexpr std::span<const EnumName<EscapePolicy>> enum_names(EscapePolicy) { return kEscapePolicyNames; }

enum class WcsphTimeStepping { dual_criteria, single_criterion };
constexpr EnumName<WcsphTimeStepping> kWcsphTimeSteppingNames[] = {
    {WcsphTimeStepping::dual_criteria, "dual_criteria"}, {WcsphTimeStepping::single_criterion, "single_criterion"}};
constexpr std::span<const EnumName<WcsphTimeStepping>> enum_names(WcsphTimeStepping) { return kWcsphTimeSteppingNames; }

enum class InteractionForce { pairwise, gradient };
constexpr EnumName<InteractionForce> kInteractionForceNames[] = {{InteractionForce::pairwise, "pairwise"},
                                                                 {InteractionForce::gradient, "gradient"}};
constexpr std::span<const EnumName<InteractionForce>> enum_names(InteractionForce) { return kInteractionForceNames; }

enum class SubstepInteraction { held, interpolated };
constexpr EnumName<SubstepInteraction> kSubstepInteractionNames[] = {
    {SubstepInteraction::held, "held"}, {SubstepInteraction::interpolated, "interpolated"}};
constexpr std::span<const EnumName<SubstepInteraction>> enum_names(SubstepInteraction) {
  return kSubstepInteractionNames;
}

// The types a list element of a case chooses by name.
enum class PlaneCondition { strain, stress };
constexpr EnumName<PlaneCondition> kPlaneConditionNames[] = {{PlaneCondition::strain, "strain"},
                                                             {PlaneCondition::stress, "stress"}};
constexpr std::span<const EnumName<PlaneCondition>> enum_names(PlaneCondition) { return kPlaneConditionNames; }

enum class InitialVelocityType { none, uniform, cantilever_mode };
constexpr EnumName<InitialVelocityType> kInitialVelocityTypeNames[] = {
    {InitialVelocityType::none, "none"},
    {InitialVelocityType::uniform, "uniform"},
    {InitialVelocityType::cantilever_mode, "cantilever_mode"}};
constexpr std::span<const EnumName<InitialVelocityType>> enum_names(InitialVelocityType) {
  return kInitialVelocityTypeNames;
}

enum class LoadType { edge, traction, point, body };
constexpr EnumName<LoadType> kLoadTypeNames[] = {
    {LoadType::edge, "edge"}, {LoadType::traction, "traction"}, {LoadType::point, "point"}, {LoadType::body, "body"}};
constexpr std::span<const EnumName<LoadType>> enum_names(LoadType) { return kLoadTypeNames; }

enum class OpenBoundaryType { inlet, outlet };
constexpr EnumName<OpenBoundaryType> kOpenBoundaryTypeNames[] = {{OpenBoundaryType::inlet, "inlet"},
                                                                 {OpenBoundaryType::outlet, "outlet"}};
constexpr std::span<const EnumName<OpenBoundaryType>> enum_names(OpenBoundaryType) { return kOpenBoundaryTypeNames; }

// What a force probe sums (ProbeSpec::terms).
enum class ForceTerms { pressure, all };
constexpr EnumName<ForceTerms> kForceTermsNames[] = {{ForceTerms::pressure, "pressure"}, {ForceTerms::all, "all"}};
constexpr std::span<const EnumName<ForceTerms>> enum_names(ForceTerms) { return kForceTermsNames; }

enum class ProbeType { displacement, structure_pressure, pressure, velocity, front, max_speed, water_level, force };
constexpr EnumName<ProbeType> kProbeTypeNames[] = {{ProbeType::displacement, "displacement"},
                                                   {ProbeType::structure_pressure, "structure_pressure"},
                                                   {ProbeType::pressure, "pressure"},
                                                   {ProbeType::velocity, "velocity"},
                                                   {ProbeType::front, "front"},
                                                   {ProbeType::max_speed, "max_speed"},
                                                   {ProbeType::water_level, "water_level"},
                                                   {ProbeType::force, "force"}};
constexpr std::span<const EnumName<ProbeType>> enum_names(ProbeType) { return kProbeTypeNames; }

// A geometric primitive. In 2D: "rectangle" (min, max), "circle" (center, radius) or "wedge". In 3D:
// "box" (min, max), "sphere" (center, radius), "cylinder" (base, axis, radius) or "stl" (a closed
// triangle mesh from a file). Unused components stay zero.
enum class ShapeType { rectangle, circle, wedge, box, sphere, cylinder, stl };
constexpr EnumName<ShapeType> kShapeTypeNames[] = {{ShapeType::rectangle, "rectangle"},
                                                   {ShapeType::circle, "circle"},
                                                   {ShapeType::wedge, "wedge"},
                                                   {ShapeType::box, "box"},
                                                   {ShapeType::sphere, "sphere"},
                                                   {ShapeType::cylinder, "cylinder"},
                                                   {ShapeType::stl, "stl"}};
constexpr std::span<const EnumName<ShapeType>> enum_names(ShapeType) { return kShapeTypeNames; }
inline bool is_ball(ShapeType t) { return t == ShapeType::circle || t == ShapeType::sphere; }
inline bool is_planar(ShapeType t) {
  return t == ShapeType::rectangle || t == ShapeType::circle || t == ShapeType::wedge;
}

class StlMesh;  // io/stl_mesh.hpp
// The mesh of an "stl" shape, read by the loader. It follows from the shape's file, scale and translate,
// which the shapes' comparison compares.
struct ShapeMesh {
  std::shared_ptr<const StlMesh> mesh;
  bool operator==(const ShapeMesh&) const { return true; }
};

struct Shape {
  ShapeType type = ShapeType::rectangle;
  std::array<double, 3> min{};  // rectangle / box
  std::array<double, 3> max{};
  std::array<double, 3> center{};  // circle / sphere
  double radius = 0.0;             // circle / sphere / cylinder
  std::array<double, 3> base{};    // cylinder: the centre of one end
  std::array<double, 3> axis{};    // cylinder: from base to the other end's centre (its length is the cylinder's)
  std::string file{};              // stl: the mesh's file (an absolute path once loaded)
  double scale = 1.0;              // stl: each vertex v becomes scale v + translate
  std::array<double, 3> translate{};
  ShapeMesh mesh{};              // stl
  std::array<double, 3> apex{};  // wedge (2D): the keel, the lowest point of its outer face
  double half_breadth = 0.0;     // wedge: horizontal distance from the keel to each chine
  double deadrise = 0.0;         // wedge: each panel's angle to the horizontal [degrees]
  double thickness = 0.0;        // wedge: each panel's thickness, normal to it
  // wedge: the height of a panel's section on a vertical line, thickness / cos(deadrise)
  double vertical_thickness() const;
  double slope() const;  // wedge: the panels' rise per unit of horizontal distance, tan(deadrise)
  bool contains(const std::array<double, 3>& p, int dimension) const;
  // The bounding box's corners in the first `dimension` components (the others zero).
  std::pair<std::array<double, 3>, std::array<double, 3>> bounding_box(int dimension) const;
  bool operator==(const Shape&) const = default;
};

enum class ParticleKind : int { fluid = 0, wall = 1, structure = 2 };
constexpr EnumName<ParticleKind> kParticleKindNames[] = {
    {ParticleKind::fluid, "fluid"}, {ParticleKind::wall, "wall"}, {ParticleKind::structure, "structure"}};
constexpr std::span<const EnumName<ParticleKind>> enum_names(ParticleKind) { return kParticleKindNames; }

// A material. The elastic models (structures; structure/elastic_law.hpp) need youngs_modulus (or
// bulk_modulus) and poisson_ratio, their small-strain moduli; "newtonian" (fluids) needs viscosity and
// takes no elastic keys.
enum class MaterialModel { saint_venant_kirchhoff, neo_hookean, mooney_rivlin, newtonian };
constexpr EnumName<MaterialModel> kMaterialModelNames[] = {
    {MaterialModel::saint_venant_kirchhoff, "saint_venant_kirchhoff"},
    {MaterialModel::neo_hookean, "neo_hookean"},
    {MaterialModel::mooney_rivlin, "mooney_rivlin"},
    {MaterialModel::newtonian, "newtonian"}};
constexpr std::span<const EnumName<MaterialModel>> enum_names(MaterialModel) { return kMaterialModelNames; }

struct MaterialSpec {
  std::string name;
  MaterialModel model = MaterialModel::saint_venant_kirchhoff;
  double density = 0.0;                           // [kg/m^3], > 0
  double youngs_modulus = 0.0;                    // [Pa], > 0 (or derived from bulk_modulus)
  double bulk_modulus = 0.0;                      // [Pa], when given instead of youngs_modulus (0: not given)
  double poisson_ratio = 0.0;                     // in (-1, 0.5)
  PlaneCondition plane = PlaneCondition::strain;  // 2D only; stress: St. Venant-Kirchhoff only
  double c01_fraction = 0.0;                      // Mooney-Rivlin: c01 / (c10 + c01), in [0, 1)
  double viscosity = 0.0;                         // newtonian: kinematic viscosity [m^2/s], > 0
  bool operator==(const MaterialSpec&) const = default;
};

// Prescribed initial velocity of a body.
//  "uniform": velocity = value.
//  "cantilever_mode": the first bending mode of a clamped-free beam (Gray et al. 2001, seed 001
//    Eqs. 51-52): v = tip_velocity * f(s)/f(length) along `direction`, with s the distance from
//    `root` along `axis`, f(s) = (cos kL + cosh kL)(cosh ks - cos ks) + (sin kL - sinh kL)(sinh ks - sin ks),
//    k = kL / length.
struct InitialVelocitySpec {
  InitialVelocityType type = InitialVelocityType::none;
  std::array<double, 3> value{};             // uniform
  double kL = 1.875;                         // cantilever_mode
  double tip_velocity = 0.0;                 // [m/s]
  double length = 0.0;                       // [m]
  std::array<double, 3> root{};              // point on the clamped end
  std::array<double, 3> axis{1, 0, 0};       // beam axis (unit)
  std::array<double, 3> direction{0, 1, 0};  // direction of the velocity (unit)
  bool operator==(const InitialVelocitySpec&) const = default;
};

// How a body's shape is filled: a Cartesian lattice, or (a wall's 2D circle) concentric rings whose outer ring
// lies s/2 inside the circle, so that the surface is smooth rather than a staircase (docs/CASES.md, shapes).
enum class LatticeType { cartesian, rings };
constexpr EnumName<LatticeType> kLatticeTypeNames[] = {{LatticeType::cartesian, "cartesian"},
                                                       {LatticeType::rings, "rings"}};
constexpr std::span<const EnumName<LatticeType>> enum_names(LatticeType) { return kLatticeTypeNames; }

// A body: a primitive filled on a lattice of spacing s (by default cell-centred: the lattice points
// inside the shape, with the lattice anchored at `lattice_origin`). Every particle has the volume s^D.
// s is the case's dx, or for a structure its own dx or the case's dx / refinement: a thin structure may be
// finer than the water around it (multi-resolution, docs/VALIDATION.md section 23).
struct BodySpec {
  std::string name;
  ParticleKind kind = ParticleKind::structure;
  std::string material;  // name in the material table
  Shape shape;
  std::vector<Shape> clamps;  // particles of this body inside any clamp are fixed
  std::vector<Shape> holes;   // fluid or wall: the body leaves these empty (an obstacle, a structure's slot)
  double refinement = 1.0;    // structures: the case's dx over the body's spacing (>= 1; s = dx / refinement)
  double dx = 0.0;            // structures: the body's own spacing [m] instead (0: from refinement)
  LatticeType lattice = LatticeType::cartesian;
  std::array<double, 3> lattice_origin{};  // lattice points at origin + (i + offset) s
  // Per axis, in units of s, in [0, 1): 1/2 puts the particles at cell centres, so that the shape's
  // faces lie s/2 beyond its outer particles; 0 puts particle rows on the faces through the origin.
  std::array<double, 3> lattice_offset{0.5, 0.5, 0.5};
  InitialVelocitySpec initial_velocity;
  MotionSpec motion;  // walls; structures: their clamps
  double spacing(double case_dx) const { return dx > 0 ? dx : case_dx / refinement; }
  bool operator==(const BodySpec&) const = default;
};

// An applied load. "edge": a total force shared equally by the body's particles inside `region`;
// "point": the force on the single particle nearest `point`. "traction": a force per unit area on each
// particle inside `region`, times its cell's face dx^(D-1). "body": an acceleration on every particle
// of the body. Loads ramp linearly from 0 to full over ramp_time (0 = at once).
struct LoadSpec {
  LoadType type = LoadType::edge;
  std::string body;
  Shape region;                          // edge, traction
  std::array<double, 3> point{};         // point
  std::array<double, 3> force{};         // edge/point: total force [N per unit depth in 2D]
  std::array<double, 3> traction{};      // traction: force per unit area of the loaded face [Pa]
  std::array<double, 3> acceleration{};  // body: [m/s^2]
  double ramp_time = 0.0;                // [s]
  bool operator==(const LoadSpec&) const = default;
};

// A probe.
//  "displacement": follows the structure particle nearest `point` in the reference configuration
//                  and reports u at `point` (fields ux, uy[, uz]).
//  "pressure":     fixed point; kernel-normalised (Shepard) interpolation of the fluid and wall
//                  pressure at `point` (field p).
//  "velocity":     fixed point; Shepard interpolation of the fluid velocity (fields ux, uy[, uz]).
//  "front":        the largest x of the fluid particles below the height point[1] (field x): the surge
//                  front of a dam break when point[1] is a little above the floor.
//  "max_speed":    the speed of the fastest fluid particle (field u); no point.
//  "water_level":  the height of the water surface on the vertical line through `point`, at or above
//                  point's height (field h): a wave gauge.
//  "force":        the fluid's pressure force on the wall or structure `body` (fields fx, fy[, fz];
//                  per unit depth in 2D), with terms = "all" on a wall also its viscous traction and
//                  the impermeability condition's impulses; the time mean over the fluid steps since
//                  the previous row; no point.
struct ProbeSpec {
  std::string name;
  ProbeType type = ProbeType::displacement;
  std::array<double, 3> point{};
  std::string body;                         // "force": the body the force acts on
  ForceTerms terms = ForceTerms::pressure;  // "force": the pressure's, or all the fluid's (a wall body)
  bool operator==(const ProbeSpec&) const = default;
};

// An open boundary of the fluid (ISPH; sim/open_boundary.hpp): a plane through `point` with the unit
// `normal` into the fluid, and behind it a buffer of `layers` particle spacings, filled by the fluid
// bodies. An inlet's buffer particles move at the prescribed velocity, normal to the plane, and become
// fluid as they cross it; each is replaced by a new one a buffer's thickness behind. Fluid crossing an
// outlet's plane joins its buffer, which moves with the fluid beside the plane and holds the pressure
// `pressure`; it is removed at the buffer's far side.
struct OpenBoundarySpec {
  std::string name;
  OpenBoundaryType type = OpenBoundaryType::inlet;
  std::array<double, 3> point{};
  std::array<double, 3> normal{};
  int layers = 0;              // buffer thickness in particle spacings; 0: the kernel's support plus one
  std::string velocity = "0";  // inlet: the inflow speed [m/s], an expression of x, y, z, t (core/expression.hpp)
  double flow_rate = 0.0;      // inlet: when > 0, `velocity` is scaled to carry this flow [m^2/s in 2D, m^3/s]
  double ramp_time = 0.0;      // inlet: the speed times (1 - cos(pi t / ramp_time)) / 2 until ramp_time [s]
  double pressure = 0.0;       // outlet [Pa]
  bool operator==(const OpenBoundarySpec&) const = default;
};

struct KernelSpec {
  KernelType type = KernelType::cubic_spline;
  double h_factor = 1.2;   // h = h_factor * dx (seed 001 uses 1.2)
  bool correction = true;  // kernel gradient correction (shape tensor K)
  bool operator==(const KernelSpec&) const = default;
};

struct StructureSpec {
  StructureIntegrator integrator = StructureIntegrator::rk4;
  StructureGradient gradient = StructureGradient::linear;       // pair gradients exact for linear or quadratic fields
  StructureQuadrature quadrature = StructureQuadrature::point;  // the strain energy at the particle or over its cell
  double courant = 0.5;                                         // dt = courant * h / c_p (c_p: P-wave speed)
  double damping = 0.0;                                         // mass-proportional damping rate [1/s]
  double hourglass = 5.0;  // hourglass control coefficient alpha (0 = off); docs/VALIDATION.md
  bool operator==(const StructureSpec&) const = default;
};

// The PPE linear solver (poisson/linear_solver.hpp) and what to do when it fails. The default is
// BoomerAMG where the build has hypre (3-4 times faster per solve than Eigen's ILUT on the bundled
// cases, docs/PERFORMANCE.md) with Eigen as its fallback, and Eigen's ILUT otherwise. A case that names
// a backend gets no fallback unless it names one too.
enum class FallbackSolver { none, eigen, hypre };
constexpr EnumName<FallbackSolver> kFallbackSolverNames[] = {
    {FallbackSolver::none, "none"}, {FallbackSolver::eigen, "eigen"}, {FallbackSolver::hypre, "hypre"}};
constexpr std::span<const EnumName<FallbackSolver>> enum_names(FallbackSolver) { return kFallbackSolverNames; }

struct PpeSolverSpec {
  SolverBackend backend = hypre_available() ? SolverBackend::hypre : SolverBackend::eigen;
  KrylovMethod method = KrylovMethod::bicgstab;  // gmres: eigen and hypre only
  PreconditionerType preconditioner =            // one of solver_preconditioners(backend)
      hypre_available() ? PreconditionerType::boomeramg : PreconditionerType::ilu;
  double tolerance = 1e-8;  // relative residual
  int max_iterations = 1000;
  FallbackSolver fallback =  // a second backend tried after a failed solve
      hypre_available() ? FallbackSolver::eigen : FallbackSolver::none;
  int preconditioner_reuse = 0;  // steps a preconditioner serves the next steps' matrices while
                                 // the particles keep their order (0: a new one every step)
  bool operator==(const PpeSolverSpec&) const = default;
};

struct ShiftingSpec {
  ShiftingType type = ShiftingType::ops;  // xu: Xu/Lind, Eqs. 21-23; ops: + Eqs. 24-26 at the surface
  double coefficient = 0.05;              // C of Eq. 21, in [0.01, 0.1]
  double max_fraction = 0.2;              // cap on |dr| as a fraction of h (Lind et al. 2012)
  bool taylor_correction = true;          // Eqs. 20, 31-32
  bool operator==(const ShiftingSpec&) const = default;
};

// Inelastic collisions of fluid particles closer than distance * dx (ISPH; sim/fluid_functors.hpp).
struct CollisionSpec {
  double distance = 0.5;     // fraction of dx; 0: no collisions
  double restitution = 0.2;  // e in [0, 1]
  bool operator==(const CollisionSpec&) const = default;
};

// The weakly compressible comparator (seed 002; sim/wcsph.hpp).
struct WcsphSpec {
  WcsphTimeStepping time_stepping = WcsphTimeStepping::dual_criteria;  // dual: Eqs. 9-15
  double advection_courant = 0.25;                                     // Eq. 9: CFL_ad
  double acoustic_courant = 0.6;  // Eq. 10: CFL_ac; default 0.6 (dual_criteria) or 0.25 (single_criterion)
  double sound_speed = 0.0;       // c of Eq. 2 [m/s]; 0: 10 U_max, U_max = sqrt(2) x the reference velocity
  double riemann_limiter = 3.0;   // eta of the low-dissipation limiter beta = min(eta max(U_L - U_R, 0)/c, 1)
  bool operator==(const WcsphSpec&) const = default;
};

// The fluid stage: the projection ISPH of seed 001 §2.1 (model "isph") or the weakly compressible
// comparator of seed 002 (model "wcsph"; it shares the particles, walls, viscosity, probes and coupling,
// and ignores the ISPH-only keys: free-surface thresholds, shifting, ppe).
struct FluidSpec {
  FluidMethod model = FluidMethod::isph;
  double courant = 0.1;                      // Eq. 49: dt = courant h / U
  double viscous_number = 0.125;             // dt <= viscous_number h^2 / nu
  double reference_velocity = 0.0;           // floor on U in Eq. 49 [m/s]; 0: sqrt(2 |g| H_fluid), or the fastest wall
  double max_dt = 0.0;                       // [s]; 0: no cap
  Turbulence turbulence = Turbulence::none;  // sps: Eq. 10
  double smagorinsky = 0.1;                  // c_s of Eq. 10
  double density_relaxation = 0.0;           // gamma of the PPE's density-invariant term (poisson/ppe_assembly.hpp)
  double constraint_weight = 1.0;            // theta: the projection keeps theta u^{n+1} + (1 - theta) u^n div-free
  bool free_surface = true;                  // detect the free surface (Dirichlet p = 0, Eq. 17)
  double surface_threshold = 0.0;            // div r below it: surface; 0: 1.4 (2D), 2.4 (3D)
  double surface_full = 0.0;                 // div r above it: Skillen alpha = 1; 0: 1.6 (2D), 2.6 (3D)
  SurfacePressure surface_pressure =
      SurfacePressure::extrapolated;  // zero: p = 0 at surface particles; extrapolated: dx/2 beyond
  EscapePolicy escape =
      EscapePolicy::remove;  // a fluid particle leaving the escape box: removed (and counted), or the run stops
  ShiftingSpec shifting;
  CollisionSpec collision;
  PpeSolverSpec ppe;
  WcsphSpec wcsph;
  bool operator==(const FluidSpec&) const = default;
};

// The fluid-structure coupling (seed 001 §2.3), used when a case has fluid and structure bodies.
struct CouplingSpec {
  int substeps = 0;          // structure steps per fluid step; 0: from the structure's stability limit
  bool fsi_shifting = true;  // the FSI shifting layer beside structures (Eqs. 27-30)
  FsiLayerLaw fsi_shifting_law = FsiLayerLaw::literal;  // what its Eq. 27 relocates
  double tolerance = 1e-3;           // interface iterations: relative change of the structure's acceleration
  int max_iterations = 30;           // interface iterations per fluid step (1: explicit, staggered)
  double first_ppe_tolerance = 0.0;  // PPE tolerance of a step's first interface iteration (0: the PPE's)
  int reuse_steps = 8;               // quasi-Newton: steps whose iterations are reused (0: none)
  InteractionForce interaction_force =
      InteractionForce::pairwise;  // gradient: Eq. 48 literally (structure/interaction.hpp)
  SubstepInteraction substep_interaction =
      SubstepInteraction::held;  // held: alpha of the step's end; interpolated: from the last step's
  bool wall_contact = true;      // structure particles overlapping wall particles are pushed out (sim/coupling.hpp)
  bool implicit_added_mass =
      true;  // the structure's inertia in its PPE rows (sim/coupling.hpp); false: a_s from the iterations alone
  bool operator==(const CouplingSpec&) const = default;
};

// Periodic axes: particles leaving [lo, hi) re-enter on the other side and neighbours are found
// across the boundary. range[k] is [lo, hi] on a periodic axis, empty on the others.
struct PeriodicSpec {
  std::array<std::vector<double>, 3> range;
  bool axis(int k) const { return range[k].size() == 2; }
  double lo(int k) const { return axis(k) ? range[k][0] : 0.0; }
  double hi(int k) const { return axis(k) ? range[k][1] : 0.0; }
  bool operator==(const PeriodicSpec&) const = default;
};

struct OutputSpec {
  double interval = 0.0;           // probes and energies every `interval` [s] (0: every 100 steps)
  double snapshot_interval = 0.0;  // HDF5 snapshot every ... [s] (0: first and last only)
  bool snapshots = true;
  bool operator==(const OutputSpec&) const = default;
};

struct StagesSpec {
  bool structure = true;  // run TLSPH (needs structure bodies)
  bool fluid = false;     // run ISPH (needs fluid bodies)
  bool operator==(const StagesSpec&) const = default;
};

struct CaseSpec {
  std::string name;  // default: file stem
  std::string source_path;
  int dimension = 2;
  double dx = 0.0;
  double end_time = 0.0;
  std::array<double, 3> gravity{};
  KernelSpec kernel;
  StructureSpec structure;
  FluidSpec fluid;
  CouplingSpec coupling;
  PeriodicSpec periodic;
  OutputSpec output;
  StagesSpec stages;
  std::vector<MaterialSpec> materials;
  std::vector<BodySpec> bodies;
  std::vector<LoadSpec> loads;
  std::vector<ProbeSpec> probes;
  std::vector<OpenBoundarySpec> open_boundaries;
  std::string resolved_toml;  // the configuration as run (written to case.resolved.toml)
  bool operator==(const CaseSpec&) const = default;
};

}  // namespace isph
