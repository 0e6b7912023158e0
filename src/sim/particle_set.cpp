#include "sim/particle_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

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
ParticleSet<D>::ParticleSet(FluidSetup<D>& s)
    : exec_{s.device},
      motions_(std::move(s.motions)),
      open_zones_(std::move(s.open_zones)),
      density_(s.density),
      dx_(s.dx),
      kernels_(s.kernels),
      fluid_level_(s.fluid_level),
      period_(s.period),
      gravity_(s.gravity) {
  if (exec_.device == Device::cuda && cuda_devices() == 0)
    throw std::runtime_error("--device cuda: no CUDA device is visible (or this build has no CUDA backend)");
  const std::size_t n = s.x.size();
  if (s.structure_index.empty()) s.structure_index.assign(n, -1);
  if (s.motion.empty()) s.motion.assign(n, -1);
  if (s.body.empty()) s.body.assign(n, -1);
  if (s.level.empty()) s.level.assign(n, static_cast<unsigned char>(s.fluid_level));
  if (s.open_zone.empty()) s.open_zone.assign(n, -1);
  const bool managed = exec_.device == Device::cuda;
  position = state_copy(s.x, managed);
  velocity = state_copy(s.u, managed);
  volume = state_copy(s.volume, managed);
  level = state_copy(s.level, managed);
  wall_depth = state_copy(s.wall_depth, managed);
  kind = state_copy(s.kind, managed);
  wall_velocity = state_copy(s.wall_velocity, managed);
  wall_normal = state_copy(s.wall_normal, managed);
  reference_normal = wall_normal;
  id = state_copy(s.id, managed);
  structure_index = state_copy(s.structure_index, managed);
  motion = state_copy(s.motion, managed);
  body = state_copy(s.body, managed);
  open_zone = state_copy(s.open_zone, managed);
  reference_position = position;
  wall_acceleration = boundary_force = viscous_force = contact_force = array(Vec<D>::zero());
  contact_body = array(Index{-1});
  pressure = viscous_impedance = array(Real{0});
  for (auto* v : {&inside_, &permute_scratch_}) *v = StateVector<unsigned char>(allocator<unsigned char>());
  for (auto* v : {&body_distance_, &body_depth_, &power_density_, &block_sums_})
    *v = StateVector<Real>(allocator<Real>());
  has_structure_ = std::count(s.kind.begin(), s.kind.end(), FluidKind::structure) > 0;
  fluid_count_ = static_cast<Index>(std::count(s.kind.begin(), s.kind.end(), FluidKind::fluid));
  wall_count_ = static_cast<Index>(std::count(s.kind.begin(), s.kind.end(), FluidKind::wall));
  structure_volume_ = StateVector<Real>(allocator<Real>());
  open_rows_ = StateVector<OpenZoneRow>(allocator<OpenZoneRow>());
  outlet_velocity_ = StateVector<Vec<D>>(allocator<Vec<D>>());
  exchange_order_ = StateVector<Index>(allocator<Index>());
  for (const OpenZone<D>& z : open_zones_) open_rows_.push_back({z.outlet, z.pressure});
  open_flows_.assign(open_zones_.size(), {});
  for (std::size_t k = 0; k < n; ++k) next_id_ = std::max(next_id_, s.id[k] + 1);
  prescribe_inflow();
  for (std::size_t k = 0; k < n; ++k)
    if (const Index i = s.structure_index[k]; i >= 0) {
      if (structure_volume_.size() <= static_cast<std::size_t>(i)) structure_volume_.resize(i + 1, 0);
      structure_volume_[i] = s.volume[k];
    }
}

template <int D>
const Index* ParticleSet<D>::neighbour_offset() const {
  return neighbours_.offset.data();
}

template <int D>
FluidView<D> ParticleSet<D>::view() const {
  const Index* index = neighbours_.index.data();
  const OperatorView<D> op{size(), position.data(), volume.data(), neighbour_offset(),
                           index,  kernels_,        period_,       kernels_.levels > 1 ? level.data() : nullptr};
  const bool open = !open_zones_.empty();
  return {op,
          kind.data(),
          wall_velocity.data(),
          wall_acceleration.data(),
          wall_normal.data(),
          wall_depth.data(),
          dx_,
          open ? open_zone.data() : nullptr,
          open ? open_rows_.data() : nullptr};
}

