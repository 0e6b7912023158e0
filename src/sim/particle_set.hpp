#pragma once
// The one particle set of a scene with a fluid: fluid, wall and structure particles, their boundary
// data, the neighbour search that re-sorts them, and what every fluid model reads or writes of them
// (moving walls, the structure's motion, penetration; the probes and energies read it from
// sim/probes.hpp). The fluid models (the projection
// ISPH of seed 001, sim/isph.hpp, and the weakly compressible comparator of seed 002, sim/wcsph.hpp) hold
// it by composition; their particle loops see it through a plain view (FluidView, kernels/fluid_view.hpp).
//
// Each particle carries its own volume and resolution level: the level indexes the kernel table (one
// smoothing length per particle spacing, kernels/operators.hpp KernelTable), so that a structure may be
// finer than the water around it. Fluid and wall particles are on the case's spacing dx.
//
// A model's own per-particle arrays follow the set's re-sorts and removals once attached (attach()).
#include <algorithm>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/device_memory.hpp"
#include "core/neighbour_search.hpp"
#include "core/rigid_motion.hpp"
#include "io/case.hpp"
#include "io/output.hpp"
#include "kernels/fluid_view.hpp"
#include "poisson/linear_solver.hpp"
#include "sim/open_boundary.hpp"
#include "sim/phase_timer.hpp"

namespace isph {

template <int D>
struct ViscousAcceleration;  // sim/fluid_functors.hpp
template <int D>
struct ForceComponent;  // structure/interaction.hpp
template <int D>
class StructureCoupling;  // sim/coupling.hpp

// One array follows a re-sort or a removal: out[k] = in[order[k]].
template <class T>
struct GatherElements {
  const T* in;
  const Index* order;
  T* out;
  ISPH_HD void operator()(Index k) const { out[k] = in[order[k]]; }
};

// Everything a fluid model needs, built by build_scene (sim/scene.cpp): the particles and the model's
// settings.
template <int D>
struct FluidSetup {
  std::vector<Vec<D>> x, u;
  std::vector<Real> volume;
  std::vector<FluidKind> kind;
  std::vector<unsigned char> level;     // index in `kernels` (0 for every particle of a one-resolution scene)
  std::vector<Vec<D>> wall_velocity;    // prescribed velocity (walls), zero for fluid
  std::vector<Vec<D>> wall_normal;      // walls, structures: unit normal into the fluid (zero when deep inside)
  std::vector<Real> wall_depth;         // walls, structures: distance below the surface
  std::vector<Index> structure_index;   // structure particles: index in the TLSPH solver; -1 for others
  std::vector<Index> id;                // stable id (output order)
  std::vector<Index> motion;            // walls: index in `motions`; -1 for fixed walls and the others
  std::vector<Index> body;              // index in the case's bodies (-1: a set built by hand)
  std::vector<RigidMotion<D>> motions;  // prescribed motions of wall bodies
  std::vector<OpenZone<D>> open_zones;  // inlets and outlets (sim/open_boundary.hpp)
  std::vector<Index> open_zone;         // buffer particles: index in `open_zones`; -1 for the others (or empty)
  Real density = 0;
  Real viscosity = 0;      // kinematic [m^2/s]
  Real dx = 0;             // the fluid's (and walls') particle spacing
  KernelTable<D> kernels;  // per level, sorted by h; level 0 need not be the fluid's
  int fluid_level = 0;     // the fluid's level in `kernels`
  bool kernel_correction = true;
  Periodicity<D> period;
  Vec<D> gravity = Vec<D>::zero();
  Real reference_velocity = 0;  // floor on U in Eq. 49 (resolved from the case)
  FluidSpec settings;
  Device device = Device::cpu;  // cuda: the state lives in managed memory and every particle loop runs on the GPU
  bool fsi_shifting = true;     // the FSI shifting layer (Eqs. 27-30)
  FsiLayerLaw fsi_shifting_law = FsiLayerLaw::literal;
  InteractionForce interaction_force =
      InteractionForce::pairwise;  // pairwise | gradient (Eq. 48 literally; structure/interaction.hpp)
  bool wall_force = false;         // the walls' pressure force after every step (force probes), moving or not
  bool wall_friction = false;      // and their viscous and contact forces (force probes with terms = "all")

