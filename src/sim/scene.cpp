#include "sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/neighbour_search.hpp"
#include "geometry/lattice.hpp"
#include "io/case_loader.hpp"
#include "sim/scene_parts.hpp"

namespace isph {

namespace {

// First bending mode of a clamped-free beam (seed 001 Eqs. 51-52).
Real cantilever_mode_shape(Real kL, Real s_over_L) {
  const Real ks = kL * s_over_L;
  return (std::cos(kL) + std::cosh(kL)) * (std::cosh(ks) - std::cos(ks)) +
         (std::sin(kL) - std::sinh(kL)) * (std::sinh(ks) - std::sin(ks));
}

// A point to six digits, for messages (a mesh's corners carry the round-off of scale and translate).
std::string point_text(const std::array<double, 3>& p, int dimension) {
  std::string text = "(";
  for (int d = 0; d < dimension; ++d) {
    char number[32];
    std::snprintf(number, sizeof number, "%g", p[d]);
    text += (d ? ", " : "") + std::string(number);
  }
  return text + ")";
}

// Advice for a mesh `ratio` times the tank's size: STL has no units, and a file in millimetres or
// centimetres needs scale = 0.001 or 0.01.
std::string scale_advice(double ratio) {
  if (ratio >= 300) return "is the file in millimetres? STL has no units: scale = 0.001 makes them metres";
  if (ratio >= 30) return "is the file in centimetres? STL has no units: scale = 0.01 makes them metres";
  return "check the file's units and the shape's scale";
}

// A body from a mesh must lie in the tank: the bounding box of the wall bodies' shapes, open against
// gravity as the tank is, and unbounded on periodic axes. A mesh ten times the tank's size or more is
// in other units (STL has none): the message says which scale would mend it. Checked before the
// bodies are filled, as a mesh in millimetres would take hours to fill.
template <int D>
void check_meshes_in_tank(const CaseSpec& spec, const std::string& file, std::vector<std::string>& problems) {
  std::array<double, 3> lo{}, hi{};
  bool walls = false;
  for (const BodySpec& b : spec.bodies) {
    if (b.kind != ParticleKind::wall) continue;
    const auto [low, high] = b.shape.bounding_box(D);
    for (int d = 0; d < D; ++d) {
      lo[d] = walls ? std::min(lo[d], low[d]) : low[d];
      hi[d] = walls ? std::max(hi[d], high[d]) : high[d];
    }
    walls = true;
  }
  if (!walls) return;
  const Periodicity<D> period = periodicity<D>(spec.periodic);
  const Vec<D> g = to_vec<D>(spec.gravity);
  Real tank = 0;
  for (int d = 0; d < D; ++d) tank = std::max(tank, hi[d] - lo[d]);
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& b = spec.bodies[bi];
    if (b.shape.type != ShapeType::stl || b.kind == ParticleKind::wall) continue;
    const auto [low, high] = b.shape.bounding_box(D);
    if (!outside_open_box(to_vec<D>(low), to_vec<D>(lo), to_vec<D>(hi), g, period) &&
        !outside_open_box(to_vec<D>(high), to_vec<D>(lo), to_vec<D>(hi), g, period))
      continue;
    Real size = 0;
    for (int d = 0; d < D; ++d) size = std::max(size, high[d] - low[d]);
    std::string text = file + ": bodies[" + std::to_string(bi) + "].shape: the mesh of body '" + b.name + "' spans " +
                       point_text(low, D) + " to " + point_text(high, D) +
                       " m, partly outside the tank (the wall bodies' bounding box, " + point_text(lo, D) + " to " +
                       point_text(hi, D) + " m, open against gravity)";
    if (size >= 10 * tank)
      text += "; it is " + std::to_string(std::lround(size / tank)) +
              " times the tank's size: " + scale_advice(size / tank);
    problems.push_back(text);
  }
}

// Whether water lies just outside both faces of a box structure across axis d at the start: the points
// dx/2 beyond the middle of each face are inside a fluid body and none of its holes.
bool water_on_both_sides(const CaseSpec& spec, const Shape& box, int d, int dimension) {
  const auto in_water = [&](std::array<double, 3> p) {
    return std::any_of(spec.bodies.begin(), spec.bodies.end(), [&](const BodySpec& b) {
      return b.kind == ParticleKind::fluid && b.shape.contains(p, dimension) &&
             std::none_of(b.holes.begin(), b.holes.end(), [&](const Shape& h) { return h.contains(p, dimension); });
    });
  };
  std::array<double, 3> middle{};
  for (int k = 0; k < dimension; ++k) middle[k] = 0.5 * (box.min[k] + box.max[k]);
  std::array<double, 3> below = middle, above = middle;
  below[d] = box.min[d] - 0.5 * spec.dx;
  above[d] = box.max[d] + 0.5 * spec.dx;
  return in_water(below) && in_water(above);
}

// Two ways a structure of thickness T (a box's thinnest side) is too thin for the water's kernel support 2h:
//  - T + dx/2 < 2h: the support of the water's first layer, dx/2 from a face, reaches through the structure to
//    its far side, a kernel deficit that reads as a free surface. In 3D this shifted water into a gate 5 mm
//    thick at 2h = 12 mm and ran it out under its foot; at 2h = 6 mm (the shipped case) it did not
//    (docs/VALIDATION.md section 31). In 2D no harm was measured.
//  - with water on both sides, T/2 + dx/2 < 2h: the structure's middle particles reach the water on both sides,
//    and their PPE rows and pressure force mix the two sides' pressures. Turek & Hron's bar, 2 cm at 2h = 2.4 cm,
//    was crushed and the run diverged at 1.4 s (docs/VALIDATION.md section 36). The shipped gate has water on
//    one side only at the start, and works.
template <int D>
void warn_thin_structures(const CaseSpec& spec, const Resolutions& resolutions, const std::string& file,
                          std::vector<std::string>& warnings) {
  if (!spec.stages.fluid || !spec.stages.structure) return;
  const Real support = resolutions.kernels<D>(spec.kernel).kernel[resolutions.fluid_level()].support();
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& b = spec.bodies[bi];
    if (b.kind != ParticleKind::structure || b.shape.type != (D == 3 ? ShapeType::box : ShapeType::rectangle)) continue;
    int axis = 0;
    for (int d = 1; d < D; ++d)
      if (b.shape.max[d] - b.shape.min[d] < b.shape.max[axis] - b.shape.min[axis]) axis = d;
    const Real thickness = b.shape.max[axis] - b.shape.min[axis];
    char buf[640];
    if (D == 3 && thickness + 0.5 * spec.dx < support) {
      std::snprintf(buf, sizeof buf,
                    "%s: bodies[%zu]: structure '%s' is %g m thick: the kernel support (2h = %g m) of the water "
                    "beside it reaches through it to its far side; in 3D this drew water into a gate and under it "
                    "(docs/VALIDATION.md section 31). A water spacing dx <= %g m keeps the support inside it",
                    file.c_str(), bi, b.name.c_str(), thickness, support, thickness / (support / spec.dx - 0.5));
    } else if (0.5 * (thickness + spec.dx) < support && water_on_both_sides(spec, b.shape, axis, D)) {
      std::snprintf(buf, sizeof buf,
                    "%s: bodies[%zu]: structure '%s' is %g m thick with water on both sides: the kernel support "
                    "(2h = %g m) of its middle particles reaches the water on both, and their pressure mixes the "
                    "two sides'; Turek & Hron's bar was crushed so (docs/VALIDATION.md section 36). A water "
                    "spacing dx <= %g m keeps each side's water to its own particles",
                    file.c_str(), bi, b.name.c_str(), thickness, support, thickness / (2 * support / spec.dx - 1));
    } else {
      continue;
    }
    warnings.push_back(buf);
  }
}

