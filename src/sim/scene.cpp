#include "sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/neighbour_search.hpp"
#include "io/case_loader.hpp"

namespace isph {

namespace {

std::array<double, 3> to_array(const Vec<2>& v) { return {v[0], v[1], 0.0}; }
std::array<double, 3> to_array(const Vec<3>& v) { return {v[0], v[1], v[2]}; }

template <int D>
Vec<D> to_vec(const std::array<double, 3>& a) {
  Vec<D> v;
  for (int d = 0; d < D; ++d) v[d] = a[d];
  return v;
}

// Bounding box of a shape in the first D components.
template <int D>
void shape_bounds(const Shape& s, Vec<D>& lo, Vec<D>& hi) {
  for (int d = 0; d < D; ++d) {
    const bool round = s.type == "circle" || s.type == "sphere";
    lo[d] = round ? s.center[d] - s.radius : s.min[d];
    hi[d] = round ? s.center[d] + s.radius : s.max[d];
  }
}

// Lattice points origin + (i + 1/2) dx inside the shape.
template <int D>
std::vector<Vec<D>> fill_lattice(const Shape& shape, const std::array<double, 3>& origin, Real dx) {
  Vec<D> lo, hi;
  shape_bounds<D>(shape, lo, hi);
  int first[D], count[D];
  for (int d = 0; d < D; ++d) {
    first[d] = static_cast<int>(std::floor((lo[d] - origin[d]) / dx)) - 1;
    count[d] = static_cast<int>(std::ceil((hi[d] - lo[d]) / dx)) + 3;
  }
  std::vector<Vec<D>> points;
  int idx[D] = {};
  while (true) {
    Vec<D> p;
    for (int d = 0; d < D; ++d) p[d] = origin[d] + (first[d] + idx[d] + 0.5) * dx;
    if (shape.contains(to_array(p), D)) points.push_back(p);
    int d = 0;
    while (d < D && ++idx[d] >= count[d]) {
      idx[d] = 0;
      ++d;
    }
    if (d == D) break;
  }
  return points;
}

// The shape grown by `margin` on every side (an edge load takes the particles whose lattice cell
// touches its region: centres within dx/2 of it).
Shape grown(Shape s, Real margin) {
  s.radius += margin;
  for (int d = 0; d < 3; ++d) {
    s.min[d] -= margin;
    s.max[d] += margin;
  }
  return s;
}

// First bending mode of a clamped-free beam (seed 001 Eqs. 51-52).
Real cantilever_mode_shape(Real kL, Real s_over_L) {
  const Real ks = kL * s_over_L;
  return (std::cos(kL) + std::cosh(kL)) * (std::cosh(ks) - std::cos(ks)) +
         (std::sin(kL) - std::sinh(kL)) * (std::sinh(ks) - std::sin(ks));
}

template <int D>
Vec<D> initial_velocity(const InitialVelocitySpec& iv, const Vec<D>& X) {
  if (iv.type == "uniform") return to_vec<D>(iv.value);
  if (iv.type == "cantilever_mode") {
    const Vec<D> axis = to_vec<D>(iv.axis), dir = to_vec<D>(iv.direction);
    const Real s = std::clamp(dot(X - to_vec<D>(iv.root), axis), 0.0, iv.length);
    const Real shape = cantilever_mode_shape(iv.kL, s / iv.length) / cantilever_mode_shape(iv.kL, 1.0);
    return (iv.tip_velocity * shape) * dir;
  }
  return Vec<D>::zero();
}

}  // namespace

ElasticMaterial elastic_material(const MaterialSpec& m, int dimension) {
  const Real E = m.youngs_modulus, nu = m.poisson_ratio;
  const Real mu = E / (2 * (1 + nu));
  Real lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  if (dimension == 2 && m.plane == "stress") lambda = E * nu / (1 - nu * nu);
  return {m.density, lambda, mu, E};
}

template <int D>
Scene<D> build_scene(const CaseSpec& spec) {
  std::vector<std::string> problems;
  const std::string file = spec.source_path.empty() ? spec.name : spec.source_path;
  const Real dx = spec.dx;
  Scene<D> scene;
  TlsphSetup<D> s;  // in creation order; sorted by cell at the end
  std::vector<Index> probe_candidates;

  for (const auto& m : spec.materials) s.materials.push_back(elastic_material(m, D));
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& body = spec.bodies[bi];
    const std::string key = "bodies[" + std::to_string(bi) + "]";
    const auto points = fill_lattice<D>(body.shape, body.lattice_origin, dx);
    if (points.empty()) {
      problems.push_back(file + ": " + key + ".shape: no particles at dx = " + std::to_string(dx) +
                         " (the shape is smaller than the particle spacing)");
      continue;
    }
    if (body.kind != ParticleKind::structure) {
      (body.kind == ParticleKind::fluid ? scene.fluid_particles : scene.wall_particles) +=
          static_cast<Index>(points.size());
      problems.push_back(file + ": " + key + ".kind: '" + (body.kind == ParticleKind::fluid ? "fluid" : "wall") +
                         "' bodies need the fluid stage, which is not available in this version");
      continue;
    }
    const auto mat = std::find_if(spec.materials.begin(), spec.materials.end(),
                                  [&](const MaterialSpec& m) { return m.name == body.material; });
    const int material = static_cast<int>(mat - spec.materials.begin());
    Vec<D> lo, hi;
    shape_bounds<D>(body.shape, lo, hi);
    for (int d = 0; d < D; ++d) scene.body_extent = std::max(scene.body_extent, hi[d] - lo[d]);
    std::vector<int> clamp_count(body.clamps.size(), 0);
    for (const auto& p : points) {
      unsigned char fixed = 0;
      for (std::size_t c = 0; c < body.clamps.size(); ++c)
        if (body.clamps[c].contains(to_array(p), D)) {
          fixed = 1;
          ++clamp_count[c];
        }
      s.X.push_back(p);
      s.v.push_back(fixed ? Vec<D>::zero() : initial_velocity<D>(body.initial_velocity, p));
      s.volume.push_back(D == 2 ? dx * dx : dx * dx * dx);
      s.material.push_back(material);
      s.body.push_back(static_cast<int>(bi));
      s.fixed.push_back(fixed);
    }
    for (std::size_t c = 0; c < body.clamps.size(); ++c)
      if (clamp_count[c] == 0)
        problems.push_back(file + ": " + key + ".clamps[" + std::to_string(c) + "]: the clamp region holds no particle of the body");
  }
  const Index n = static_cast<Index>(s.X.size());
  if (n == 0 && problems.empty()) problems.push_back(file + ": bodies: the case has no structure particles");