  const SmoothingKernel<D>& fluid_kernel() const { return kernels.kernel[fluid_level]; }
};

// Penetration diagnostics of one step against one body, the structure or the walls
// (BodyContact, structure/interaction.hpp).
template <int D>
struct InteractionReport {
  Index fluid_inside = 0;             // fluid particles inside the body
  Real min_distance = 0;              // smallest fluid-body particle distance (inf: none in reach)
  Real max_depth = 0;                 // deepest fluid particle inside, behind the body's surface
  Vec<D> inside_at = Vec<D>::zero();  // position of the lowest-id fluid particle inside (when any)
};

// The penetration diagnostics of a run against one body, step by step, for summary.json.
template <int D>
class ContactRecord {
 public:
  void add(const InteractionReport<D>& step, Real t);
  // Keys named after the body ("structure", "wall"): fluid_inside_<body>_max, steps_with_fluid_inside_<body>,
  // min_fluid_<body>_distance (-1: never in reach), max_fluid_<body>_depth (behind the surface; 0: none
  // inside) and, when any was inside, first_fluid_inside_<body>_time,
  // max_fluid_inside_<body>_time and max_fluid_inside_<body>_at (a particle inside at that step).
  void write(JsonObject& o, const std::string& body) const;

 private:
  Index max_inside_ = 0;
  long long steps_with_inside_ = 0;
  Real first_inside_time_ = 0, worst_inside_time_ = 0;
  Vec<D> worst_inside_at_ = Vec<D>::zero();
  Real min_distance_ = std::numeric_limits<Real>::infinity();
  Real max_depth_ = 0;
};

struct FluidStepReport {
  SolveReport ppe;               // the step's last PPE solve
  int ppe_solves = 0;            // PPE solves in the step (the coupling's interface iterations repeat it)
  long long ppe_iterations = 0;  // Krylov iterations over all of them (a fallback's included)
  int ppe_max_iterations = 0;    // the most any one of them took
  std::string ppe_solver;        // the backend that produced the pressure ("none" for a weakly compressible fluid)
  bool ppe_failed = false;       // no backend converged
};

// The vector of a snapshot row (a field of 3 components, z dropped in 2D).
template <int D>
Vec<D> snapshot_vector(const SnapshotField& field, std::size_t row) {
  Vec<D> v;
  for (int d = 0; d < D; ++d) v[d] = field.data[3 * row + d];
  return v;
}

template <int D>
class ParticleSet {
 public:
  explicit ParticleSet(FluidSetup<D>& setup);
  ParticleSet(const ParticleSet&) = delete;  // attached arrays refer to the models' members
  ParticleSet& operator=(const ParticleSet&) = delete;

  // ---- the state (permuted together by find_neighbours; in managed memory on the cuda device) ----
  StateVector<Vec<D>> position, velocity;
  StateVector<Real> pressure, volume;
  StateVector<FluidKind> kind;
  StateVector<unsigned char> level;  // index in kernels()
  StateVector<Vec<D>> wall_velocity, wall_acceleration, wall_normal, reference_normal;
  StateVector<Real> wall_depth;
  StateVector<Index> id, structure_index,
      motion;                              // stable id; TLSPH index (-1: not a structure particle); motion (-1: none)
  StateVector<Index> body;                 // index in the case's bodies (FluidSetup::body)
  StateVector<Index> open_zone;            // buffer particles: their open boundary; -1 for the others
  StateVector<Vec<D>> reference_position;  // initial positions (moving walls follow their motion from them)
  StateVector<Vec<D>> boundary_force;      // pressure force per unit volume on wall and structure particles
  StateVector<Vec<D>> viscous_force;       // viscous force per unit volume on structure particles, and on
                                           // wall particles when asked for (record_viscous_force)
  StateVector<Real> viscous_impedance;     // Z_w = -df_w/dU_w of viscous_force on structure particles
  StateVector<Vec<D>> contact_force;       // on fluid particles: the force per unit volume of the projection's
  StateVector<Index> contact_body;         // impermeability condition on the body of a wall face (Project)
  Real time = 0;
  Real wall_work = 0;  // work done on the fluid by the moving walls' pressure and viscous traction

