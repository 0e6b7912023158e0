#pragma once
// The TLSPH structure solver: reference configuration (neighbours, kernel gradients and the
// correction L = K^{-T}, built once), the stress and acceleration loops, and the time
// integrators (classical RK4, Eqs. 43-45, and velocity-Verlet as the second-order scheme).
//
// On the cuda device the set-up runs on the host; the arrays the loops read then move to managed
// memory (StateVector), where the device steps them and the host reads them for output. A structure
// of a few thousand particles is launch-bound (13 launches per RK4 step of a few microseconds each; 4 more with
// quadratic gradients and hourglass control, 8 more with cell quadrature), so the RK4 step is recorded once as a CUDA
// graph and replayed (LaunchGraph); it is recorded again when the step size changes or the interaction field or the
// obstacle candidates move in memory, and not used while a load ramps up or a clamp moves (their values change from
// step to step), where the launches go one by one. The substeps of a coupled fluid step (advance) are queued on the
// graph's stream with the interaction's power after each, and the host waits once, at the end, where no clamp moves (a
// moving clamp's work is read back at every stage).
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/device_memory.hpp"
#include "core/neighbour_search.hpp"
#include "core/parallel.hpp"
#include "core/rigid_motion.hpp"
#include "core/types.hpp"
#include "kernels/operators.hpp"
#include "structure/structure_options.hpp"
#include "structure/tlsph_functors.hpp"

namespace isph {

// An applied load: a per-particle acceleration at full load, ramped linearly over ramp_time.
template <int D>
struct LoadField {
  std::vector<Vec<D>> acc;
  Real ramp_time = 0;
  Real factor(Real t) const { return ramp_time > 0 && t < ramp_time ? t / ramp_time : 1.0; }
};

// The interaction fields of the substeps of one fluid step. Ramped: substep k of n applies
// from + (k + 1/2)/n (to - from) (StructureCoupling's "interpolated" alpha); held: `to`, or without it
// the field set last. With an impedance, each substep's field also answers the structure's velocity at
// the substep's start: - Gamma_a (v_a - w_a), where Gamma_a is the rate at which the fluid's pressure
// force on particle a changes with its velocity and w_a the velocity the force was evaluated with
// (StructureCoupling::explicit_step says why).
template <int D>
struct InteractionSchedule {
  const Vec<D>* from = nullptr;
  const Vec<D>* to = nullptr;
  const Mat<D>* impedance = nullptr;
  const Vec<D>* reference_velocity = nullptr;
  // The field differs from substep to substep.
  bool varies() const { return from != nullptr || impedance != nullptr; }
};

template <int D>
struct TlsphSetup {
  std::vector<Vec<D>> X;  // reference positions
  std::vector<Vec<D>> v;  // initial velocities
  std::vector<Real> volume;
  std::vector<int> material;
  std::vector<int> body;  // particles interact only within their body
  std::vector<unsigned char> fixed;
  std::vector<Index> motion;  // clamped particles: index in `motions` (-1: the clamp stands still)
  std::vector<RigidMotion<D>> motions;
  std::vector<ElasticMaterial> materials;
  std::vector<LoadField<D>> loads;
  KernelTable<D> kernels;            // one per particle spacing (a body's particles share one)
  std::vector<unsigned char> level;  // index in `kernels` per particle (empty: all on level 0)
  StructureGradient gradient = StructureGradient::linear;
  StructureQuadrature quadrature = StructureQuadrature::point;
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

// A structure's loops are short (hundreds of particles) and run tens of thousands of times per
// simulated second: from this size they take every thread. On two quiet cores the gate's structure
// phase takes 2.6 s instead of 3.6 s on one, the 2D plate's 22.7 s instead of 32.2 s (docs/PERFORMANCE.md);
// when the cores are shared, give the run fewer threads (scripts/ci/test.sh runs each test on one).
inline constexpr Index kStructureParallelLoop = 64;

template <int D>
class TlsphSolver {
 public:
  TlsphSolver(TlsphSetup<D> setup, Exec exec = {});

