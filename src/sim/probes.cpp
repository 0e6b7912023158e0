#include "sim/probes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isph {

namespace {

const char* const kDisplacementComponents[3] = {"ux", "uy", "uz"};
const char* const kForceComponents[3] = {"fx", "fy", "fz"};

// V_b W(|x - x_b|), with b's kernel against the fluid's: the weight of particle b in the Shepard
// interpolations at x (interpolate_pressure, interpolate_velocity, water_level).
template <int D>
Real weight_at(const ParticleSet<D>& p, const Vec<D>& point, Index b) {
  return p.volume[b] *
         p.kernels().pair(p.fluid_level(), p.level[b]).value(std::sqrt(norm2(p.period().delta(point, p.position[b]))));
}

// A fixed point or line of the fluid: one column, `field`, of a scalar sampler.
template <int D, class Sampler>
class ScalarProbe final : public Probe<D> {
 public:
  ScalarProbe(std::string name, const char* field, Sampler sampler)
      : column_(std::move(name) + "." + field), sampler_(std::move(sampler)) {}
  void add_columns(std::vector<std::string>& columns) const override { columns.push_back(column_); }
  void sample(std::vector<double>& row) override { row.push_back(sampler_()); }

 private:
  std::string column_;
  Sampler sampler_;
};

template <int D, class Sampler>
std::unique_ptr<Probe<D>> scalar_probe(const std::string& name, const char* field, Sampler sampler) {
  return std::make_unique<ScalarProbe<D, Sampler>>(name, field, std::move(sampler));
}

// The fluid's velocity at a point (Shepard): ux, uy (uz).
template <int D>
class VelocityProbe final : public Probe<D> {
 public:
  VelocityProbe(const ParticleSet<D>& particles, const FluidProbe<D>& probe) : particles_(particles), probe_(probe) {}
  void add_columns(std::vector<std::string>& columns) const override {
    for (int d = 0; d < D; ++d) columns.push_back(probe_.name + "." + kDisplacementComponents[d]);
  }
  void sample(std::vector<double>& row) override {
    const Vec<D> u = interpolate_velocity(particles_, probe_.point);
    for (int d = 0; d < D; ++d) row.push_back(u[d]);
  }

 private:
  const ParticleSet<D>& particles_;
  FluidProbe<D> probe_;
};

// The structure's displacement at the probe point by its nearest particle's own deformation gradient,
// u_a + (F_a - I)(point - X_a).
template <int D>
class DisplacementProbeOf final : public Probe<D> {
 public:
  DisplacementProbeOf(const TlsphSolver<D>& solver, const DisplacementProbe<D>& probe)
      : solver_(solver), probe_(probe) {}
  void add_columns(std::vector<std::string>& columns) const override {
    for (int d = 0; d < D; ++d) columns.push_back(probe_.name + "." + kDisplacementComponents[d]);
  }
  void sample(std::vector<double>& row) override {
    const Index a = probe_.particle;
    const Vec<D> X = solver_.reference()[a];
    const Vec<D> u =
        (solver_.position()[a] - X) + (solver_.deformation_gradient()[a] - Mat<D>::identity()) * (probe_.point - X);
    for (int d = 0; d < D; ++d) row.push_back(u[d]);
  }

 private:
  const TlsphSolver<D>& solver_;
  DisplacementProbe<D> probe_;
};

// The force probes: each row holds the time mean of the body's force over the fluid steps since the
// previous row, sum(F dt) / sum(dt) (the instantaneous force swings from step to step). The sums go
// into the snapshots, so that a restart writes the rows the uninterrupted run would. One object serves
// every force probe of a run: they share the window.
template <int D>
class ForceProbes final : public Probe<D> {
 public:
  ForceProbes(const ParticleSet<D>& particles, std::vector<ForceProbe> probes)
      : particles_(particles), probes_(std::move(probes)), impulse_(probes_.size()) {}
  void add_columns(std::vector<std::string>& columns) const override {
    for (const auto& p : probes_)
      for (int d = 0; d < D; ++d) columns.push_back(p.name + "." + kForceComponents[d]);
  }
  void after_step(Real dt) override {
    for (std::size_t i = 0; i < probes_.size(); ++i) {
      const ForceProbe& p = probes_[i];
      impulse_[i] += dt * (particles_.body_force(p.body) +
                           (p.all_terms ? particles_.body_viscous_force(p.body) + particles_.body_contact_force(p.body)
                                        : Vec<D>::zero()));
    }
    window_ += dt;
  }
  // The means since the previous row (NaN in the first row, before any step), and a new window.
  void sample(std::vector<double>& row) override {
    for (auto& impulse : impulse_) {
      for (int d = 0; d < D; ++d) row.push_back(window_ > 0 ? impulse[d] / window_ : std::nan(""));
      impulse = Vec<D>::zero();
    }
    window_ = 0;
  }
  void save(SnapshotAttributes& attributes) const override {
    attributes.emplace_back("force_probe_window", window_);
    for (std::size_t i = 0; i < probes_.size(); ++i)
      for (int d = 0; d < D; ++d) attributes.emplace_back(key(i, d), impulse_[i][d]);
  }
  // A snapshot without the sums (written before force probes were asked for) starts a new window.
  void restore(const SnapshotData& state) override {
    const auto& a = state.attributes;
    const auto window = a.find("force_probe_window");
    if (window == a.end()) return;
    window_ = window->second;
    for (std::size_t i = 0; i < probes_.size(); ++i)
      for (int d = 0; d < D; ++d)
        if (const auto v = a.find(key(i, d)); v != a.end()) impulse_[i][d] = v->second;
  }