  Index size() const { return static_cast<Index>(position.size()); }
  Index fluid_count() const { return fluid_count_; }
  Index wall_count() const { return wall_count_; }
  const Exec& exec() const { return exec_; }
  const KernelTable<D>& kernels() const { return kernels_; }
  const SmoothingKernel<D>& fluid_kernel() const { return kernels_.kernel[fluid_level_]; }
  int fluid_level() const { return fluid_level_; }  // the fluid's level in kernels()
  Real dx() const { return dx_; }
  Real density() const { return density_; }
  const Periodicity<D>& period() const { return period_; }
  const Vec<D>& gravity() const { return gravity_; }
  bool has_structure() const { return has_structure_; }
  bool has_moving_walls() const { return !motions_.empty(); }
  bool has_outlet() const;
  const std::vector<OpenZone<D>>& open_zones() const { return open_zones_; }
  const std::vector<OpenZoneFlow>& open_flows() const { return open_flows_; }
  Index next_id() const { return next_id_; }
  // Counts the re-sorts and removals: the particles' order is that of the last count.
  long long order_version() const { return order_version_; }
  // Neighbour searches so far: every kSortInterval-th re-sorts (a snapshot keeps the count, so that a
  // restart re-sorts where the uninterrupted run does).
  long long neighbour_searches() const { return neighbour_searches_; }

  // The plain view the particle loops read (positions, volumes, levels, the neighbour list of the
  // last search, kinds, boundary data).
  FluidView<D> view() const;
  // Cell list and CSR neighbour list at the current positions; every kSortInterval calls the particles
  // are first re-sorted by cell (with the attached arrays). Both are built on the device in use.
  void find_neighbours();
  // Start of the CSR neighbour list (n + 1 offsets) on the device in use.
  const Index* neighbour_offset() const;
  // An allocator for per-particle arrays: managed memory on the cuda device, host memory otherwise.
  template <class T>
  StateAllocator<T> allocator() const {
    return StateAllocator<T>(exec_.device == Device::cuda);
  }
  // One value per particle, in the state's memory.
  template <class T>
  StateVector<T> array(const T& value) const {
    return StateVector<T>(static_cast<std::size_t>(size()), value, allocator<T>());
  }
  // A model's per-particle array follows the particles from now on (re-sorts and removals). The array
  // must outlive the set or be detached with the set's owner.
  template <class T>
  void attach(StateVector<T>& v) {
    followers_.push_back([this, &v](const Index* order, Index count) { permute(v, order, count); });
  }

  // After a fluid step of length dt (time at its end): the open boundaries' exchange of buffer and
  // fluid particles, and the inlets' velocities at `time` (sim/open_boundary.hpp). Particles created
  // take new stable ids; the neighbour list is rebuilt when the count changed.
  void exchange_open_boundaries(Real dt);