// The case's spacings: at most kMaxLevels of them, and no structure coarser than the water.
void check_spacings(const CaseSpec& spec, const Resolutions& resolutions, const std::string& file,
                    std::vector<std::string>& problems) {
  if (resolutions.levels() > kMaxLevels)
    throw CaseError({file + ": bodies: " + std::to_string(resolutions.levels()) +
                     " particle spacings (the case's dx and the structures' own); at most " +
                     std::to_string(kMaxLevels) + " are supported"});
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi)
    if (spec.bodies[bi].spacing(spec.dx) > spec.dx)
      problems.push_back(file + ": bodies[" + std::to_string(bi) + "].dx: " + std::to_string(spec.bodies[bi].dx) +
                         " m is coarser than the case's dx = " + std::to_string(spec.dx) +
                         " m; a structure may be finer than the water, not coarser");
}

// Appends a structure body's particles to the TLSPH set-up (clamped where a clamp holds them, moving
// with the body's motion there) and, in a coupled case, to the fluid's as boundary particles.
template <int D>
void add_structure_body(const CaseSpec& spec, std::size_t bi, const std::vector<Vec<D>>& points, Real volume, int level,
                        const std::string& file, Scene<D>& scene, TlsphSetup<D>& s, FluidSetup<D>& fluid,
                        std::vector<std::string>& problems) {
  const BodySpec& body = spec.bodies[bi];
  const auto mat = std::find_if(spec.materials.begin(), spec.materials.end(),
                                [&](const MaterialSpec& m) { return m.name == body.material; });
  const int material = static_cast<int>(mat - spec.materials.begin());
  Vec<D> lo, hi;
  shape_bounds<D>(body.shape, lo, hi);
  for (int d = 0; d < D; ++d) scene.body_extent = std::max(scene.body_extent, hi[d] - lo[d]);
  std::vector<int> clamp_count(body.clamps.size(), 0);
  if (body.motion.type != MotionType::none) s.motions.emplace_back(body.motion);
  const Index clamp_motion = body.motion.type != MotionType::none ? static_cast<Index>(s.motions.size()) - 1 : -1;
  for (const auto& p : points) {
    unsigned char fixed = 0;
    for (std::size_t c = 0; c < body.clamps.size(); ++c)
      if (body.clamps[c].contains(to_array(p), D)) {
        fixed = 1;
        ++clamp_count[c];
      }
    s.X.push_back(p);
    const Vec<D> clamp_velocity = clamp_motion >= 0 ? s.motions[clamp_motion].velocity(p, 0) : Vec<D>::zero();
    s.v.push_back(fixed ? clamp_velocity : initial_velocity<D>(body.initial_velocity, p));
    s.volume.push_back(volume);
    s.level.push_back(static_cast<unsigned char>(level));
    s.material.push_back(material);
    s.body.push_back(static_cast<int>(bi));
    s.fixed.push_back(fixed);
    s.motion.push_back(fixed ? clamp_motion : -1);
    if (spec.stages.fluid)
      add_structure_particle<D>(p, s.v.back(), static_cast<Index>(s.X.size()) - 1, volume, level, bi, fluid);
  }
  for (std::size_t c = 0; c < body.clamps.size(); ++c)
    if (clamp_count[c] == 0)
      problems.push_back(file + ": bodies[" + std::to_string(bi) + "].clamps[" + std::to_string(c) +
                         "]: the clamp region holds no particle of the body");
}