template <int D>
void ParticleSet<D>::find_neighbours() {
  build_neighbours(neighbour_searches_++ % kSortInterval == 0);
}

template <int D>
void ParticleSet<D>::build_neighbours(bool sort) {
  const Real radius = kernels_.largest_support();
  cells_.build(position.data(), size(), radius, period_);
  if (sort) {
    reorder(cells_.order().data(), size());
    cells_.build(position.data(), size(), radius, period_);
  }
  fill_neighbour_list(exec_, cells_.view(nullptr, kernels_.reach(level.data())), size(), neighbours_);
}

template <int D>
void ParticleSet<D>::reorder(const Index* order, Index count) {
  for (auto* v : {&position, &velocity, &wall_velocity, &wall_acceleration, &wall_normal, &reference_normal,
                  &reference_position, &boundary_force, &viscous_force, &contact_force})
    permute(*v, order, count);
  for (auto* v : {&pressure, &volume, &wall_depth, &viscous_impedance}) permute(*v, order, count);
  for (auto* v : {&id, &structure_index, &motion, &body, &open_zone, &contact_body}) permute(*v, order, count);
  permute(kind, order, count);
  permute(level, order, count);
  for (const auto& follow : followers_) follow(order, count);
  ++order_version_;
}

template <int D>
Index ParticleSet<D>::remove_fluid_outside(const Vec<D>& lo, const Vec<D>& hi, const Vec<D>& up, Real rim) {
  StateVector<Index> keep(allocator<Index>());
  keep.reserve(position.size());
  const FluidOutsideBox<D> outside{kind.data(), position.data(), lo, hi};
  for (Index a = 0; a < size(); ++a)
    if (!outside(a) || !(dot(position[a], up) > rim)) keep.push_back(a);
  const Index removed = size() - static_cast<Index>(keep.size());
  if (removed > 0) {
    reorder(keep.data(), static_cast<Index>(keep.size()));
    fluid_count_ -= removed;
    build_neighbours(false);  // no stale list between now and the next step
  }
  return removed;
}

template <int D>
bool ParticleSet<D>::has_outlet() const {
  return std::any_of(open_zones_.begin(), open_zones_.end(), [](const OpenZone<D>& z) { return z.outlet; });
}

template <int D>
void ParticleSet<D>::prescribe_inflow() {
  constexpr Real dt = 1e-6;  // the acceleration by a central difference in time
  for (Index a = 0; a < size(); ++a) {
    const Index z = open_zone[a];
    if (z < 0 || open_zones_[z].outlet) continue;
    const OpenZone<D>& zone = open_zones_[z];
    const Real u = zone.speed(position[a], time);
    velocity[a] = wall_velocity[a] = u * zone.normal;
    if (zone.steady_at(time)) {
      wall_acceleration[a] = Vec<D>::zero();
      continue;
    }
    const Real before = zone.speed(position[a], std::max(time - dt, Real{0})),
               after = zone.speed(position[a], time + dt);
    wall_acceleration[a] = ((after - before) / (time + dt - std::max(time - dt, Real{0}))) * zone.normal;
  }
}

template <int D>
void ParticleSet<D>::carry_outlet_velocity() {
  if (!has_outlet()) return;
  Real thickness = 0;
  for (const OpenZone<D>& z : open_zones_) thickness = std::max(thickness, z.thickness);
  const int passes = static_cast<int>(std::ceil(thickness / dx_ - 1e-9)) + 1;
  outlet_velocity_.resize(position.size());
  const FluidView<D> v = view();
  for (int pass = 0; pass < passes; ++pass) {
    parallel_for(exec_, size(),
                 OutletVelocityPass<D>{v, velocity.data(), outlet_velocity_.data(),
                                       pass == passes - 1 ? wall_velocity.data() : nullptr});
    velocity.swap(outlet_velocity_);
  }
}