  // Moving walls over [t, t + dt] (t = time; PrescribeWalls).
  void prescribe_walls(Real dt);
  // The wall particles as the structure's obstacles (sim/coupling.hpp), in particle order: their
  // positions and radii, half their spacing V^(1/D). Gathered on the particles' device.
  void gather_walls(StateVector<Vec<D>>& point, StateVector<Real>& radius) const;
  // From boundary_force and viscous_force (filled by the model): the force density on the structure
  // particles indexed as in TLSPH, and its sum.
  Vec<D> gather_structure_force(std::span<Vec<D>> force_density) const;
  // From boundary_force (filled by the model): the pressure force on the particles of one body.
  Vec<D> body_force(Index body_index) const;
  // The fluid's viscous traction on the particles of one kind, wall or structure (ViscousBoundaryForce),
  // into viscous_force (on structure particles with viscous_impedance); and from it, the viscous force
  // on the particles of one body.
  void record_viscous_force(const ViscousAcceleration<D>& viscous, FluidKind target);
  // viscous_impedance on the structure particles, indexed as in TLSPH.
  void gather_structure_impedance(std::span<Real> impedance) const;
  Vec<D> body_viscous_force(Index body_index) const;
  // The force of the projection's impermeability condition on the wall particles of one body (Project).
  Vec<D> body_contact_force(Index body_index) const;
  // The power of the moving walls on the fluid: their pressure's (from boundary_force) and their
  // viscous traction's (the last record_viscous_wall_power).
  Real moving_wall_power() const;
  // Records the power of the walls' viscous traction (ViscousWallPower) for moving_wall_power, with
  // the viscous term the model integrates over the coming step(s).
  void record_viscous_wall_power(const ViscousAcceleration<D>& viscous);

  // Structure particles follow the TLSPH solver: positions, velocities and deformation gradients,
  // indexed as in the TLSPH solver. The surface normals turn with F: n = F^{-T} N / |F^{-T} N|.
  // On the cuda device the three arrays must be device-visible (managed memory).
  void move_structure(std::span<const Vec<D>> x, std::span<const Vec<D>> v, std::span<const Mat<D>> F);
  // The structure's acceleration over the current step, indexed as in the TLSPH solver, into
  // wall_acceleration (device-visible on the cuda device).
  void follow_structure_acceleration(std::span<const Vec<D>> a);

  Real max_speed() const;  // fastest fluid particle (probes and energies: sim/probes.hpp)
  // First particle with a non-finite position, velocity or pressure, or -1.
  Index first_non_finite() const;
  // First fluid particle outside the box [lo, hi], or -1.
  Index first_outside(const Vec<D>& lo, const Vec<D>& hi) const;
  // Removes the fluid particles outside the box [lo, hi] that are also above `rim` along `up` (thrown
  // out over the walls; wall and structure particles stay); returns how many. The others keep their
  // order and stable ids.
  Index remove_fluid_outside(const Vec<D>& lo, const Vec<D>& hi, const Vec<D>& up, Real rim);
  // Fluid particles inside the body of one kind (structure or wall), and the smallest fluid-body particle
  // distance (inf if none is within the kernel support).
  InteractionReport<D> contact(FluidKind body);

  // Continues from a snapshot of the same case (a restart): positions, velocities, pressures, the time
  // and the moving walls' work, matched by stable id. Fluid particles the snapshot lacks (removed
  // after leaving the tank) are removed; a wall or structure particle it lacks, an id this case does
  // not have, or a particle of another kind is an error naming the snapshot. Where the snapshot has
  // them ("memory_row", "neighbour_searches"), the particles take the order they had in memory and the
  // search count, so that the continued run sums over neighbours in the same order.
  void restore(const SnapshotData& snapshot);

