#include "sim/fluid_particles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/ordered_sum.hpp"
#include "sim/fluid_functors.hpp"
#include "structure/interaction.hpp"

namespace isph {

namespace {

// Sorting particles by cell keeps neighbours close in memory; positions drift, so re-sort this often.
constexpr long long kSortInterval = 20;

// A host vector as the state's array (in managed memory on the cuda device).
template <class T>
StateVector<T> state_copy(const std::vector<T>& v, bool device_visible) {
  return StateVector<T>(v.begin(), v.end(), StateAllocator<T>(device_visible));
}

}  // namespace

template <int D>
FluidParticles<D>::FluidParticles(FluidSetup<D>& s)
    : exec_{s.device},
      motions_(std::move(s.motions)),
      density_(s.density),
      viscosity_(s.viscosity),
      dx_(s.dx),
      reference_velocity_(s.reference_velocity),
      kernel_(s.kernel),
      period_(s.period),
      gravity_(s.gravity),
      settings_(s.settings) {
  if (exec_.device == Device::cuda && cuda_devices() == 0)
    throw std::runtime_error("--device cuda: no CUDA device is visible (or this build has no CUDA backend)");
  const std::size_t n = s.x.size();
  if (s.structure_index.empty()) s.structure_index.assign(n, -1);
  if (s.motion.empty()) s.motion.assign(n, -1);
  const bool managed = exec_.device == Device::cuda;
  x_ = state_copy(s.x, managed);
  u_ = state_copy(s.u, managed);
  volume_ = state_copy(s.volume, managed);
  wall_depth_ = state_copy(s.wall_depth, managed);
  kind_ = state_copy(s.kind, managed);
  wall_velocity_ = state_copy(s.wall_velocity, managed);
  wall_normal_ = state_copy(s.wall_normal, managed);
  reference_normal_ = wall_normal_;
  id_ = state_copy(s.id, managed);
  structure_index_ = state_copy(s.structure_index, managed);
  motion_ = state_copy(s.motion, managed);
  reference_x_ = x_;
  wall_acceleration_ = boundary_force_ = state_array(Vec<D>::zero());
  p_ = state_array(Real{0});
  for (auto* v : {&inside_, &permute_scratch_}) *v = StateVector<unsigned char>(state_allocator<unsigned char>());
  for (auto* v : {&body_distance_, &body_depth_, &power_density_, &block_sums_}) *v = StateVector<Real>(state_allocator<Real>());
  has_structure_ = std::count(s.kind.begin(), s.kind.end(), FluidKind::structure) > 0;
  fluid_count_ = static_cast<Index>(std::count(s.kind.begin(), s.kind.end(), FluidKind::fluid));
  wall_count_ = static_cast<Index>(std::count(s.kind.begin(), s.kind.end(), FluidKind::wall));
  structure_volume_ = StateVector<Real>(state_allocator<Real>());
  for (std::size_t k = 0; k < n; ++k)
    if (const Index i = s.structure_index[k]; i >= 0) {
      if (structure_volume_.size() <= static_cast<std::size_t>(i)) structure_volume_.resize(i + 1, 0);
      structure_volume_[i] = s.volume[k];
    }
}

template <int D>
const Index* FluidParticles<D>::neighbour_offset() const {
  return exec_.device == Device::cuda ? device_neighbours_.offset.data() : neighbours_.offset.data();
}

template <int D>
FluidView<D> FluidParticles<D>::view() const {
  const Index* index = exec_.device == Device::cuda ? device_neighbours_.index.data() : neighbours_.index.data();
  OperatorView<D> op{size(), x_.data(), volume_.data(), neighbour_offset(), index, kernel_, period_};
  return {op,       kind_.data(),        wall_velocity_.data(), wall_acceleration_.data(), wall_normal_.data(),
          wall_depth_.data(), dx_};
}

template <int D>
void FluidParticles<D>::find_neighbours() {
  build_neighbours(neighbour_searches_++ % kSortInterval == 0);
}

template <int D>
void FluidParticles<D>::build_neighbours(bool sort) {
  if (exec_.device == Device::cuda) {
    device_cells_.build(x_.data(), size(), kernel_.support(), period_);
    if (sort) {
      reorder(device_cells_.order().data(), size());
      device_cells_.build(x_.data(), size(), kernel_.support(), period_);
    }
    device_neighbours_ = device_neighbour_list(device_cells_, size());
    return;
  }
  cells_.build(x_, kernel_.support(), period_);
  if (sort) {
    reorder(cells_.order().data(), size());
    cells_.build(x_, kernel_.support(), period_);
  }
  neighbours_ = neighbour_list(cells_, size());
}

template <int D>
void FluidParticles<D>::reorder(const Index* order, Index count) {
  for (auto* v : {&x_, &u_, &wall_velocity_, &wall_acceleration_, &wall_normal_, &reference_normal_, &reference_x_,
                  &boundary_force_})
    permute(*v, order, count);
  for (auto* v : {&p_, &volume_, &wall_depth_}) permute(*v, order, count);
  for (auto* v : {&id_, &structure_index_, &motion_}) permute(*v, order, count);
  permute(kind_, order, count);
  permute_work(order, count);
}

template <int D>
Index FluidParticles<D>::remove_fluid_outside(const Vec<D>& lo, const Vec<D>& hi, const Vec<D>& up, Real rim) {
  StateVector<Index> keep(state_allocator<Index>());
  keep.reserve(x_.size());
  const FluidOutsideBox<D> outside{kind_.data(), x_.data(), lo, hi};
  for (Index a = 0; a < size(); ++a)
    if (!outside(a) || !(dot(x_[a], up) > rim)) keep.push_back(a);
  const Index removed = size() - static_cast<Index>(keep.size());
  if (removed > 0) {
    reorder(keep.data(), static_cast<Index>(keep.size()));
    fluid_count_ -= removed;
    build_neighbours(false);  // no stale list between now and the next step
  }
  return removed;
}

template <int D>
void FluidParticles<D>::restore(const SnapshotData& snapshot) {
  const SnapshotField &kinds = snapshot.field("kind"), &x = snapshot.field("position"), &u = snapshot.field("velocity"),
                      &p = snapshot.field("pressure");
  const std::vector<long long> row = snapshot.rows_by_id();
  const auto mismatch = [&](const std::string& what) {
    return std::runtime_error("restart: " + snapshot.path + " is not a snapshot of this case: " + what);
  };
  StateVector<Index> keep(state_allocator<Index>());
  for (Index a = 0; a < size(); ++a) {
    const long long r = static_cast<std::size_t>(id_[a]) < row.size() ? row[id_[a]] : -1;
    if (r < 0) {  // fluid the earlier run removed; every wall and structure particle must be there
      if (kind_[a] != FluidKind::fluid) throw mismatch("it lacks the wall or structure particle id " + std::to_string(id_[a]));
      continue;
    }
    if (kinds.data[r] != static_cast<double>(kind_[a]))
      throw mismatch("particle id " + std::to_string(id_[a]) + " is of another kind there");
    x_[a] = snapshot_vector<D>(x, r);
    u_[a] = snapshot_vector<D>(u, r);
    p_[a] = p.data[r];
    keep.push_back(a);
  }
  if (keep.size() != snapshot.size())
    throw mismatch("it has " + std::to_string(snapshot.size() - keep.size()) + " particles whose ids this case lacks");
  if (const Index removed = size() - static_cast<Index>(keep.size()); removed > 0) {
    reorder(keep.data(), static_cast<Index>(keep.size()));
    fluid_count_ -= removed;
  }
  time_ = snapshot.time;
  const auto work = snapshot.attributes.find("wall_work");
  wall_work_ = work != snapshot.attributes.end() ? work->second : 0;
}

template <int D>
void FluidParticles<D>::prescribe_walls(Real dt) {
  parallel_for(exec_, size(), PrescribeWalls<D>{motion_.data(), poses_at(motions_, time_), poses_at(motions_, time_ + dt), reference_x_.data(),
                                                reference_normal_.data(), dt, period_, x_.data(), u_.data(),
                                                wall_velocity_.data(), wall_acceleration_.data(), wall_normal_.data()});
}

template <int D>
void FluidParticles<D>::gather_walls(StateVector<Vec<D>>& point, StateVector<Real>& radius) const {
  const Index n = size();
  if (wall_slot_.size() != static_cast<std::size_t>(n) + 1)
    wall_slot_ = StateVector<Index>(static_cast<std::size_t>(n) + 1, 0, state_allocator<Index>());
  parallel_for(exec_, n, MarkWalls{kind_.data(), wall_slot_.data()});
  inclusive_scan(exec_, wall_slot_.data() + 1, n);
  resize_for_overwrite(point, wall_slot_[n]);  // the number of walls: one value back from the device
  resize_for_overwrite(radius, wall_slot_[n]);
  parallel_for(exec_, n, GatherWalls<D>{kind_.data(), x_.data(), volume_.data(), wall_slot_.data(), point.data(), radius.data()});
}

template <int D>
Vec<D> FluidParticles<D>::gather_structure_force(std::span<Vec<D>> force_density) const {
  parallel_for(exec_, size(), ScatterStructureForce<D>{structure_index_.data(), boundary_force_.data(), force_density.data()});
  Vec<D> total;
  for (int d = 0; d < D; ++d)
    total[d] = ordered_sum(exec_, static_cast<Index>(structure_volume_.size()),
                           ForceComponent<D>{structure_volume_.data(), force_density.data(), d}, block_sums_);
  return total;
}

// Power of the moving walls on the fluid: their pressure force's, sum_w -V_w f_w · u_w, and their
// viscous traction's.
template <int D>
Real FluidParticles<D>::moving_wall_power() const {
  return viscous_wall_power_ +
         ordered_sum(exec_, size(), MovingWallPressurePower<D>{motion_.data(), volume_.data(), boundary_force_.data(),
                                                               wall_velocity_.data()}, block_sums_);
}

template <int D>
void FluidParticles<D>::record_viscous_wall_power(const ViscousAcceleration<D>& viscous) {
  power_density_.resize(x_.size());
  parallel_for(exec_, size(), ViscousWallPower<D>{viscous, density_, power_density_.data()});
  viscous_wall_power_ = ordered_sum(exec_, size(), ScalarAt{power_density_.data()}, block_sums_);
}

template <int D>
void FluidParticles<D>::move_structure(std::span<const Vec<D>> x, std::span<const Vec<D>> v,
                                       std::span<const Mat<D>> F) {
  parallel_for(exec_, size(), FollowStructure<D>{structure_index_.data(), x.data(), v.data(), F.data(),
                                                 reference_normal_.data(), x_.data(), u_.data(), wall_velocity_.data(),
                                                 wall_normal_.data()});
}

template <int D>
void FluidParticles<D>::set_structure_acceleration(std::span<const Vec<D>> a) {
  parallel_for(exec_, size(), FollowStructureAcceleration<D>{structure_index_.data(), a.data(), wall_acceleration_.data()});
}

template <int D>
InteractionReport<D> FluidParticles<D>::contact(FluidKind body) {
  const Index n = size();
  inside_.resize(n);
  body_distance_.resize(n);
  body_depth_.resize(n);
  parallel_for(exec_, n, BodyContact<D>{view(), body, inside_.data(), body_distance_.data(), body_depth_.data()});
  InteractionReport<D> report;
  report.fluid_inside = parallel_reduce(exec_, n, Index{0}, Flagged{inside_.data()}, IntegerSum{});
  const Real nearest = parallel_reduce(exec_, n, kOutOfReach, ScalarAt{body_distance_.data()}, MinOf{});
  report.min_distance = nearest < kOutOfReach ? nearest : std::numeric_limits<Real>::infinity();
  report.max_depth = parallel_reduce(exec_, n, Real{0}, ScalarAt{body_depth_.data()}, MaxOf{});
  if (report.fluid_inside > 0) report.inside_at = x_[lowest_id_particle(exec_, n, Flagged{inside_.data()}, id_.data())];
  return report;
}

template <int D>
void ContactRecord<D>::add(const InteractionReport<D>& step, Real t) {
  if (step.fluid_inside > 0) {
    if (steps_with_inside_++ == 0) first_inside_time_ = t;
    if (step.fluid_inside > max_inside_) worst_inside_time_ = t, worst_inside_at_ = step.inside_at;
  }
  max_inside_ = std::max(max_inside_, step.fluid_inside);
  min_distance_ = std::min(min_distance_, step.min_distance);
  max_depth_ = std::max(max_depth_, step.max_depth);
}

template <int D>
void ContactRecord<D>::write(JsonObject& o, const std::string& body) const {
  o.set("fluid_inside_" + body + "_max", static_cast<long long>(max_inside_))
      .set("steps_with_fluid_inside_" + body, steps_with_inside_)
      .set("min_fluid_" + body + "_distance", std::isfinite(min_distance_) ? min_distance_ : -1.0)
      .set("max_fluid_" + body + "_depth", max_depth_);
  if (steps_with_inside_ == 0) return;
  JsonObject at;
  for (int d = 0; d < D; ++d) at.set(d == 0 ? "x" : d == 1 ? "y" : "z", worst_inside_at_[d]);
  o.set("first_fluid_inside_" + body + "_time", first_inside_time_)
      .set("max_fluid_inside_" + body + "_time", worst_inside_time_)
      .set("max_fluid_inside_" + body + "_at", at);
}

template <int D>
Real FluidParticles<D>::max_speed() const {
  return std::sqrt(parallel_reduce(exec_, size(), Real{0}, FluidSpeed2<D>{kind_.data(), u_.data()}, MaxOf{}));
}

template <int D>
Real FluidParticles<D>::kinetic_energy() const {
  Real e = 0;
  for (Index a = 0; a < size(); ++a)
    if (kind_[a] == FluidKind::fluid) e += 0.5 * density_ * volume_[a] * norm2(u_[a]);
  return e;
}

template <int D>
Real FluidParticles<D>::potential_energy() const {
  Real e = 0;
  for (Index a = 0; a < size(); ++a)
    if (kind_[a] == FluidKind::fluid) e -= density_ * volume_[a] * dot(gravity_, x_[a]);
  return e;
}

template <int D>
Real FluidParticles<D>::interpolate_pressure(const Vec<D>& point) const {
  Real num = 0, den = 0;
  for (Index b = 0; b < size(); ++b) {
    const Real w = volume_[b] * kernel_.value(std::sqrt(norm2(period_.delta(point, x_[b]))));
    num += w * p_[b];
    den += w;
  }
  return den > 0 ? num / den : 0;
}

template <int D>
Vec<D> FluidParticles<D>::interpolate_velocity(const Vec<D>& point) const {
  Vec<D> num = Vec<D>::zero();
  Real den = 0;
  for (Index b = 0; b < size(); ++b) {
    if (kind_[b] != FluidKind::fluid) continue;
    const Real w = volume_[b] * kernel_.value(std::sqrt(norm2(period_.delta(point, x_[b]))));
    num += w * u_[b];
    den += w;
  }
  return den > 0 ? (1.0 / den) * num : Vec<D>::zero();
}

template <int D>
Real FluidParticles<D>::front(Real height) const {
  Real best = -std::numeric_limits<Real>::infinity();
  for (Index a = 0; a < size(); ++a)
    if (kind_[a] == FluidKind::fluid && x_[a][D - 1] < height) best = std::max(best, x_[a][0]);
  return best;
}

template <int D>
Index FluidParticles<D>::first_non_finite() const {
  return first_particle(exec_, size(), NonFiniteState<D>{x_.data(), u_.data(), p_.data()});
}

template <int D>
Index FluidParticles<D>::first_outside(const Vec<D>& lo, const Vec<D>& hi) const {
  return first_particle(exec_, size(), FluidOutsideBox<D>{kind_.data(), x_.data(), lo, hi});
}

template class FluidParticles<2>;
template class FluidParticles<3>;
template class ContactRecord<2>;
template class ContactRecord<3>;

}  // namespace isph