template <int D>
void ParticleSet<D>::count_kinds() {
  fluid_count_ = wall_count_ = 0;
  for (Index a = 0; a < size(); ++a) {
    fluid_count_ += kind[a] == FluidKind::fluid;
    wall_count_ += kind[a] == FluidKind::wall;
  }
}

// Sequential and in particle order, so that the new particles' ids and places repeat exactly.
template <int D>
void ParticleSet<D>::exchange_open_boundaries(Real dt) {
  if (open_zones_.empty()) return;
  const Index n = size();
  carry_outlet_velocity();
  StateVector<Index>& order = exchange_order_;      // the particles kept, then the inlet crossers' copies
  std::vector<Index>& entered = exchange_entered_;  // inlet crossers, by their index in `order`
  order.clear();
  entered.clear();
  for (Index a = 0; a < n; ++a) {
    Index z = open_zone[a];
    if (z < 0 && kind[a] == FluidKind::fluid)  // fluid that crossed an outlet's plane joins its buffer
      for (std::size_t k = 0; k < open_zones_.size() && z < 0; ++k)
        if (open_zones_[k].outlet && open_zones_[k].depth(position[a]) > 0) {
          z = open_zone[a] = static_cast<Index>(k);
          kind[a] = FluidKind::wall;
          wall_velocity[a] = velocity[a];
          wall_acceleration[a] = Vec<D>::zero();
          wall_normal[a] = reference_normal[a] = open_zones_[k].normal;
          ++open_flows_[k].crossed;
          open_flows_[k].volume_crossed += volume[a];
        }
    if (z < 0) {
      order.push_back(a);
      continue;
    }
    const OpenZone<D>& zone = open_zones_[z];
    OpenZoneFlow& flow = open_flows_[z];
    const Real depth = zone.depth(position[a]);
    wall_depth[a] = depth;
    // The energy carried across the plane, (p + rho |u|^2 / 2 - rho g·x) u·n per unit area, from the
    // buffer's first layer (deeper ones see no fluid, and their rows give them p = 0): the boundary
    // work of the energy books.
    if (const Vec<D>& u = velocity[a]; depth >= 0 && depth < dx_)
      wall_work += dt * volume[a] / dx_ * dot(u, zone.normal) *
                   (pressure[a] + density_ * (0.5 * norm2(u) - dot(gravity_, position[a])));
    if (zone.outlet) {
      if (depth > zone.thickness)
        ++flow.removed;
      else
        order.push_back(a);
      continue;
    }
    flow.volume_prescribed += dt * volume[a] * dot(wall_velocity[a], zone.normal) / zone.thickness;
    if (depth < 0) {  // into the fluid: a copy takes its place a buffer's thickness behind
      entered.push_back(static_cast<Index>(order.size()));
      ++flow.crossed;
      flow.volume_crossed += volume[a];
    }
    order.push_back(a);
  }
  const Index kept = static_cast<Index>(order.size());
  for (const Index k : entered) order.push_back(order[k]);
  if (kept != n || !entered.empty()) reorder(order.data(), static_cast<Index>(order.size()));
  for (std::size_t e = 0; e < entered.size(); ++e) {
    const Index a = entered[e], copy = kept + static_cast<Index>(e);
    const OpenZone<D>& zone = open_zones_[open_zone[a]];
    kind[a] = FluidKind::fluid;
    open_zone[a] = -1;
    wall_normal[a] = reference_normal[a] = wall_acceleration[a] = Vec<D>::zero();
    wall_depth[a] = 0;
    position[copy] = reference_position[copy] = position[copy] - zone.thickness * zone.normal;
    wall_depth[copy] = zone.depth(position[copy]);
    id[copy] = next_id_++;
  }
  prescribe_inflow();
  count_kinds();
  if (static_cast<Index>(order.size()) != n) build_neighbours(false);  // no stale list between now and the next step
}