 private:
  std::string key(std::size_t i, int d) const {
    return "force_probe_impulse." + probes_[i].name + "." + kForceComponents[d];
  }
  const ParticleSet<D>& particles_;
  std::vector<ForceProbe> probes_;
  std::vector<Vec<D>> impulse_;  // sum of F dt over the window
  Real window_ = 0;              // sum of dt
};

// A probe of the case's fluid probes (io/case.hpp ProbeType).
template <int D>
std::unique_ptr<Probe<D>> fluid_probe(const ParticleSet<D>& p, const FluidProbe<D>& probe) {
  const Vec<D> point = probe.point;
  switch (probe.type) {
    case ProbeType::pressure:
      return scalar_probe<D>(probe.name, "p", [&p, point] { return interpolate_pressure(p, point); });
    case ProbeType::front:
      return scalar_probe<D>(probe.name, "x", [&p, point] { return surge_front(p, point[D - 1]); });
    case ProbeType::max_speed:
      return scalar_probe<D>(probe.name, "u", [&p] { return p.max_speed(); });
    case ProbeType::water_level:
      return scalar_probe<D>(probe.name, "h", [&p, point] { return water_level(p, point); });
    case ProbeType::velocity:
      return std::make_unique<VelocityProbe<D>>(p, probe);
    default:
      throw std::logic_error("probe " + probe.name + " is not a fluid probe");
  }
}

}  // namespace

template <int D>
Real fluid_kinetic_energy(const ParticleSet<D>& p) {
  Real e = 0;
  for (Index a = 0; a < p.size(); ++a)
    if (p.kind[a] == FluidKind::fluid) e += 0.5 * p.density() * p.volume[a] * norm2(p.velocity[a]);
  return e;
}

template <int D>
Real fluid_potential_energy(const ParticleSet<D>& p) {
  Real e = 0;
  for (Index a = 0; a < p.size(); ++a)
    if (p.kind[a] == FluidKind::fluid) e -= p.density() * p.volume[a] * dot(p.gravity(), p.position[a]);
  return e;
}

template <int D>
Real interpolate_pressure(const ParticleSet<D>& p, const Vec<D>& point) {
  Real num = 0, den = 0;
  for (Index b = 0; b < p.size(); ++b) {
    const Real w = weight_at(p, point, b);
    num += w * p.pressure[b];
    den += w;
  }
  return den > 0 ? num / den : 0;
}

template <int D>
Real structure_pressure(const ParticleSet<D>& p, Index structure) {
  for (Index a = 0; a < p.size(); ++a)
    if (p.structure_index[a] == structure) return p.pressure[a];
  return 0;
}

template <int D>
Vec<D> interpolate_velocity(const ParticleSet<D>& p, const Vec<D>& point) {
  Vec<D> num = Vec<D>::zero();
  Real den = 0;
  for (Index b = 0; b < p.size(); ++b) {
    if (p.kind[b] != FluidKind::fluid) continue;
    const Real w = weight_at(p, point, b);
    num += w * p.velocity[b];
    den += w;
  }
  return den > 0 ? (1.0 / den) * num : Vec<D>::zero();
}

template <int D>
Real surge_front(const ParticleSet<D>& p, Real height) {
  Real best = -std::numeric_limits<Real>::infinity();
  for (Index a = 0; a < p.size(); ++a)
    if (p.kind[a] == FluidKind::fluid && p.position[a][D - 1] < height) best = std::max(best, p.position[a][0]);
  return best;
}