 private:
  // sum_a V_a f_a over the particles whose `owner` entry is body_index (f: a force density).
  Vec<D> owned_sum(const StateVector<Vec<D>>& force_density, const StateVector<Index>& owner, Index body_index) const;
  // Each component of sum_a V_a f_a (`component` over the first n particles, its d set per component).
  Vec<D> summed(Index n, ForceComponent<D> component) const;
  // The cell list and the neighbour list, after a re-sort by cell when `sort`.
  void build_neighbours(bool sort);
  // The inlets' buffer particles take the velocity U(x, time) n and its time derivative.
  void prescribe_inflow();
  // The outlets' buffer particles take the velocity of the fluid beside their plane (OutletVelocityPass).
  void carry_outlet_velocity();
  // Counts the fluid and wall particles again (after the open boundaries' exchange).
  void count_kinds();
  // Reorders (or, from remove_fluid_outside and restore, shrinks; from the open boundaries' exchange,
  // grows by copies) the state and the attached arrays: v[k] = v[order[k]] for k < count, `order`
  // readable by the device in use.
  void reorder(const Index* order, Index count);
  // v[k] = v_old[order[k]] for k < count, and v keeps count elements (count <= v.size()), gathered by
  // the launcher through a scratch buffer.
  template <class T>
  void permute(StateVector<T>& v, const Index* order, Index count) {
    resize_for_overwrite(permute_scratch_, std::max(permute_scratch_.size(), count * sizeof(T)));
    T* gathered = reinterpret_cast<T*>(permute_scratch_.data());
    parallel_for(exec_, count, GatherElements<T>{v.data(), order, gathered});
    v.resize(count);
    parallel_for(exec_, count, CopyElements<T>{gathered, v.data()});
  }

  Exec exec_{};
  std::vector<std::function<void(const Index*, Index)>> followers_;  // attach()
  StateVector<unsigned char> inside_;
  StateVector<Real> body_distance_, body_depth_;
  StateVector<Real> structure_volume_;    // volume of each structure particle, indexed as in TLSPH
  mutable StateVector<Index> wall_slot_;  // gather_walls: walls before each particle (entry 0 stays 0)
  StateVector<unsigned char> permute_scratch_;
  StateVector<Real> power_density_;       // per-particle work array of record_viscous_wall_power
  mutable StateVector<Real> block_sums_;  // ordered_sum's scratch
  CellList<D> cells_{exec_};
  NeighbourList neighbours_{StateVector<Index>(allocator<Index>()), StateVector<Index>(allocator<Index>())};

  Index fluid_count_ = 0, wall_count_ = 0;
  long long neighbour_searches_ = 0, order_version_ = 0;
  Real viscous_wall_power_ = 0;
  std::vector<RigidMotion<D>> motions_;
  std::vector<OpenZone<D>> open_zones_;
  StateVector<OpenZoneRow> open_rows_;   // per zone, for the PPE rows (FluidView)
  StateVector<Vec<D>> outlet_velocity_;  // carry_outlet_velocity's other buffer
  StateVector<Index> exchange_order_;    // exchange_open_boundaries' scratch, kept across steps
  std::vector<Index> exchange_entered_;
  std::vector<OpenZoneFlow> open_flows_;
  Index next_id_ = 0;  // the stable id of the next particle created
  Real density_, dx_;
  KernelTable<D> kernels_;
  int fluid_level_;
  Periodicity<D> period_;
  Vec<D> gravity_;
  bool has_structure_;
};

// What the time loop asks of a fluid model (sim/run.cpp); the models own their particle set.
template <int D>
class FluidModel {
 public:
  virtual ~FluidModel() = default;
  virtual ParticleSet<D>& particles() = 0;
  virtual const ParticleSet<D>& particles() const = 0;
  // The largest stable step of the model at the current state.
  virtual Real time_step() const = 0;
  // One step [t, t + dt] (dt at most time_step()) with the coupled structure, if any, advanced over it:
  // the projection step iterates the interface inside it (StructureCoupling::step), the weakly
  // compressible step advances the structure at each of its acoustic steps (explicit_step).
  virtual FluidStepReport step(Real t, Real dt, StructureCoupling<D>* structure, PhaseTimer& timer) = 0;
  // The pressure solver in use ("none" without a PPE), and the model's own figures for summary.json's
  // performance object.
  virtual std::string pressure_solver() const { return "none"; }
  virtual void add_performance(JsonObject& /*performance*/) const {}
  // The model's own fields for snapshots (in stable-id order: field value k belongs to particle slot[k]).
  virtual void add_snapshot_fields(const std::vector<Index>& slot, std::vector<SnapshotField>& fields) const = 0;
  // The model's own state from a snapshot, after particles().restore() (a restart).
  virtual void restore_fields(const SnapshotData&) {}
};

}  // namespace isph