template <int D>
void ParticleSet<D>::restore(const SnapshotData& snapshot) {
  const SnapshotField &kinds = snapshot.field("kind"), &x = snapshot.field("position"), &u = snapshot.field("velocity"),
                      &p = snapshot.field("pressure");
  const std::vector<long long> row = snapshot.rows_by_id();
  const auto mismatch = [&](const std::string& what) {
    return std::runtime_error("restart: " + snapshot.path + " is not a snapshot of this case: " + what);
  };
  // With open boundaries, fluid and buffer particles change kind, come and go (sim/open_boundary.hpp).
  const bool open = !open_zones_.empty();
  const SnapshotField* zones = nullptr;
  if (open) {
    zones = &snapshot.field("open_zone");
    next_id_ = static_cast<Index>(snapshot.attributes.at("next_id"));
  }
  const auto exchanged = [&](Index a) { return open && (kind[a] == FluidKind::fluid || open_zone[a] >= 0); };
  std::vector<bool> matched(snapshot.size(), false);
  StateVector<Index> keep(allocator<Index>());
  for (Index a = 0; a < size(); ++a) {
    const long long r = static_cast<std::size_t>(id[a]) < row.size() ? row[id[a]] : -1;
    if (r < 0) {  // fluid the earlier run removed; every wall and structure particle must be there
      if (kind[a] != FluidKind::fluid && !exchanged(a))
        throw mismatch("it lacks the wall or structure particle id " + std::to_string(id[a]));
      continue;
    }
    if (kinds.data[r] != static_cast<double>(kind[a]) && !exchanged(a))
      throw mismatch("particle id " + std::to_string(id[a]) + " is of another kind there");
    matched[r] = true;
    keep.push_back(a);
  }
  // Particles the open boundaries created: copies of a fluid or buffer particle, given their state below.
  const Index kept = static_cast<Index>(keep.size());
  std::vector<std::size_t> created;
  // the particle copied, by value: keep grows below, and an iterator into it would dangle
  const auto found = std::find_if(keep.begin(), keep.end(), [&](Index a) { return exchanged(a); });
  const Index source = found == keep.end() ? -1 : *found;
  for (std::size_t r = 0; r < snapshot.size(); ++r)
    if (!matched[r]) {
      if (source < 0)
        throw mismatch("it has " + std::to_string(snapshot.size() - kept) + " particles whose ids this case lacks");
      created.push_back(r);
      keep.push_back(source);
    }
  if (static_cast<Index>(keep.size()) != size() || kept != size())
    reorder(keep.data(), static_cast<Index>(keep.size()));
  for (Index a = 0; a < size(); ++a) {
    const std::size_t r = a < kept ? static_cast<std::size_t>(row[id[a]]) : created[a - kept];
    position[a] = snapshot_vector<D>(x, r);
    velocity[a] = snapshot_vector<D>(u, r);
    pressure[a] = p.data[r];
    if (!exchanged(a)) continue;
    id[a] = static_cast<Index>(snapshot.field("id").data[r]);
    kind[a] = static_cast<FluidKind>(kinds.data[r]);
    open_zone[a] = static_cast<Index>(zones->data[r]);
    const bool buffer = open_zone[a] >= 0;
    wall_velocity[a] = buffer ? velocity[a] : Vec<D>::zero();
    wall_acceleration[a] = Vec<D>::zero();
    wall_normal[a] = reference_normal[a] = buffer ? open_zones_[open_zone[a]].normal : Vec<D>::zero();
    wall_depth[a] = buffer ? open_zones_[open_zone[a]].depth(position[a]) : 0;
    reference_position[a] = position[a];
  }
  count_kinds();
  if (const auto memory = snapshot.fields.find("memory_row"); memory != snapshot.fields.end()) {
    StateVector<Index> order(static_cast<std::size_t>(size()), -1, allocator<Index>());
    for (Index a = 0; a < size(); ++a) {
      const double r = memory->second.data[static_cast<std::size_t>(row[id[a]])];
      if (!(r >= 0 && r < size()) || order[static_cast<Index>(r)] >= 0)
        throw mismatch("its memory_row field is not a permutation");
      order[static_cast<Index>(r)] = a;
    }
    reorder(order.data(), size());
  }
  if (const auto searches = snapshot.attributes.find("neighbour_searches"); searches != snapshot.attributes.end())
    neighbour_searches_ = static_cast<long long>(searches->second);
  time = snapshot.time;
  const auto work = snapshot.attributes.find("wall_work");
  wall_work = work != snapshot.attributes.end() ? work->second : 0;
  if (open) prescribe_inflow();
}