template <int D>
Real water_level(const ParticleSet<D>& p, const Vec<D>& point) {
  const Real base = point[D - 1], reach = p.fluid_kernel().support();
  std::vector<Index> column;  // fluid particles whose kernel reaches the line
  Real top = base;
  for (Index b = 0; b < p.size(); ++b) {
    if (p.kind[b] != FluidKind::fluid) continue;
    Vec<D> across = p.period().delta(point, p.position[b]);
    across[D - 1] = 0;
    if (norm2(across) >= reach * reach) continue;
    column.push_back(b);
    top = std::max(top, p.position[b][D - 1] + reach);
  }
  // sum_b V_b W(|x - x_b|) - 1/2 at height z on the line: negative above the water, where it is -1/2
  const auto excess = [&](Real z) {
    Vec<D> x = point;
    x[D - 1] = z;
    Real filled = 0;
    for (const Index b : column) filled += weight_at(p, x, b);
    return filled - 0.5;
  };
  // Down from above the highest water in quarter smoothing lengths, then bisection in the first
  // interval whose lower end is filled (excess(hi) < 0 holds throughout).
  const Real step = p.fluid_kernel().h / 4;
  for (Real hi = top; hi > base; hi -= step) {
    Real lo = std::max(hi - step, base);
    if (excess(lo) < 0) continue;
    for (int i = 0; i < 40 && hi - lo > 1e-6 * step; ++i) {
      const Real mid = (lo + hi) / 2;
      (excess(mid) >= 0 ? lo : hi) = mid;
    }
    return lo;
  }
  return base;
}

template <int D>
std::vector<std::string> ProbeSet<D>::columns() const {
  std::vector<std::string> columns;
  for (const auto& p : probes_) p->add_columns(columns);
  return columns;
}

template <int D>
std::vector<double> ProbeSet<D>::sample(double t) {
  std::vector<double> row{t};
  for (auto& p : probes_) p->sample(row);
  return row;
}

template <int D>
void ProbeSet<D>::after_step(Real dt) {
  for (auto& p : probes_) p->after_step(dt);
}

template <int D>
void ProbeSet<D>::save(SnapshotAttributes& attributes) const {
  for (const auto& p : probes_) p->save(attributes);
}

template <int D>
void ProbeSet<D>::restore(const SnapshotData& state) {
  for (auto& p : probes_) p->restore(state);
}

template <int D>
ProbeSet<D> fluid_run_probes(const Scene<D>& scene, const ParticleSet<D>& particles, const TlsphSolver<D>* structure) {
  ProbeSet<D> set;
  for (const auto& p : scene.fluid_probes) set.add(fluid_probe(particles, p));
  if (structure) {
    for (const auto& p : scene.probes) set.add(std::make_unique<DisplacementProbeOf<D>>(*structure, p));
    for (const auto& p : scene.pressure_probes) {
      const Index particle = p.particle;
      set.add(scalar_probe<D>(p.name, "p", [&particles, particle] { return structure_pressure(particles, particle); }));
    }
  }
  if (!scene.force_probes.empty()) set.add(std::make_unique<ForceProbes<D>>(particles, scene.force_probes));
  return set;
}

template <int D>
ProbeSet<D> structure_run_probes(const Scene<D>& scene, const TlsphSolver<D>& structure) {
  ProbeSet<D> set;
  for (const auto& p : scene.probes) set.add(std::make_unique<DisplacementProbeOf<D>>(structure, p));
  return set;
}

#define ISPH_PROBES(D)                                                                                  \
  template Real fluid_kinetic_energy(const ParticleSet<D>&);                                            \
  template Real fluid_potential_energy(const ParticleSet<D>&);                                          \
  template Real interpolate_pressure(const ParticleSet<D>&, const Vec<D>&);                             \
  template Vec<D> interpolate_velocity(const ParticleSet<D>&, const Vec<D>&);                           \
  template Real structure_pressure(const ParticleSet<D>&, Index);                                       \
  template Real surge_front(const ParticleSet<D>&, Real);                                               \
  template Real water_level(const ParticleSet<D>&, const Vec<D>&);                                      \
  template class ProbeSet<D>;                                                                           \
  template ProbeSet<D> fluid_run_probes(const Scene<D>&, const ParticleSet<D>&, const TlsphSolver<D>*); \
  template ProbeSet<D> structure_run_probes(const Scene<D>&, const TlsphSolver<D>&);
ISPH_PROBES(2)
ISPH_PROBES(3)
#undef ISPH_PROBES

}  // namespace isph