  // Largest step for Courant number `courant`: courant * h / c_p, c_p the P-wave speed.
  Real stable_dt(Real courant) const;
  // Advances positions and velocities from t to t + dt with the chosen integrator. On the device it
  // returns when the step is done, so that the host may read the state.
  void step(Real t, Real dt);
  // Runs `count` steps of dt / count from t under the interaction field set last, or the schedule's, and
  // returns the interaction's work over them: the trapezoidal rule on the power of each step's field at
  // the step's two ends (interaction_power()). On the device the steps and the powers are queued and the
  // host waits once, at the end (RK4 with no moving clamp).
  Real advance(Real t, Real dt, int count, InteractionSchedule<D> schedule = {});
  // Recomputes F, P and the strain energy at the current state (for output).
  void update_stress();
  // The acceleration at the current state (time t) without the interaction field: the structure's own
  // (stress, gravity, loads, contact), into `acc`.
  void own_acceleration(Real t, StateVector<Vec<D>>& acc);
  // The fluid's interaction acceleration alpha(f->s) (Eq. 48), one per particle, added to the
  // acceleration until it is set again.
  void set_interaction(std::span<const Vec<D>> acc);
  // Rigid obstacles the structure may touch (the fluid's walls; for_each_wall_overlap in
  // tlsph_functors.hpp): points with a radius, half their spacing, kept with a cell list of edge `reach`
  // until they are set again. Each particle's candidates are the points within `reach` of it, found here
  // and again by find_obstacle_candidates() (at the positions of that call, until the next).
  void set_obstacles(std::span<const Vec<D>> point, std::span<const Real> radius, Real reach);
  void find_obstacle_candidates();
  // Whether the last RK4 step on the device replayed a recorded graph (for tests and benchmarks).
  bool replayed_graph() const { return replayed_graph_; }
  // Graphs on (the default) or off: off, the device's launches go one by one (for benchmarks).
  void use_graphs(bool on) { use_graphs_ = on; }
  // Power of the interaction acceleration on the current velocities.
  Real interaction_power() const;
  // Keeps the current positions and velocities and goes back to them, so that a coupled step can be
  // repeated with another interaction field.
  void save_state();
  void restore_state();
  // Takes positions and velocities from elsewhere (a restart), indexed as this solver's particles,
  // and recomputes F and the stress. With the acceleration of the step that ended there (acceleration()),
  // velocity-Verlet goes on as if it had not stopped; without it, the explicit scheme starts afresh.
  void set_motion(std::span<const Vec<D>> x, std::span<const Vec<D>> v, std::span<const Vec<D>> acc = {});

  Index size() const { return n_; }
  Real support() const { return kernels_.largest_support(); }  // the largest of the bodies' kernels
  Index pairs() const { return static_cast<Index>(nbr_.size()); }
  long long pair_evaluations() const { return pair_evaluations_; }
  const StateVector<Vec<D>>& reference() const { return X_; }
  const StateVector<Vec<D>>& position() const { return x_; }
  const StateVector<Vec<D>>& velocity() const { return v_; }
  const StateVector<Vec<D>>& acceleration() const { return acc_; }  // of the last evaluation
  const StateVector<Mat<D>>& deformation_gradient() const { return F_; }
  const StateVector<unsigned char>& fixed() const { return fixed_; }
  Real density(Index a) const { return mass_[a] / volume_[a]; }
  Real mass(Index a) const { return mass_[a]; }
  const Vec<D>& gravity() const { return gravity_; }
  const StateVector<Index>& neighbour_offset() const { return nbr_offset_; }
  const StateVector<Index>& neighbours() const { return nbr_; }
  // Cauchy stress sigma = F S F^T / det F of particle a (from the last update_stress()).
  Mat<D> cauchy_stress(Index a) const;

  Real kinetic_energy() const;
  Real strain_energy() const;  // from the last update_stress()
  // The overlaps with obstacles at the current state: their stored energy, the deepest and their number.
  struct ObstacleContact {
    Real energy = 0, deepest = 0;
    Index pairs = 0;
  };
  ObstacleContact obstacle_contact() const;
  Real potential_energy() const;      // gravity, relative to the reference configuration
  Real external_power(Real t) const;  // power of the applied loads at time t
  // Work done on the structure by its moving clamps since the start, integrated over the steps
  // (clamp_power); 0 while the clamps stand still. A restart sets it from the snapshot.
  Real clamp_work() const { return clamp_work_; }
  void set_clamp_work(Real work) { clamp_work_ = work; }
  // The first particle with a non-finite position or velocity, or moved farther than `limit` from its
  // reference place; -1 when none (a reduction on the solver's device).
  Index first_runaway(Real limit) const;
  TlsphView<D> view();  // host view of the current state
  ObstacleView<D> obstacles() const { return {contact_offset_.data(), contact_point_.data(), contact_radius_.data()}; }

