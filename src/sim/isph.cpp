#include "sim/isph.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/ordered_sum.hpp"
#include "poisson/ppe_assembly.hpp"
#include "sim/coupling.hpp"
#include "sim/fluid_functors.hpp"
#include "structure/interaction.hpp"

namespace isph {

namespace {

SolverSettings solver_settings(const PpeSolverSpec& s, SolverBackend backend, int dimension) {
  SolverSettings out;
  out.dimension = dimension;
  out.backend = backend;
  out.method = s.method;
  out.preconditioner = s.preconditioner;
  if (backend != s.backend)  // the fallback keeps the method and takes its backend's best preconditioner
    out.preconditioner = solver_preconditioners(backend).front();
  out.tolerance = s.tolerance;
  out.max_iterations = s.max_iterations;
  return out;
}

// row_of_id[id_a] = a: the rows of the particles at the preconditioner's set-up, by stable id.
struct RowOfId {
  const Index* id;
  Index* row_of_id;
  ISPH_HD void operator()(Index a) const { row_of_id[id[a]] = a; }
};
// origin_a = the set-up's row of particle a, or -1 for a particle created since.
struct RowOrigin {
  const Index* id;
  const Index* row_of_id;
  Index ids;  // row_of_id's size
  Index* origin;
  ISPH_HD void operator()(Index a) const { origin[a] = id[a] < ids ? row_of_id[id[a]] : -1; }
};

}  // namespace

template <int D>
IsphSolver<D>::IsphSolver(FluidSetup<D> s)
    : particles_(s),
      exec_(particles_.exec()),
      density_(s.density),
      viscosity_(s.viscosity),
      reference_velocity_(s.reference_velocity),
      kernel_(s.fluid_kernel()),
      gravity_(s.gravity),
      settings_(s.settings),
      kernel_correction_(s.kernel_correction),
      shifting_(s.settings.shifting.type),
      extrapolate_surface_(s.settings.surface_pressure == SurfacePressure::extrapolated),
      fsi_shifting_(s.fsi_shifting),
      fsi_shifting_law_(s.fsi_shifting_law),
      pairwise_force_(s.interaction_force == InteractionForce::pairwise),
      wall_force_(s.wall_force),
      wall_friction_(s.wall_friction) {
  ParticleSet<D>& ps = particles_;
  for (auto* v : {&x_old_, &u_star_, &u_new_, &u_collided_, &grad_p_, &surface_normal_, &shift_, &wall_moment_})
    *v = ps.array(Vec<D>::zero());
  for (auto* v : {&L_, &Bhat_, &L_structure_}) *v = ps.array(Mat<D>::identity());
  grad_u_ = ps.array(Mat<D>::zero());
  div_r_ = ps.array(Real{D});
  alpha_ = ps.array(Real{1});
  for (auto* v : {&div_u_star_, &eddy_viscosity_, &pressure_volume_, &rhs_, &p_trial_}) *v = ps.array(Real{0});
  block_sums_ = box_totals_ = StateVector<double>(ps.template allocator<double>());
  resize_for_overwrite(box_totals_, 2);
  for (auto* v : {&detected_, &cls_}) *v = ps.array(SurfaceClass::interior);
  setup_row_of_id_ = row_origin_ = ps.array(Index{-1});
  // The work arrays are refilled every step before they are read; they follow the particles anyway, so
  // that their sizes follow a removal and the snapshot fields (classes, div r, shift) stay aligned.
  // p_trial_ is a copy of the pressure from each solve on.
  for (auto* v : {&x_old_, &u_star_, &u_new_, &u_collided_, &grad_p_, &surface_normal_, &shift_, &wall_moment_})
    ps.attach(*v);
  for (auto* v : {&L_, &Bhat_, &grad_u_, &L_structure_}) ps.attach(*v);
  for (auto* v : {&div_r_, &alpha_, &div_u_star_, &eddy_viscosity_, &pressure_volume_, &rhs_}) ps.attach(*v);
  ps.attach(detected_);
  ps.attach(cls_);
  for (auto* m : {&full_matrix_, &matrix_}) {
    m->row_offset = StateVector<int>(ps.template allocator<int>());
    m->col = StateVector<int>(ps.template allocator<int>());
    m->val = StateVector<double>(ps.template allocator<double>());
  }
  full_kernel_sum_ = lattice_kernel_sum(kernel_, s.dx);
  const Real full = D;  // div r in a full support
  thresholds_.chi = settings_.surface_threshold > 0 ? settings_.surface_threshold : full - 0.6;
  thresholds_.chi_full = settings_.surface_full > 0 ? settings_.surface_full : full - 0.4;
  solver_ = make_linear_solver(solver_settings(settings_.ppe, settings_.ppe.backend, D));
  if (settings_.ppe.fallback != FallbackSolver::none)
    fallback_ = make_linear_solver(solver_settings(
        settings_.ppe, settings_.ppe.fallback == FallbackSolver::hypre ? SolverBackend::hypre : SolverBackend::eigen,
        D));
  solver_name_ = solver_->name();
}

template <int D>
void IsphSolver<D>::compress_matrix() {
  const CsrMatrix& full = full_matrix_;
  const Index n = full.rows;
  matrix_.rows = n;
  matrix_.row_offset.resize(n + 1);  // filled by the loop, not on the host (managed memory stays on the device)
  parallel_for(exec_, n + 1,
               CountRowEntries{full.row_offset.data(), full.col.data(), full.val.data(), matrix_.row_offset.data()});
  inclusive_scan(exec_, matrix_.row_offset.data(), n + 1);
  resize_for_overwrite(matrix_.col, matrix_.row_offset[n]);
  resize_for_overwrite(matrix_.val, matrix_.row_offset[n]);
  parallel_for(exec_, n,
               CompactRow{.row_offset = full.row_offset.data(),
                          .col = full.col.data(),
                          .val = full.val.data(),
                          .out_offset = matrix_.row_offset.data(),
                          .out_col = matrix_.col.data(),
                          .out_val = matrix_.val.data()});
}

template <int D>
Real IsphSolver<D>::time_step() const {
  const Real h = kernel_.h;
  const Real u = std::max(particles_.max_speed(), reference_velocity_);
  Real dt = settings_.courant * h / u;  // Eq. 49
  const Real nu_max =
      viscosity_ + parallel_reduce(exec_, particles_.size(), Real{0}, ScalarAt{eddy_viscosity_.data()}, MaxOf{});
  if (nu_max > 0) dt = std::min(dt, settings_.viscous_number * h * h / nu_max);
  if (settings_.max_dt > 0) dt = std::min(dt, settings_.max_dt);
  return dt;
}

template <int D>
FluidStepReport IsphSolver<D>::step(Real t, Real dt, StructureCoupling<D>* structure, PhaseTimer& timer) {
  return structure ? structure->step(t, dt, *this, timer) : step(dt, timer);
}

template <int D>
FluidStepReport IsphSolver<D>::step(Real dt, PhaseTimer& timer) {
  FluidStepReport report;
  begin_step(dt, timer);
  solve_pressure(report, timer);
  if (!report.ppe_failed) end_step(dt, timer);
  return report;
}

template <int D>
void IsphSolver<D>::begin_step(Real dt, PhaseTimer& timer) {
  if (particles_.has_moving_walls()) timer.time("wall_motion", [&] { particles_.prescribe_walls(dt); });
  timer.time("neighbours", [&] { drift_and_find_neighbours(dt); });
  const FluidView<D> v = particles_.view();
  FluidView<D> pv = v;  // the pressure stages' view: dry walls have no volume (PressureVolume)
  pv.op.volume = pressure_volume_.data();
  timer.time("predictor", [&] { predict_velocity(v, dt); });
  Index pinned = -1;
  timer.time("free_surface", [&] { pinned = detect_free_surface(v, pv); });
  timer.time("ppe_assembly", [&] { assemble_ppe(pv, dt, pinned); });
}

// Eq. 11: r* = r^n + dt u^n (walls move with their prescribed velocity). The neighbours are found at r*,
// where the particles may be re-sorted; r^n is then recovered as r* - dt u^n.
template <int D>
void IsphSolver<D>::drift_and_find_neighbours(Real dt) {
  const Index n = particles_.size();
  parallel_for(exec_, n,
               Drift<D>{.kind = particles_.kind.data(),
                        .u = particles_.velocity.data(),
                        .wall_velocity = particles_.wall_velocity.data(),
                        .step = dt,
                        .wrap = true,
                        .period = particles_.period(),
                        .from = particles_.position.data(),
                        .to = particles_.position.data()});
  particles_.find_neighbours();
  parallel_for(exec_, n,
               Drift<D>{.kind = particles_.kind.data(),
                        .u = particles_.velocity.data(),
                        .wall_velocity = particles_.wall_velocity.data(),
                        .step = -dt,
                        .wrap = false,
                        .period = particles_.period(),
                        .from = particles_.position.data(),
                        .to = x_old_.data()});
}

// Eqs. 10, 12-13: intermediate velocity at r* from gravity and viscosity.
template <int D>
void IsphSolver<D>::predict_velocity(const FluidView<D>& v, Real dt) {
  const Index n = particles_.size();
  const bool sps = settings_.turbulence == Turbulence::sps;
  if (kernel_correction_) parallel_for(exec_, n, LaplacianRenormalisation<D>{v.op, L_.data(), Bhat_.data()});
  parallel_for(exec_, n,
               VelocityGradient<D>{.v = v,
                                   .L = L_.data(),
                                   .u = particles_.velocity.data(),
                                   .no_slip = true,
                                   .smagorinsky = sps ? settings_.smagorinsky : 0.0,
                                   .grad = grad_u_.data(),
                                   .eddy_viscosity = eddy_viscosity_.data()});
  const ViscousAcceleration<D> viscous{
      v, Bhat_.data(), grad_u_.data(), particles_.velocity.data(), sps ? eddy_viscosity_.data() : nullptr, viscosity_};
  parallel_for(exec_, n, VelocityPredictor<D>{viscous, gravity_, dt, u_star_.data()});
  if (particles_.has_moving_walls()) particles_.record_viscous_wall_power(viscous);
  // The structure feels the shear the predictor gave the fluid beside it (and answers it in its
  // substeps where it matters: sim/coupling.hpp).
  if (particles_.has_structure() && viscosity_ > 0) particles_.record_viscous_force(viscous, FluidKind::structure);
}

// Free surface (Fig. 2) and Skillen's coefficient (Eq. 17); returns the particle whose pressure is
// pinned where no row carries the surface condition (-1 when one does).
template <int D>
Index IsphSolver<D>::detect_free_surface(const FluidView<D>& v, const FluidView<D>& pv) {
  const Index n = particles_.size();
  Index pinned = -1;
  parallel_for(exec_, n,
               SurfaceDetection<D>{.v = v,
                                   .thresholds = thresholds_,
                                   .detect = settings_.free_surface,
                                   .div_r = div_r_.data(),
                                   .cls = detected_.data(),
                                   .alpha = alpha_.data()});
  parallel_for(exec_, n, NearSurfaceDetection<D>{v, detected_.data(), cls_.data()});
  // p is defined up to a constant without a Dirichlet row (an outlet's are): fix it at the fluid particle
  // of lowest id.
  if (!particles_.has_outlet() &&
      parallel_reduce(exec_, n, Index{0}, DirichletRow{particles_.kind.data(), alpha_.data()}, IntegerSum{}) == 0)
    pinned = lowest_id_particle(exec_, n, IsFluid{particles_.kind.data()}, particles_.id.data());
  parallel_for(exec_, n, PressureVolume<D>{v, alpha_.data(), pressure_volume_.data()});
  if (kernel_correction_) parallel_for(exec_, n, GradientCorrection<D>{pv.op, L_.data()});
  parallel_for(exec_, n,
               SurfaceNormal<D>{.v = pv,
                                .L = L_.data(),
                                .cls = cls_.data(),
                                .alpha = alpha_.data(),
                                .surface_normal = surface_normal_.data()});
  return pinned;
}

// Eqs. 14-16: the PPE assembled as CSR; its source is div u*, or div(u* + ((1 - theta)/theta) u^n) with
// fluid.constraint_weight theta < 1 (ConstrainedVelocity).
template <int D>
void IsphSolver<D>::assemble_ppe(const FluidView<D>& pv, Real dt, Index pinned) {
  const Index n = particles_.size();
  const Vec<D>* source_velocity = u_star_.data();
  if (const Real theta = settings_.constraint_weight; theta < 1) {  // u_new_ is free until the projection
    parallel_for(
        exec_, n,
        ConstrainedVelocity<D>{u_star_.data(), particles_.velocity.data(), (1 - theta) / theta, u_new_.data()});
    source_velocity = u_new_.data();
  }
  parallel_for(exec_, n, CorrectedDivergence<D>{pv.op, L_.data(), source_velocity, div_u_star_.data()});
  if (pinned >= 0) {  // a box fixed at one particle: a source of zero sum (FluidVolumeSum)
    const FluidKind* kind = particles_.kind.data();
    const Real* volume = particles_.volume.data();
    ordered_sum_into(exec_, n, FluidVolumeSum{kind, volume, div_u_star_.data()}, block_sums_, box_totals_.data());
    ordered_sum_into(exec_, n, FluidVolumeSum{kind, volume, nullptr}, block_sums_, box_totals_.data() + 1);
    parallel_for(exec_, n, RemoveFromFluid{kind, box_totals_.data(), div_u_star_.data()});
  }
  full_matrix_.rows = n;
  full_matrix_.row_offset.resize(n + 1);
  parallel_for(exec_, n + 1, PpeRowOffsets{particles_.neighbour_offset(), full_matrix_.row_offset.data()});
  resize_for_overwrite(full_matrix_.col, full_matrix_.row_offset[n]);
  resize_for_overwrite(full_matrix_.val, full_matrix_.row_offset[n]);
  parallel_for(exec_, n,
               PpeRowFill<D>{.v = pv,
                             .L = L_.data(),
                             .alpha = alpha_.data(),
                             .div_u_star = div_u_star_.data(),
                             .density = density_,
                             .dt = dt,
                             .gravity = gravity_,
                             .cls = cls_.data(),
                             .surface_normal = surface_normal_.data(),
                             .extrapolate_surface = extrapolate_surface_,
                             .pinned = pinned,
                             .col = full_matrix_.col.data(),
                             .val = full_matrix_.val.data(),
                             .rhs = rhs_.data(),
                             .wall_moment = wall_moment_.data(),
                             .structure_index = particles_.structure_index.data(),
                             .structure_inverse_density = structure_inverse_density_,
                             .added_mass = added_mass_,
                             .density_relaxation = settings_.density_relaxation,
                             .full_kernel_sum = full_kernel_sum_});
  compress_matrix();
  solves_since_assembly_ = 0;
}

template <int D>
void IsphSolver<D>::warm_start() {
  p_trial_.resize(particles_.pressure.size());  // allocated once: the copy runs on the particles' device
  parallel_for(exec_, particles_.size(), CopyElements<Real>{particles_.pressure.data(), p_trial_.data()});
}

// What the solve keeps: the matrix between interface iterations; the preconditioner across steps
// (settings_.ppe.preconditioner_reuse) while a solve with it needs no more than twice the iterations of
// the first after its set-up (plus two). Re-sorted, created and removed particles are followed by their
// stable ids (rows_since_setup), so that the open boundaries' exchange and the re-sorts do not drop it.
template <int D>
MatrixReuse IsphSolver<D>::matrix_reuse() const {
  if (solves_since_assembly_ > 0) return MatrixReuse::all;
  const bool fresh_enough =
      preconditioner_age_ < settings_.ppe.preconditioner_reuse && last_first_iterations_ <= 2 * setup_iterations_ + 2;
  return fresh_enough ? MatrixReuse::preconditioner : MatrixReuse::none;
}

// For each particle the row it had when the preconditioner was set up (-1: created since); empty while
// the particles keep that order, or when the solve keeps nothing.
template <int D>
std::span<const Index> IsphSolver<D>::rows_since_setup(MatrixReuse reuse) {
  if (reuse == MatrixReuse::none || particles_.order_version() == preconditioner_order_) return {};
  const Index n = particles_.size();
  resize_for_overwrite(row_origin_, n);
  parallel_for(exec_, n,
               RowOrigin{.id = particles_.id.data(),
                         .row_of_id = setup_row_of_id_.data(),
                         .ids = static_cast<Index>(setup_row_of_id_.size()),
                         .origin = row_origin_.data()});
  return {row_origin_.data(), row_origin_.size()};
}

template <int D>
void IsphSolver<D>::remember_setup_rows() {
  preconditioner_order_ = particles_.order_version();
  const Index ids = particles_.next_id();
  resize_for_overwrite(setup_row_of_id_, ids);
  parallel_for(exec_, ids, SetElements<Index>{setup_row_of_id_.data(), Index{-1}});
  parallel_for(exec_, particles_.size(), RowOfId{particles_.id.data(), setup_row_of_id_.data()});
}

template <int D>
void IsphSolver<D>::solve_pressure(FluidStepReport& report, PhaseTimer& timer, double tolerance) {
  timer.time("ppe_solve", [&] {
    const double case_tolerance = solver_->tolerance(), fallback_tolerance = fallback_ ? fallback_->tolerance() : 0;
    if (tolerance > 0) {
      solver_->set_tolerance(tolerance);
      if (fallback_) fallback_->set_tolerance(tolerance);
    }
    warm_start();
    const MatrixReuse reuse = matrix_reuse();
    report.ppe = solver_->solve(matrix_, rhs_, p_trial_, reuse, rows_since_setup(reuse));
    int iterations = report.ppe.iterations;                         // of this solve, the fallback's included
    if (!report.ppe.converged && solver_->kept_preconditioner()) {  // an old preconditioner may be why
      warm_start();
      report.ppe = solver_->solve(matrix_, rhs_, p_trial_, MatrixReuse::none);
      iterations += report.ppe.iterations;
    }
    if (reuse != MatrixReuse::all) {  // the step's first solve: keep count of the preconditioner's use
      if (solver_->kept_preconditioner()) {
        ++preconditioner_age_;
      } else if (solver_->built_preconditioner()) {
        preconditioner_age_ = 0;
        setup_iterations_ = report.ppe.iterations;
        remember_setup_rows();
      }
      last_first_iterations_ = report.ppe.iterations;
    }
    ++solves_since_assembly_;
    report.ppe_solver = solver_->name();
    if (!report.ppe.converged && fallback_) {
      warm_start();
      report.ppe = fallback_->solve(matrix_, rhs_, p_trial_);
      report.ppe_solver = fallback_->name();
      iterations += report.ppe.iterations;
      if (!report.ppe.converged) report.ppe.iterations = iterations;
    }
    ++report.ppe_solves;
    report.ppe_iterations += iterations;
    report.ppe_max_iterations = std::max(report.ppe_max_iterations, iterations);
    report.ppe_failed = !report.ppe.converged;
    if (!report.ppe_failed) particles_.pressure.swap(p_trial_);
    if (tolerance > 0) {
      solver_->set_tolerance(case_tolerance);
      if (fallback_) fallback_->set_tolerance(fallback_tolerance);
    }
  });
}

template <int D>
void IsphSolver<D>::end_step(Real dt, PhaseTimer& timer) {
  const FluidView<D> v = particles_.view();
  FluidView<D> pv = v;
  pv.op.volume = pressure_volume_.data();
  timer.time("projection", [&] { project_and_advance(v, pv, dt); });
  if (shifting_ != ShiftingType::none) timer.time("shifting", [&] { shift_particles(pv, dt); });
  if (particles_.has_moving_walls())
    timer.time("wall_motion", [&] {
      boundary_pressure_force(true, FluidKind::wall);
      particles_.wall_work += dt * particles_.moving_wall_power();
    });
  else if (wall_force_)
    timer.time("wall_force", [&] { boundary_pressure_force(true, FluidKind::wall); });
  if (wall_friction_)  // with the new velocity (the flux form reads neither B^ nor G)
    timer.time("wall_force", [&] {
      const bool sps = settings_.turbulence == Turbulence::sps;
      particles_.record_viscous_force(
          ViscousAcceleration<D>{v, Bhat_.data(), grad_u_.data(), particles_.velocity.data(),
                                 sps ? eddy_viscosity_.data() : nullptr, viscosity_},
          FluidKind::wall);
    });
  particles_.time += dt;
  if (!particles_.open_zones().empty()) timer.time("open_boundaries", [&] { particles_.exchange_open_boundaries(dt); });
}

// Eqs. 18-19: projection and position update.
template <int D>
void IsphSolver<D>::project_and_advance(const FluidView<D>& v, const FluidView<D>& pv, Real dt) {
  const Index n = particles_.size();
  parallel_for(exec_, n, CorrectedGradient<D>{pv.op, L_.data(), particles_.pressure.data(), grad_p_.data()});
  parallel_for(exec_, n,
               Project<D>{.v = v,
                          .grad_p = grad_p_.data(),
                          .u_star = u_star_.data(),
                          .density = density_,
                          .dt = dt,
                          .u_new = u_new_.data(),
                          .kinematic_walls = settings_.free_surface,
                          .body = particles_.body.data(),
                          .contact_force = wall_friction_ ? particles_.contact_force.data() : nullptr,
                          .contact_body = particles_.contact_body.data()});
  if (settings_.collision.distance > 0) {
    parallel_for(exec_, n,
                 ParticleCollision<D>{.v = v,
                                      .u = u_new_.data(),
                                      .distance = settings_.collision.distance * v.dx,
                                      .restitution = settings_.collision.restitution,
                                      .out = u_collided_.data()});
    u_new_.swap(u_collided_);
  }
  parallel_for(exec_, n,
               Advance<D>{.kind = particles_.kind.data(),
                          .wall_velocity = particles_.wall_velocity.data(),
                          .u_new = u_new_.data(),
                          .x_old = x_old_.data(),
                          .dt = dt,
                          .period = particles_.period(),
                          .u = particles_.velocity.data(),
                          .x = particles_.position.data()});
}

// Eqs. 20-26, 31-32: shifting at r^{n+1}, with the neighbour list, classes and surface normals of r*.
template <int D>
void IsphSolver<D>::shift_particles(const FluidView<D>& pv, Real dt) {
  const Index n = particles_.size();
  if (kernel_correction_) parallel_for(exec_, n, GradientCorrection<D>{pv.op, L_.data()});
  const Real zeta = particles_.max_speed() * dt;
  parallel_for(exec_, n,
               ShiftDisplacement<D>{.v = pv,
                                    .volume = particles_.volume.data(),
                                    .cls = cls_.data(),
                                    .surface_normal = surface_normal_.data(),
                                    .type = shifting_,
                                    .coefficient = settings_.shifting.coefficient,
                                    .zeta = zeta,
                                    .max_shift = settings_.shifting.max_fraction * kernel_.h,
                                    .fsi_layer = fsi_shifting_ && particles_.has_structure(),
                                    .fsi_law = fsi_shifting_law_,
                                    .velocity = particles_.velocity.data(),
                                    .dt = dt,
                                    .shift = shift_.data()});
  if (settings_.shifting.taylor_correction) {
    parallel_for(exec_, n,
                 VelocityGradient<D>{.v = pv,
                                     .L = L_.data(),
                                     .u = particles_.velocity.data(),
                                     .no_slip = false,
                                     .smagorinsky = 0.0,
                                     .grad = grad_u_.data(),
                                     .eddy_viscosity = nullptr});
    parallel_for(exec_, n, CorrectedGradient<D>{pv.op, L_.data(), particles_.pressure.data(), grad_p_.data()});
    parallel_for(exec_, n,
                 TaylorCorrection<D>{.v = pv,
                                     .cls = cls_.data(),
                                     .shift = shift_.data(),
                                     .grad_u = grad_u_.data(),
                                     .grad_p = grad_p_.data(),
                                     .u = particles_.velocity.data(),
                                     .p = particles_.pressure.data(),
                                     .u_out = u_new_.data(),
                                     .p_out = p_trial_.data()});
    particles_.velocity.swap(u_new_);
    particles_.pressure.swap(p_trial_);
  }
  parallel_for(exec_, n, ApplyShift<D>{shift_.data(), particles_.period(), particles_.position.data()});
}

template <int D>
void IsphSolver<D>::boundary_pressure_force(bool pairwise, FluidKind target) {
  parallel_for(exec_, particles_.size(),
               BoundaryPressureForce<D>{.v = particles_.view(),
                                        .p = particles_.pressure.data(),
                                        .L = L_structure_.data(),
                                        .grad_p = grad_p_.data(),
                                        .force_density = particles_.boundary_force.data(),
                                        .pairwise = pairwise,
                                        .target = target});
}

template <int D>
void IsphSolver<D>::set_structure_acceleration(std::span<const Vec<D>> a) {
  particles_.follow_structure_acceleration(a);
  parallel_for(exec_, particles_.size(),
               StructureRowRhs<D>{.structure_index = particles_.structure_index.data(),
                                  .acceleration = a.data(),
                                  .gravity = gravity_,
                                  .wall_moment = wall_moment_.data(),
                                  .rhs = rhs_.data()});
}

template <int D>
void IsphSolver<D>::structure_row_directions(std::span<Vec<D>> direction) const {
  parallel_for(exec_, particles_.size(),
               ScatterToStructure<D>{particles_.structure_index.data(), wall_moment_.data(), true, direction.data()});
}

template <int D>
Vec<D> IsphSolver<D>::structure_pressure_force(std::span<Vec<D>> force_density) {
  boundary_pressure_force(pairwise_force_, FluidKind::structure);
  return particles_.gather_structure_force(force_density);
}

template <int D>
void IsphSolver<D>::add_snapshot_fields(const std::vector<Index>& slot, std::vector<SnapshotField>& fields) const {
  const std::size_t n = slot.size();
  SnapshotField surface{"surface_class", 1, std::vector<double>(n)}, div_r{"div_r", 1, std::vector<double>(n)};
  SnapshotField shift{"shift", 3, std::vector<double>(3 * n, 0.0)};
  for (std::size_t k = 0; k < n; ++k) {
    const Index a = slot[k];
    surface.data[k] = static_cast<double>(cls_[a]);
    div_r.data[k] = div_r_[a];
    for (int d = 0; d < D; ++d) shift.data[3 * k + d] = shift_[a][d];
  }
  fields.insert(fields.end(), {surface, div_r, shift});
}

template class IsphSolver<2>;
template class IsphSolver<3>;

}  // namespace isph