  // Loads: per-particle acceleration at full load.
  for (std::size_t li = 0; li < spec.loads.size(); ++li) {
    const LoadSpec& load = spec.loads[li];
    const std::string key = "loads[" + std::to_string(li) + "]";
    LoadField<D> field;
    field.ramp_time = load.ramp_time;
    field.acc.assign(n, Vec<D>::zero());
    const auto body = std::find_if(spec.bodies.begin(), spec.bodies.end(),
                                   [&](const BodySpec& b) { return b.name == load.body; });
    const int bi = static_cast<int>(body - spec.bodies.begin());
    std::vector<Index> targets;
    if (load.type == "body") {
      for (Index a = 0; a < n; ++a)
        if (s.body[a] == bi && !s.fixed[a]) field.acc[a] = to_vec<D>(load.acceleration);
    } else {
      if (load.type == "point") {
        Real best = std::numeric_limits<Real>::max();
        Index arg = -1;
        for (Index a = 0; a < n; ++a) {
          const Real d2 = norm2(s.X[a] - to_vec<D>(load.region.center));
          if (s.body[a] == bi && !s.fixed[a] && d2 < best) best = d2, arg = a;
        }
        if (arg >= 0) targets.push_back(arg);
      } else {
        const Shape region = grown(load.region, 0.5 * dx);
        for (Index a = 0; a < n; ++a)
          if (s.body[a] == bi && !s.fixed[a] && region.contains(to_array(s.X[a]), D)) targets.push_back(a);
      }
      if (targets.empty())
        problems.push_back(file + ": " + key + ".region: no free particle of body '" + load.body + "' is loaded");
      // A total force F shared by the loaded particles: a_i = F / (n m_i).
      for (Index a : targets) {
        const Real m = s.materials[s.material[a]].density * s.volume[a];
        field.acc[a] = (1.0 / (static_cast<Real>(targets.size()) * m)) * to_vec<D>(load.force);
      }
    }
    s.loads.push_back(std::move(field));
  }

  if (!problems.empty()) throw CaseError(problems);

  // Sort particles by cell for memory locality; keep the creation index as stable id.
  CellList<D> cells;
  const SmoothingKernel<D> kernel = SmoothingKernel<D>::make(kernel_type_from_name(spec.kernel.type),
                                                             spec.kernel.h_factor * dx);
  cells.build(s.X, kernel.support());
  const std::vector<Index>& order = cells.order();
  auto permute = [&](auto& v) {
    auto copy = v;
    for (Index k = 0; k < n; ++k) v[k] = copy[order[k]];
  };
  permute(s.X);
  permute(s.v);
  permute(s.volume);
  permute(s.material);
  permute(s.body);
  permute(s.fixed);
  for (auto& l : s.loads) permute(l.acc);
  scene.structure_id = order;
  scene.structure_body = s.body;

  // Probes: the structure particle nearest the point, which must lie within dx of the body.
  for (std::size_t pi = 0; pi < spec.probes.size(); ++pi) {
    const ProbeSpec& p = spec.probes[pi];
    const Vec<D> point = to_vec<D>(p.point);
    Real best = std::numeric_limits<Real>::max();
    Index arg = -1;
    for (Index a = 0; a < n; ++a) {
      const Real d2 = norm2(s.X[a] - point);
      if (d2 < best) best = d2, arg = a;
    }
    if (arg < 0 || std::sqrt(best) > dx)
      problems.push_back(file + ": probes[" + std::to_string(pi) + "].point: probe '" + p.name +
                         "' lies outside every structure (nearest particle " + std::to_string(std::sqrt(best)) +
                         " m away, more than dx)");
    else
      scene.probes.push_back({p.name, arg, point});
  }
  if (!problems.empty()) throw CaseError(problems);

  s.kernel = kernel;
  s.correction = spec.kernel.correction;
  s.integrator = structure_integrator_from_name(spec.structure.integrator);
  s.gravity = to_vec<D>(spec.gravity);
  s.damping = spec.structure.damping;
  s.hourglass = spec.structure.hourglass;
  scene.structure = std::move(s);
  return scene;
}

template Scene<2> build_scene<2>(const CaseSpec&);
template Scene<3> build_scene<3>(const CaseSpec&);

}  // namespace isph