// Every body filled on its lattice: structures into the TLSPH set-up, fluid and walls into the fluid's.
template <int D>
void add_bodies(const CaseSpec& spec, const Resolutions& resolutions, const std::string& file, Scene<D>& scene,
                TlsphSetup<D>& s, FluidSetup<D>& fluid, std::vector<std::string>& problems) {
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& body = spec.bodies[bi];
    const Real spacing = body.spacing(spec.dx);
    const int level = resolutions.level(body);
    auto points = body_particles<D>(body, spacing);
    std::erase_if(points, [&](const Vec<D>& x) {
      return std::any_of(body.holes.begin(), body.holes.end(),
                         [&](const Shape& hole) { return hole.contains(to_array(x), D); });
    });
    if (points.empty()) {
      problems.push_back(file + ": bodies[" + std::to_string(bi) + "].shape: no particles at a spacing of " +
                         std::to_string(spacing) + " m (the shape is smaller than the particle spacing)");
      continue;
    }
    if (body.kind == ParticleKind::structure)
      add_structure_body<D>(spec, bi, points, cell_volume<D>(body.shape, spacing), level, file, scene, s, fluid,
                            problems);
    else
      add_fluid_body<D>(spec, bi, points, level, fluid);
  }
}

// Loads: each structure particle's acceleration at full load.
template <int D>
void add_loads(const CaseSpec& spec, const std::string& file, TlsphSetup<D>& s, std::vector<std::string>& problems) {
  const Index n = static_cast<Index>(s.X.size());
  for (std::size_t li = 0; li < spec.loads.size(); ++li) {
    const LoadSpec& load = spec.loads[li];
    const std::string key = "loads[" + std::to_string(li) + "]";
    LoadField<D> field;
    field.ramp_time = load.ramp_time;
    field.acc.assign(n, Vec<D>::zero());
    const auto body =
        std::find_if(spec.bodies.begin(), spec.bodies.end(), [&](const BodySpec& b) { return b.name == load.body; });
    const int bi = static_cast<int>(body - spec.bodies.begin());
    std::vector<Index> targets;
    if (load.type == LoadType::body) {
      for (Index a = 0; a < n; ++a)
        if (s.body[a] == bi && !s.fixed[a]) field.acc[a] = to_vec<D>(load.acceleration);
    } else {
      if (load.type == LoadType::point) {
        Real best = std::numeric_limits<Real>::max();
        Index arg = -1;
        for (Index a = 0; a < n; ++a) {
          const Real d2 = norm2(s.X[a] - to_vec<D>(load.point));
          if (s.body[a] == bi && !s.fixed[a] && d2 < best) best = d2, arg = a;
        }
        if (arg >= 0) targets.push_back(arg);
      } else {
        const Shape region = grown(load.region, 0.5 * body->spacing(spec.dx));
        for (Index a = 0; a < n; ++a)
          if (s.body[a] == bi && !s.fixed[a] && region.contains(to_array(s.X[a]), D)) targets.push_back(a);
      }
      if (targets.empty())
        problems.push_back(file + ": " + key + ".region: no free particle of body '" + load.body + "' is loaded");
      // A total force F shared by the loaded particles, f_i = F / n; or a traction t on each particle's
      // cell face, f_i = t s^(D-1) (s the body's spacing). Then a_i = f_i / m_i.
      const Vec<D> force = load.type == LoadType::traction
                               ? std::pow(body->spacing(spec.dx), D - 1) * to_vec<D>(load.traction)
                               : (1.0 / static_cast<Real>(targets.size())) * to_vec<D>(load.force);
      for (Index a : targets) field.acc[a] = (1.0 / (s.materials[s.material[a]].density * s.volume[a])) * force;
    }
    s.loads.push_back(std::move(field));
  }
}