template <int D>
void ParticleSet<D>::prescribe_walls(Real dt) {
  parallel_for(exec_, size(),
               PrescribeWalls<D>{.motion = motion.data(),
                                 .now = poses_at(motions_, time),
                                 .next = poses_at(motions_, time + dt),
                                 .reference_x = reference_position.data(),
                                 .reference_normal = reference_normal.data(),
                                 .dt = dt,
                                 .period = period_,
                                 .x = position.data(),
                                 .u = velocity.data(),
                                 .wall_velocity = wall_velocity.data(),
                                 .wall_acceleration = wall_acceleration.data(),
                                 .wall_normal = wall_normal.data()});
}

template <int D>
void ParticleSet<D>::gather_walls(StateVector<Vec<D>>& point, StateVector<Real>& radius) const {
  const Index n = size();
  if (wall_slot_.size() != static_cast<std::size_t>(n) + 1)
    wall_slot_ = StateVector<Index>(static_cast<std::size_t>(n) + 1, 0, allocator<Index>());
  parallel_for(exec_, n, MarkWalls{kind.data(), wall_slot_.data()});
  inclusive_scan(exec_, wall_slot_.data() + 1, n);
  resize_for_overwrite(point, wall_slot_[n]);  // the number of walls: one value back from the device
  resize_for_overwrite(radius, wall_slot_[n]);
  parallel_for(exec_, n,
               GatherWalls<D>{.kind = kind.data(),
                              .x = position.data(),
                              .volume = volume.data(),
                              .slot = wall_slot_.data(),
                              .point = point.data(),
                              .radius = radius.data()});
}

template <int D>
Vec<D> ParticleSet<D>::gather_structure_force(std::span<Vec<D>> force_density) const {
  parallel_for(exec_, size(),
               ScatterToStructure<D>{.structure_index = structure_index.data(),
                                     .value = boundary_force.data(),
                                     .unit = false,
                                     .out = force_density.data(),
                                     .added = viscous_force.data()});
  return summed(static_cast<Index>(structure_volume_.size()),
                ForceComponent<D>{structure_volume_.data(), force_density.data(), 0});
}

// F_body = sum over the body's particles of V_a f_a, f_a the pressure force density on particle a.
template <int D>
Vec<D> ParticleSet<D>::body_force(Index body_index) const {
  return owned_sum(boundary_force, body, body_index);
}

template <int D>
void ParticleSet<D>::record_viscous_force(const ViscousAcceleration<D>& viscous, FluidKind target) {
  parallel_for(
      exec_, size(),
      ViscousBoundaryForce<D>{.viscous = viscous,
                              .density = density_,
                              .target = target,
                              .force_density = viscous_force.data(),
                              .impedance = target == FluidKind::structure ? viscous_impedance.data() : nullptr});
}

template <int D>
void ParticleSet<D>::gather_structure_impedance(std::span<Real> impedance) const {
  parallel_for(exec_, size(),
               ScatterToStructure<D, Real>{structure_index.data(), viscous_impedance.data(), false, impedance.data()});
}

template <int D>
Vec<D> ParticleSet<D>::body_viscous_force(Index body_index) const {
  return owned_sum(viscous_force, body, body_index);
}

template <int D>
Vec<D> ParticleSet<D>::body_contact_force(Index body_index) const {
  return owned_sum(contact_force, contact_body, body_index);
}

// sum_a V_a f_a over the particles a whose owner is the body.
template <int D>
Vec<D> ParticleSet<D>::owned_sum(const StateVector<Vec<D>>& force_density, const StateVector<Index>& owner,
                                 Index body_index) const {
  return summed(size(), ForceComponent<D>{.volume = volume.data(),
                                          .force_density = force_density.data(),
                                          .d = 0,
                                          .body = owner.data(),
                                          .target = body_index});
}