 private:
  void evaluate(const Exec& exec, Real t);  // acc at the current (x, v)
  // One RK4 step's launches. With moving clamps they also sum, into clamp_record[0..5] (memory of the
  // solver's device), the clamped particles' kinetic energy at the start, the clamps' power at each of
  // the four stages and the kinetic energy at the end, which add_clamp_work books.
  void rk4_launches(const Exec& exec, Real t, Real dt, Real* clamp_record);
  // One RK4 step sent to exec; on the device's graph stream (graph_->exec()) the recorded graph is
  // replayed where it may be (replayable), recorded first when stale. Does not wait.
  void step_rk4(const Exec& exec, Real t, Real dt, Real* clamp_record);
  // Room in clamp_record_ for `steps` RK4 steps (none without moving clamps), and the clamps' work of
  // those steps from it once they have run: read back once, not after every stage.
  Real* clamp_record(int steps);
  void add_clamp_work(int steps, Real dt);
  bool replayable(Real t) const;  // no ramping load at t, no moving clamp, graphs on
  // Whether advance() and step() queue RK4 steps on the graph's stream (device, RK4, no moving clamp).
  bool queues_steps() const;
  void step_verlet(Real t, Real dt);
  void prescribe_clamps(const Exec& exec, Real t);  // moving clamps: x and v at time t (PrescribeClamps)
  // The power a moving clamp puts into the rest of the structure, -sum_c m_c acc_c · v_c over the
  // clamped particles c, with acc_c the acceleration they would have free (from the last evaluate):
  // the clamp holds them against it. With the change of their own kinetic energy, which the clamp
  // also supplies, this is the clamp's work (clamp_work). Summed in fixed blocks (ordered_sum).
  Real clamp_power() const;
  Real clamped_kinetic_energy() const;
  PowerTerm<D> clamp_power_term() const { return {motion_.data(), mass_.data(), acc_.data(), v_.data(), -1.0}; }
  KineticEnergyTerm<D> clamped_energy_term() const { return {motion_.data(), mass_.data(), v_.data()}; }
  // m_a alpha_a · v_a, the interaction's power per particle (interaction_power, advance).
  PowerTerm<D> interaction_power_term() const { return {nullptr, mass_.data(), interaction_.data(), v_.data(), 1.0}; }
  // The particles the stress and the acceleration passes visit (TlsphView::strained, moving).
  void list_strained_particles();
  void make_state_device_visible();
  // Launches that wait for each other (the host's, or the device's one by one).
  // On the host the structure's loops take every thread from kStructureParallelLoop particles on.
  Exec waiting_exec() const { return Exec{exec_.device, nullptr, true, kStructureParallelLoop}; }
  // Where a loop over values handed in runs: on the host for values in ordinary host memory.
  Exec exec_reading(const void* values) const {
    return exec_.device == Device::cuda && !device_accessible(values) ? Exec{} : waiting_exec();
  }
  // Neighbour passes of one evaluation of the stress, and of the stress and the acceleration.
  int stress_passes() const { return 1 + (hourglass_ > 0) + 2 * cell_quadrature_; }
  int evaluation_passes() const { return stress_passes() + 1; }

  Exec exec_;
  Index n_ = 0;
  KernelTable<D> kernels_;
  std::vector<unsigned char> level_;  // host copy: the loops read the reference configuration's pair data
  StructureIntegrator integrator_;
  Vec<D> gravity_;
  Real damping_, hourglass_;
  bool quadratic_;        // quadratic-exact pair gradients (and the symmetric hourglass error)
  bool cell_quadrature_;  // StructureQuadrature::cell
  StateVector<ElasticMaterial> materials_;
  std::vector<LoadField<D>> loads_;
  StateVector<Vec<D>> load_acc_, interaction_;
  StateVector<Vec<D>> obstacle_point_;  // the obstacles (set_obstacles) and their cell list (the device's on cuda)
  StateVector<Real> obstacle_radius_;
  CellList<D> obstacle_cells_{exec_};
  StateVector<Index> contact_offset_;  // obstacle candidates per particle (find_obstacle_candidates)
  StateVector<Vec<D>> contact_point_;
  StateVector<Real> contact_radius_;
  StateVector<Vec<D>> X_, x_, v_, acc_;
  StateVector<Real> volume_, cell_moment_;
  StateVector<Real> mass_;
  StateVector<int> material_;
  StateVector<unsigned char> fixed_;
  StateVector<Index> strained_, moving_;  // empty: every particle
  StateVector<Index> motion_;
  std::vector<RigidMotion<D>> motions_;
  mutable StateVector<Real> block_sums_;  // ordered_sum's scratch
  StateVector<Real> power_record_;        // advance(): the interaction's power at each step's ends
  StateVector<Real> clamp_record_;        // rk4_launches with moving clamps: six sums per step
  Real clamp_work_ = 0, saved_clamp_work_ = 0;
  StateVector<Index> nbr_offset_, nbr_;
  StateVector<Vec<D>> cgrad_;
  StateVector<Real> hg_weight_;
  StateVector<Mat<D>> hg_moment_;  // G_a = sum_b w_ab X_ab ⊗ X_ab
  StateVector<Vec<D>> rcgrad_, cgrad_sum_;
  StateVector<Mat<D>> F_, stress_;
  StateVector<Mat<D>> strain_, gradient_stress_;  // cell quadrature only
  StateVector<Real> psi_;
  StateVector<Vec<D>> x0_, v0_, x_sum_, v_sum_;  // integrator scratch
  bool verlet_started_ = false;
  StateVector<Vec<D>> saved_x_, saved_v_;
  long long pair_evaluations_ = 0;
  // the device's RK4 step as a graph, and what it was recorded for
  std::unique_ptr<LaunchGraph> graph_;
  Real recorded_dt_ = 0;
  const Vec<D>* recorded_interaction_ = nullptr;
  const Vec<D>* recorded_contact_point_ = nullptr;
  const Real* recorded_contact_radius_ = nullptr;
  bool replayed_graph_ = false;
  bool use_graphs_ = true;
};

}  // namespace isph