// Sorts the structure particles by cell for memory locality, keeping the creation index as stable id,
// and points the fluid's structure rows at the sorted particles.
template <int D>
void sort_structure(Scene<D>& scene, TlsphSetup<D>& s, FluidSetup<D>& fluid) {
  const Index n = static_cast<Index>(s.X.size());
  CellList<D> cells;
  cells.build(s.X, s.kernels.largest_support());
  const auto& order = cells.order();
  auto permute = [&](auto& v) {
    auto copy = v;
    for (Index k = 0; k < n; ++k) v[k] = copy[order[k]];
  };
  permute(s.X);
  permute(s.v);
  permute(s.volume);
  permute(s.level);
  permute(s.material);
  permute(s.body);
  permute(s.fixed);
  permute(s.motion);
  for (auto& l : s.loads) permute(l.acc);
  scene.structure_id.assign(order.begin(), order.end());
  scene.structure_body = s.body;
  std::vector<Index> sorted_slot(n);  // creation index -> index after sorting
  for (Index k = 0; k < n; ++k) sorted_slot[order[k]] = k;
  for (Index& i : fluid.structure_index)
    if (i >= 0) i = sorted_slot[i];
}

// Structure probes: the structure particle nearest the point, which must lie within its spacing of the
// body.
template <int D>
void place_structure_probes(const CaseSpec& spec, const Resolutions& resolutions, const std::string& file,
                            const TlsphSetup<D>& s, Scene<D>& scene, std::vector<std::string>& problems) {
  for (std::size_t pi = 0; pi < spec.probes.size(); ++pi) {
    const ProbeSpec& p = spec.probes[pi];
    if (p.type != ProbeType::displacement && p.type != ProbeType::structure_pressure) continue;
    const Vec<D> point = to_vec<D>(p.point);
    Real best = std::numeric_limits<Real>::max();
    Index arg = -1;
    for (Index a = 0; a < static_cast<Index>(s.X.size()); ++a) {
      const Real d2 = norm2(s.X[a] - point);
      if (d2 < best) best = d2, arg = a;
    }
    if (arg < 0 || std::sqrt(best) > resolutions.spacing[s.level[arg]])
      problems.push_back(file + ": probes[" + std::to_string(pi) + "].point: probe '" + p.name +
                         "' lies outside every structure (nearest particle " + std::to_string(std::sqrt(best)) +
                         " m away, more than its spacing)");
    else if (p.type == ProbeType::displacement)
      scene.probes.push_back({p.name, arg, point});
    else
      scene.pressure_probes.push_back({p.name, arg});
  }
}

}  // namespace