template <int D>
Vec<D> ParticleSet<D>::summed(Index n, ForceComponent<D> component) const {
  Vec<D> total;
  for (int d = 0; d < D; ++d) {
    component.d = d;
    total[d] = ordered_sum(exec_, n, component, block_sums_);
  }
  return total;
}

// Power of the moving walls on the fluid: their pressure force's, sum_w -V_w f_w · u_w, and their
// viscous traction's.
template <int D>
Real ParticleSet<D>::moving_wall_power() const {
  return viscous_wall_power_ + ordered_sum(exec_, size(),
                                           MovingWallPressurePower<D>{motion.data(), volume.data(),
                                                                      boundary_force.data(), wall_velocity.data()},
                                           block_sums_);
}

template <int D>
void ParticleSet<D>::record_viscous_wall_power(const ViscousAcceleration<D>& viscous) {
  power_density_.resize(position.size());
  parallel_for(exec_, size(), ViscousWallPower<D>{viscous, density_, power_density_.data()});
  viscous_wall_power_ = ordered_sum(exec_, size(), ScalarAt{power_density_.data()}, block_sums_);
}

template <int D>
void ParticleSet<D>::move_structure(std::span<const Vec<D>> x, std::span<const Vec<D>> v, std::span<const Mat<D>> F) {
  parallel_for(exec_, size(),
               FollowStructure<D>{.structure_index = structure_index.data(),
                                  .x = x.data(),
                                  .v = v.data(),
                                  .F = F.data(),
                                  .reference_normal = reference_normal.data(),
                                  .position = position.data(),
                                  .velocity = velocity.data(),
                                  .wall_velocity = wall_velocity.data(),
                                  .wall_normal = wall_normal.data()});
}

template <int D>
void ParticleSet<D>::follow_structure_acceleration(std::span<const Vec<D>> a) {
  parallel_for(exec_, size(),
               FollowStructureAcceleration<D>{structure_index.data(), a.data(), wall_acceleration.data()});
}

template <int D>
InteractionReport<D> ParticleSet<D>::contact(FluidKind body) {
  const Index n = size();
  inside_.resize(n);
  body_distance_.resize(n);
  body_depth_.resize(n);
  parallel_for(exec_, n,
               BodyContact<D>{.v = view(),
                              .body = body,
                              .inside = inside_.data(),
                              .distance = body_distance_.data(),
                              .depth = body_depth_.data()});
  InteractionReport<D> report;
  report.fluid_inside = parallel_reduce(exec_, n, Index{0}, Flagged{inside_.data()}, IntegerSum{});
  const Real nearest = parallel_reduce(exec_, n, kOutOfReach, ScalarAt{body_distance_.data()}, MinOf{});
  report.min_distance = nearest < kOutOfReach ? nearest : std::numeric_limits<Real>::infinity();
  report.max_depth = parallel_reduce(exec_, n, Real{0}, ScalarAt{body_depth_.data()}, MaxOf{});
  if (report.fluid_inside > 0)
    report.inside_at = position[lowest_id_particle(exec_, n, Flagged{inside_.data()}, id.data())];
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
Real ParticleSet<D>::max_speed() const {
  return std::sqrt(parallel_reduce(exec_, size(), Real{0}, FluidSpeed2<D>{kind.data(), velocity.data()}, MaxOf{}));
}

template <int D>
Index ParticleSet<D>::first_non_finite() const {
  return first_particle(exec_, size(), NonFiniteState<D>{position.data(), velocity.data(), pressure.data()});
}

template <int D>
Index ParticleSet<D>::first_outside(const Vec<D>& lo, const Vec<D>& hi) const {
  return first_particle(exec_, size(), FluidOutsideBox<D>{kind.data(), position.data(), lo, hi});
}

template class ParticleSet<2>;
template class ParticleSet<3>;
template class ContactRecord<2>;
template class ContactRecord<3>;

}  // namespace isph