template <int D>
Vec<D> initial_velocity(const InitialVelocitySpec& iv, const Vec<D>& X) {
  if (iv.type == InitialVelocityType::uniform) return to_vec<D>(iv.value);
  if (iv.type == InitialVelocityType::cantilever_mode) {
    const Vec<D> axis = to_vec<D>(iv.axis), dir = to_vec<D>(iv.direction);
    const Real s = std::clamp(dot(X - to_vec<D>(iv.root), axis), 0.0, iv.length);
    const Real shape = cantilever_mode_shape(iv.kL, s / iv.length) / cantilever_mode_shape(iv.kL, 1.0);
    return (iv.tip_velocity * shape) * dir;
  }
  return Vec<D>::zero();
}

template Vec<2> initial_velocity<2>(const InitialVelocitySpec&, const Vec<2>&);
template Vec<3> initial_velocity<3>(const InitialVelocitySpec&, const Vec<3>&);

// The small-strain moduli of E and nu, and each law's constants from them (structure/elastic_law.hpp).
ElasticMaterial elastic_material(const MaterialSpec& m, int dimension) {
  const Real E = m.youngs_modulus, nu = m.poisson_ratio;
  const Real mu = E / (2 * (1 + nu));
  const Real lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  ElasticMaterial e{m.density, lambda, mu, E};
  if (m.model == MaterialModel::neo_hookean) e.law = ElasticLaw::neo_hookean;
  if (m.model == MaterialModel::mooney_rivlin) {
    e.law = ElasticLaw::mooney_rivlin;
    e.c01 = m.c01_fraction * mu / 2;
    e.c10 = mu / 2 - e.c01;
    e.kappa = lambda + 2 * mu / 3;
  }
  if (dimension == 2 && m.plane == PlaneCondition::stress) e.lambda = E * nu / (1 - nu * nu);  // SVK only
  return e;
}

template <int D>
Scene<D> build_scene(const CaseSpec& spec) {
  std::vector<std::string> problems;
  const std::string file = spec.source_path.empty() ? spec.name : spec.source_path;
  Scene<D> scene;
  TlsphSetup<D> s;  // in creation order; sorted by cell at the end
  FluidSetup<D> fluid;
  const Resolutions resolutions(spec);
  check_spacings(spec, resolutions, file, problems);
  check_meshes_in_tank<D>(spec, file, problems);
  if (!problems.empty()) throw CaseError(problems);
  warn_thin_structures<D>(spec, resolutions, file, scene.warnings);
  for (const auto& m : spec.materials) s.materials.push_back(elastic_material(m, D));
  add_bodies(spec, resolutions, file, scene, s, fluid, problems);
  const Index n = static_cast<Index>(s.X.size());
  scene.has_structure = spec.stages.structure && n > 0;
  scene.has_fluid = spec.stages.fluid;
  if (spec.stages.structure && n == 0 && problems.empty())
    problems.push_back(file + ": bodies: the case has no structure particles (set stages.structure = false)");
  if (s.motions.size() > static_cast<std::size_t>(kMaxMotions))
    problems.push_back(file + ": bodies: " + std::to_string(s.motions.size()) +
                       " structures with moving clamps; at most " + std::to_string(kMaxMotions) + " are supported");
  if (scene.has_fluid) finish_fluid<D>(spec, scene, fluid, s, problems);
  add_loads(spec, file, s, problems);
  if (!problems.empty()) throw CaseError(problems);

  s.kernels = resolutions.kernels<D>(spec.kernel);
  sort_structure(scene, s, fluid);
  place_structure_probes(spec, resolutions, file, s, scene, problems);
  if (!problems.empty()) throw CaseError(problems);

  s.gradient = spec.kernel.correction ? spec.structure.gradient : StructureGradient::uncorrected;
  s.quadrature = spec.structure.quadrature;
  s.integrator = spec.structure.integrator;
  s.gravity = to_vec<D>(spec.gravity);
  s.damping = spec.structure.damping;
  s.hourglass = spec.structure.hourglass;
  scene.structure = std::move(s);
  scene.fluid = std::move(fluid);
  return scene;
}

template Scene<2> build_scene<2>(const CaseSpec&);
template Scene<3> build_scene<3>(const CaseSpec&);

}  // namespace isph
