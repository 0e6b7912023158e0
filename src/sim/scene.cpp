#include "sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/neighbour_search.hpp"
#include "io/case_loader.hpp"

namespace isph {

namespace {

std::array<double, 3> to_array(const Vec<2>& v) { return {v[0], v[1], 0.0}; }
std::array<double, 3> to_array(const Vec<3>& v) { return {v[0], v[1], v[2]}; }

// Bounding box of a shape in the first D components.
template <int D>
void shape_bounds(const Shape& s, Vec<D>& lo, Vec<D>& hi) {
  const auto [low, high] = s.bounding_box(D);
  lo = to_vec<D>(low), hi = to_vec<D>(high);
}

// Lattice points origin + (i + offset) dx inside the shape.
template <int D>
std::vector<Vec<D>> fill_lattice(const Shape& shape, const std::array<double, 3>& origin,
                                 const std::array<double, 3>& offset, Real dx) {
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
    for (int d = 0; d < D; ++d) p[d] = origin[d] + (first[d] + idx[d] + offset[d]) * dx;
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

// A wedge's own lattice: columns s apart from the keel out to each chine, each holding n particles
// stacked vertically from the outer face, n = round(thickness / (s cos β)), their pitch the vertical
// thickness / n. The lattice is a rectangle's sheared onto each panel's slope (a shear keeps areas):
// the faces are straight rows of particles, and each particle's cell, s times the pitch, makes the
// panel exactly its thickness (docs/CASES.md, shapes).
struct WedgeLattice {
  int layers = 1;
  Real pitch = 0;  // vertical distance between a column's particles
};
WedgeLattice wedge_lattice(const Shape& w, Real s) {
  const Real vertical = w.vertical_thickness();
  const int layers = std::max(1, static_cast<int>(std::lround(vertical / s)));
  return {layers, vertical / layers};
}

template <int D>
std::vector<Vec<D>> fill_wedge(const Shape& w, Real s) {
  std::vector<Vec<D>> points;
  const WedgeLattice lattice = wedge_lattice(w, s);
  const int columns = static_cast<int>(std::lround(w.half_breadth / s));
  for (int side : {-1, 1})
    for (int i = 0; i < columns; ++i) {
      const Real across = (i + 0.5) * s;
      for (int j = 0; j < lattice.layers; ++j) {
        Vec<D> p = Vec<D>::zero();
        p[0] = w.apex[0] + side * across;
        p[1] = w.apex[1] + across * w.slope() + (j + 0.5) * lattice.pitch;
        points.push_back(p);
      }
    }
  return points;
}

// A body's particles: its shape filled on its lattice (a wedge on its own).
template <int D>
std::vector<Vec<D>> fill_body(const BodySpec& body, Real s) {
  if (body.shape.type == ShapeType::wedge) return fill_wedge<D>(body.shape, s);
  return fill_lattice<D>(body.shape, body.lattice_origin, body.lattice_offset, s);
}
// The volume of each particle of a body of spacing s.
template <int D>
Real cell_volume(const Shape& shape, Real s) {
  if (shape.type == ShapeType::wedge) return s * wedge_lattice(shape, s).pitch;
  return D == 2 ? s * s : s * s * s;
}

// The shape grown by `margin` on every side (an edge load takes the particles whose lattice cell
// touches its region: centres within dx/2 of it).
Shape grown(Shape s, Real margin) {
  s.radius += margin;
  if (s.type == ShapeType::cylinder) {  // both ends out by the margin
    const Real length = std::sqrt(s.axis[0] * s.axis[0] + s.axis[1] * s.axis[1] + s.axis[2] * s.axis[2]);
    for (int d = 0; d < 3; ++d) {
      s.base[d] -= margin * s.axis[d] / length;
      s.axis[d] += 2 * margin * s.axis[d] / length;
    }
  }
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
  if (iv.type == InitialVelocityType::uniform) return to_vec<D>(iv.value);
  if (iv.type == InitialVelocityType::cantilever_mode) {
    const Vec<D> axis = to_vec<D>(iv.axis), dir = to_vec<D>(iv.direction);
    const Real s = std::clamp(dot(X - to_vec<D>(iv.root), axis), 0.0, iv.length);
    const Real shape = cantilever_mode_shape(iv.kL, s / iv.length) / cantilever_mode_shape(iv.kL, 1.0);
    return (iv.tip_velocity * shape) * dir;
  }
  return Vec<D>::zero();
}

// The particle spacings of a case, finest first: the levels of the kernel table (kernels/operators.hpp
// KernelTable). The case's dx is the fluid's and the walls'; a structure body may be finer (its own dx,
// or the case's dx / refinement). Bodies of equal spacing share a level.
struct Resolutions {
  std::vector<Real> spacing;  // ascending: level l has the spacing spacing[l]
  Real dx = 0;
  explicit Resolutions(const CaseSpec& spec) : dx(spec.dx) {
    spacing.push_back(spec.dx);
    for (const auto& b : spec.bodies) spacing.push_back(b.spacing(spec.dx));
    std::sort(spacing.begin(), spacing.end());
    spacing.erase(std::unique(spacing.begin(), spacing.end()), spacing.end());
  }
  int levels() const { return static_cast<int>(spacing.size()); }
  int level(const BodySpec& b) const {
    return static_cast<int>(std::find(spacing.begin(), spacing.end(), b.spacing(dx)) - spacing.begin());
  }
  int fluid_level() const { return level_of(dx); }
  int level_of(Real s) const {
    return static_cast<int>(std::find(spacing.begin(), spacing.end(), s) - spacing.begin());
  }
  template <int D>
  KernelTable<D> kernels(const KernelSpec& k) const {
    KernelTable<D> table;
    table.levels = levels();
    for (int l = 0; l < levels(); ++l) table.kernel[l] = SmoothingKernel<D>::make(k.type, k.h_factor * spacing[l]);
    return table;
  }
};

// Appends a fluid or wall body's lattice points to the fluid set-up.
template <int D>
void add_fluid_body(const CaseSpec& spec, std::size_t bi, const std::vector<Vec<D>>& points, int level,
                    FluidSetup<D>& f) {
  const BodySpec& body = spec.bodies[bi];
  const bool is_fluid = body.kind == ParticleKind::fluid;
  const Real volume = cell_volume<D>(body.shape, spec.dx);
  const bool moves = !is_fluid && body.motion.type != MotionType::none;
  if (moves) f.motions.emplace_back(body.motion);
  f.motion.resize(f.x.size(), -1);
  f.body.insert(f.body.end(), points.size(), static_cast<Index>(bi));
  for (const auto& p : points) {
    const Vec<D> wall_velocity = moves ? f.motions.back().velocity(p, 0) : Vec<D>::zero();
    f.id.push_back(static_cast<Index>(f.x.size()));
    f.x.push_back(p);
    f.u.push_back(is_fluid ? initial_velocity<D>(body.initial_velocity, p) : wall_velocity);
    f.volume.push_back(volume);
    f.kind.push_back(is_fluid ? FluidKind::fluid : FluidKind::wall);
    f.level.push_back(static_cast<unsigned char>(level));
    f.wall_velocity.push_back(wall_velocity);
    f.motion.push_back(moves ? static_cast<Index>(f.motions.size()) - 1 : -1);
    if (!f.structure_index.empty()) f.structure_index.push_back(-1);
  }
}

// Appends a structure particle of the given volume to the fluid set-up, where it acts as a moving
// boundary (coupled cases).
template <int D>
void add_structure_particle(const Vec<D>& x, const Vec<D>& v, Index structure_index, Real volume, int level,
                            std::size_t body, FluidSetup<D>& f) {
  f.structure_index.resize(f.x.size(), -1);
  f.id.push_back(static_cast<Index>(f.x.size()));
  f.x.push_back(x);
  f.u.push_back(v);
  f.volume.push_back(volume);
  f.kind.push_back(FluidKind::structure);
  f.level.push_back(static_cast<unsigned char>(level));
  f.wall_velocity.push_back(v);
  f.structure_index.push_back(structure_index);
  f.body.push_back(static_cast<Index>(body));
  f.motion.resize(f.x.size(), -1);
}

// Whether q lies outside the box [lo, hi] on a non-periodic axis, the box being open against gravity
// (a tank is open at its top).
template <int D>
bool outside_open_box(const Vec<D>& q, const Vec<D>& lo, const Vec<D>& hi, const Vec<D>& gravity,
                      const Periodicity<D>& period) {
  for (int d = 0; d < D; ++d)
    if (!period.axis[d] && ((q[d] < lo[d] && !(gravity[d] > 0)) || (q[d] > hi[d] && !(gravity[d] < 0)))) return true;
  return false;
}

template <int D>
Periodicity<D> periodicity(const PeriodicSpec& p) {
  Periodicity<D> period;
  for (int d = 0; d < D; ++d) {
    period.axis[d] = p.axis(d);
    period.lo[d] = p.lo(d);
    period.length[d] = p.hi(d) - p.lo(d);
  }
  return period;
}

// Wall surface geometry for the no-slip condition (FluidView::velocity_seen): for each wall particle
// the nearest lattice point (of its own spacing s, around it) that is inside the bounding box of all
// particles and not occupied by a boundary particle (the "cavity" the fluid lives in) gives the normal
// n_w, pointing to it, and the depth d_w = |q - x_w| - s/2 (the wall surface lies half a spacing before
// the first free lattice point). A point is occupied when it lies inside a boundary particle's cell (the
// square or cube of its own spacing around it), so that a fine structure's sites inside a coarser wall
// are occupied too.
// The box is open upwards, against gravity, as the tank is: the top face of a wall is a surface too,
// where water thrown over it lands (with the box closed there, the Walhorn tank's right wall had only
// its inner face, and two spray particles that fell onto its top sank into it, 4.8 mm deep).
// Boundary particles with no free point within the fluid's kernel support keep n = 0 and never meet fluid.
// What occupies a point depends on the particle: a structure particle's surface is found among all
// boundary particles, a wall particle's only among the walls and the clamped structure particles, which
// stay where they are. The free part of a structure standing on a wall may move off it (the elastic
// gate's foot lifts off the floor): the wall beneath is then exposed, and its particles need the normal
// and depth of that face (with the foot counted, they pointed sideways, 1.7 dx deep, and water that
// ran into the floor there was not stopped by the impermeability condition of Project).
// Returns 1 for the corner particles (normals bisecting two or more faces), 0 for the others.
template <int D>
std::vector<unsigned char> wall_surface_geometry(FluidSetup<D>& f, const std::vector<unsigned char>& structure_fixed,
                                                 const std::vector<Real>& spacing, Real support,
                                                 const Periodicity<D>& period, const Vec<D>& gravity) {
  const Index n = static_cast<Index>(f.x.size());
  f.wall_normal.assign(n, Vec<D>::zero());
  f.wall_depth.assign(n, 0);
  std::vector<unsigned char> corner(n, 0);
  std::vector<Vec<D>> boundary, permanent;
  std::vector<Real> boundary_half, permanent_half;  // half the spacing of each
  for (Index a = 0; a < n; ++a) {
    if (f.kind[a] == FluidKind::fluid) continue;
    const Real half = 0.5 * spacing[f.level[a]];
    boundary.push_back(f.x[a]);
    boundary_half.push_back(half);
    if (f.kind[a] == FluidKind::wall || structure_fixed[f.structure_index[a]]) {
      permanent.push_back(f.x[a]);
      permanent_half.push_back(half);
    }
  }
  if (boundary.empty()) return corner;
  Vec<D> lo = f.x[0], hi = f.x[0];
  for (const auto& x : f.x)
    for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], x[d]), hi[d] = std::max(hi[d], x[d]);
  const Real coarsest = *std::max_element(spacing.begin(), spacing.end());
  CellList<D> boundary_cells, permanent_cells;
  boundary_cells.build(boundary, coarsest, period);
  permanent_cells.build(permanent, coarsest, period);
  // Occupancy: q inside the cell of a particle of `cells` (whose half spacings are `half`).
  auto occupied = [&](const CellList<D>& cells, const std::vector<Real>& half, const Vec<D>& q) {
    bool hit = false;
    cells.view().for_each_near(q, [&](Index j, const Vec<D>& r) {
      bool inside = true;
      for (int d = 0; d < D; ++d) inside = inside && std::abs(r[d]) < half[j];
      hit = hit || inside;
    });
    return hit;
  };
  for (Index a = 0; a < n; ++a) {
    if (f.kind[a] == FluidKind::fluid) continue;
    const Real s = spacing[f.level[a]];
    const bool wall = f.kind[a] == FluidKind::wall;
    const int reach = static_cast<int>(std::ceil(support / s)) + 1;
    int best = std::numeric_limits<int>::max();  // |k|^2 of the nearest free sites, offsets k s
    Vec<D> first = Vec<D>::zero(), sum = Vec<D>::zero();
    int ties = 0;
    int k[D];
    for (int d = 0; d < D; ++d) k[d] = -reach;
    while (true) {
      int k2 = 0;
      Vec<D> offset;
      for (int d = 0; d < D; ++d) offset[d] = k[d] * s, k2 += k[d] * k[d];
      if (k2 > 0 && k2 <= best) {
        const Vec<D> q = period.wrap(f.x[a] + offset);
        if (!outside_open_box(q, lo, hi, gravity, period) &&
            !occupied(wall ? permanent_cells : boundary_cells, wall ? permanent_half : boundary_half, q)) {
          if (k2 < best) best = k2, first = offset, sum = Vec<D>::zero(), ties = 0;
          sum = sum + offset;
          ++ties;
        }
      }
      int d = 0;
      while (d < D && ++k[d] > reach) k[d] = -reach, ++d;
      if (d == D) break;
    }
    if (best == std::numeric_limits<int>::max()) continue;
    const Real dist = std::sqrt(static_cast<Real>(best)) * s;
    // A convex corner or edge has its nearest free sites on two or more faces: its normal is their
    // bisector, as if the corner were chamfered, so that water arriving on either face is met (with
    // the normal of one face only, spray that fell onto the Walhorn tank's wall top at its inner corner
    // was stopped only sideways, and slid down inside the wall). Sites on opposite sides (a wall one
    // column thick at its middle) cancel; the first found is then kept.
    const Real len = std::sqrt(norm2(sum));
    corner[a] = ties > 1 && len > 1e-9 * dist;
    f.wall_normal[a] = corner[a] ? (1.0 / len) * sum : (1.0 / dist) * first;
    f.wall_depth[a] = dist - 0.5 * s;
  }
  return corner;
}

// Every wall must be thick enough to fill the kernel support of the fluid beside it: behind each
// particle of a wall's first layer there must be wall particles down to a depth of 2h. Corners are left
// out: a corner is as thick as the faces it joins, which are checked, and along its diagonal normal the
// lattice's particles lie sqrt(2) dx apart, the second of them beyond the support.
template <int D>
void check_wall_thickness(const FluidSetup<D>& f, const std::vector<unsigned char>& corner, Real dx, Real support,
                          const Periodicity<D>& period, const std::string& file, std::vector<std::string>& problems) {
  const Index n = static_cast<Index>(f.x.size());
  std::vector<Vec<D>> walls;
  for (Index a = 0; a < n; ++a)
    if (f.kind[a] == FluidKind::wall) walls.push_back(f.x[a]);
  if (walls.empty()) return;
  const Index layers_needed = static_cast<Index>(std::ceil(support / dx - 1e-9));  // for fluid right at the wall
  Index thin = 0;
  Vec<D> example = Vec<D>::zero();
  const NeighbourList nl = build_neighbour_list<D>(walls, support, nullptr, period);
  Index w = 0;
  for (Index a = 0; a < n; ++a) {
    if (f.kind[a] != FluidKind::wall) continue;
    const Index self = w++;
    const Vec<D> nrm = f.wall_normal[a];
    if (!(norm2(nrm) > 0) || f.wall_depth[a] > 0.75 * dx || corner[a]) continue;  // not on the first layer's faces
    // the deepest wall particle straight behind (within dx/2 of the inward line)
    Real deepest = 0;
    for (Index k = nl.offset[self]; k < nl.offset[self + 1]; ++k) {
      const Vec<D> r = period.delta(walls[nl.index[k]], walls[self]);
      const Real along = -dot(r, nrm);
      if (norm2(r - (-along) * nrm) < 0.25 * dx * dx) deepest = std::max(deepest, along);
    }
    if (deepest < (layers_needed - 1) * dx - 0.25 * dx) {
      if (thin == 0) example = walls[self];
      ++thin;
    }
  }
  if (thin > 0) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "%s: bodies: %d wall particles (e.g. at (%g, %g)) have fewer than %d wall layers behind them; walls "
                  "must be at least %d particles (%g m) thick at dx = %g to fill the kernel support (2h = %g m)",
                  file.c_str(), thin, example[0], example[1], layers_needed, layers_needed, layers_needed * dx, dx,
                  support);
    problems.push_back(buf);
  }
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

// The support of the water's first layer, dx/2 from a structure's face, reaches through a structure of
// thickness T to its empty far side where T + dx/2 < 2h: a kernel deficit that reads as a free surface. In
// 3D this shifted water into a gate 5 mm thick at 2h = 12 mm and ran it out under its foot; at 2h = 6 mm
// (the shipped case) it did not (docs/VALIDATION.md section 31). In 2D no harm was measured. Measured on
// box shapes, whose thinnest side is the thickness.
template <int D>
void warn_thin_structures(const CaseSpec& spec, const Resolutions& resolutions, const std::string& file,
                          std::vector<std::string>& warnings) {
  if (D != 3 || !spec.stages.fluid || !spec.stages.structure) return;
  const Real support = resolutions.kernels<D>(spec.kernel).kernel[resolutions.fluid_level()].support();
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& b = spec.bodies[bi];
    if (b.kind != ParticleKind::structure || b.shape.type != ShapeType::box) continue;
    Real thickness = std::numeric_limits<Real>::max();
    for (int d = 0; d < D; ++d) thickness = std::min(thickness, b.shape.max[d] - b.shape.min[d]);
    if (thickness + 0.5 * spec.dx >= support) continue;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: bodies[%zu]: structure '%s' is %g m thick: the kernel support (2h = %g m) of the water beside "
                  "it reaches through it to its far side; in 3D this drew water into a gate and under it "
                  "(docs/VALIDATION.md section 31). A water spacing dx <= %g m keeps the support inside it",
                  file.c_str(), bi, b.name.c_str(), thickness, support, thickness / (support / spec.dx - 0.5));
    warnings.push_back(buf);
  }
}

// Checks the fluid set-up and completes it: material, overlaps, containment, wall geometry, the
// reference velocity of Eq. 49 and the fluid probes.
template <int D>
void finish_fluid(const CaseSpec& spec, Scene<D>& scene, FluidSetup<D>& f, const TlsphSetup<D>& structure,
                  std::vector<std::string>& problems) {
  const std::string file = spec.source_path.empty() ? spec.name : spec.source_path;
  const Real dx = spec.dx;
  const Index n = static_cast<Index>(f.x.size());
  const Periodicity<D> period = periodicity<D>(spec.periodic);
  const Resolutions resolutions(spec);
  f.dx = dx;
  f.kernels = resolutions.kernels<D>(spec.kernel);
  f.fluid_level = resolutions.fluid_level();
  f.kernel_correction = spec.kernel.correction;
  f.period = period;
  f.gravity = to_vec<D>(spec.gravity);
  f.settings = spec.fluid;
  f.fsi_shifting = spec.coupling.fsi_shifting;
  f.fsi_shifting_law = spec.coupling.fsi_shifting_law;
  f.interaction_force = spec.coupling.interaction_force;

  // One fluid material.
  std::string material;
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& b = spec.bodies[bi];
    if (b.kind != ParticleKind::fluid) continue;
    if (material.empty())
      material = b.material;
    else if (b.material != material)
      problems.push_back(file + ": bodies[" + std::to_string(bi) +
                         "].material: all fluid bodies must share one material ('" + material + "' and '" + b.material +
                         "')");
  }
  for (const auto& m : spec.materials)
    if (m.name == material) f.density = m.density, f.viscosity = m.viscosity;

  Index fluid = 0, wall = 0;
  for (Index a = 0; a < n; ++a) {
    fluid += f.kind[a] == FluidKind::fluid;
    wall += f.kind[a] == FluidKind::wall;
  }
  scene.fluid_particles = fluid;
  scene.wall_particles = wall;
  if (fluid == 0) {
    problems.push_back(file + ": bodies: stages.fluid is on but no fluid body has particles");
    return;
  }
  if (f.motions.size() > static_cast<std::size_t>(kMaxMotions))
    problems.push_back(file + ": bodies: " + std::to_string(f.motions.size()) + " moving wall bodies; at most " +
                       std::to_string(kMaxMotions) + " are supported");

  // Particles on periodic axes must lie inside the period.
  for (int d = 0; d < D; ++d) {
    if (!period.axis[d]) continue;
    for (Index a = 0; a < n; ++a)
      if (f.x[a][d] < period.lo[d] || f.x[a][d] >= period.lo[d] + period.length[d]) {
        problems.push_back(file + ": periodic: a particle at coordinate " + std::to_string(f.x[a][d]) + " on axis " +
                           std::to_string(d) + " lies outside the periodic range; shrink the bodies to it");
        break;
      }
  }

  // Overlaps: a fluid particle inside a wall or structure body, a wall particle inside a structure.
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& b = spec.bodies[bi];
    if (b.kind == ParticleKind::fluid) continue;
    for (const FluidKind other : {FluidKind::fluid, FluidKind::wall}) {
      if (other == FluidKind::wall && b.kind != ParticleKind::structure) continue;
      Index inside = 0;
      for (Index a = 0; a < n; ++a)
        if (f.kind[a] == other && b.shape.contains(to_array(f.x[a]), D)) ++inside;
      if (inside > 0)
        problems.push_back(file + ": bodies[" + std::to_string(bi) + "].shape: " + std::to_string(inside) + " " +
                           (other == FluidKind::fluid ? "fluid" : "wall") + " particles lie inside this " +
                           (b.kind == ParticleKind::wall ? "wall" : "structure") + " body '" + b.name +
                           "' (bodies of different kinds must not overlap)");
    }
  }

  // Containment: fluid inside the walls' bounding box on every non-periodic axis (open upwards,
  // against gravity).
  bool all_periodic = true;
  for (int d = 0; d < D; ++d) all_periodic = all_periodic && period.axis[d];
  Vec<D> lo, hi;
  for (int d = 0; d < D; ++d) lo[d] = std::numeric_limits<Real>::max(), hi[d] = -lo[d];
  for (Index a = 0; a < n; ++a)
    if (f.kind[a] == FluidKind::wall)
      for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], f.x[a][d]), hi[d] = std::max(hi[d], f.x[a][d]);
  if (wall == 0 && !all_periodic) {
    problems.push_back(file + ": bodies: the fluid needs wall bodies around it (or periodic axes)");
  } else {
    Index outside = 0;
    for (Index a = 0; a < n; ++a)
      if (f.kind[a] == FluidKind::fluid && outside_open_box(f.x[a], lo, hi, to_vec<D>(spec.gravity), period)) ++outside;
    if (outside > 0)
      problems.push_back(file + ": bodies: " + std::to_string(outside) +
                         " fluid particles lie outside every wall (beyond the walls' bounding box)");
  }

  const std::vector<unsigned char> corner = wall_surface_geometry(
      f, structure.fixed, resolutions.spacing, f.fluid_kernel().support(), period, to_vec<D>(spec.gravity));
  check_wall_thickness(f, corner, dx, f.fluid_kernel().support(), period, file, problems);

  // Moving walls: where they go and how fast, sampled over the run (for Eq. 49 and the escape box); and
  // how fast the moving clamps of structures go (for Eq. 49: a slamming wedge's water is still until it
  // arrives).
  constexpr int samples = 200;
  const auto sample_time = [&spec](int k) { return spec.end_time * k / samples; };
  Real boundary_speed = 0;
  for (std::size_t a = 0; a < structure.X.size(); ++a) {
    if (!structure.fixed[a] || structure.motion[a] < 0) continue;
    for (int k = 0; k <= samples; ++k) {
      const Vec<D> v = structure.motions[structure.motion[a]].velocity(structure.X[a], sample_time(k));
      boundary_speed = std::max(boundary_speed, std::sqrt(norm2(v)));
    }
  }
  for (Index a = 0; a < n; ++a) {
    if (f.motion[a] < 0) continue;
    const RigidMotion<D>& m = f.motions[f.motion[a]];
    for (int k = 0; k <= samples; ++k) {
      const Real t = sample_time(k);
      const Vec<D> x = m.position(f.x[a], t);
      for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], x[d]), hi[d] = std::max(hi[d], x[d]);
      boundary_speed = std::max(boundary_speed, std::sqrt(norm2(m.velocity(f.x[a], t))));
    }
  }

  // Reference velocity of Eq. 49: free fall over the fluid's height, or the fastest wall or clamp.
  Real fluid_lo = std::numeric_limits<Real>::max(), fluid_hi = -fluid_lo;
  const Vec<D> g = to_vec<D>(spec.gravity);
  const Real g_norm = std::sqrt(norm2(g));
  for (Index a = 0; a < n; ++a) {
    if (f.kind[a] == FluidKind::fluid && g_norm > 0) {
      const Real height = -dot(f.x[a], g) / g_norm;
      fluid_lo = std::min(fluid_lo, height), fluid_hi = std::max(fluid_hi, height);
    }
  }
  const Real fall = g_norm > 0 ? std::sqrt(2 * g_norm * (fluid_hi - fluid_lo + dx)) : 0;
  f.reference_velocity =
      spec.fluid.reference_velocity > 0 ? spec.fluid.reference_velocity : std::max(fall, boundary_speed);
  if (!(f.reference_velocity > 0))
    problems.push_back(file +
                       ": fluid.reference_velocity: no gravity and no moving wall or clamp; give the velocity scale of "
                       "the flow (Eq. 49 needs it)");

  // Escape box: the box of all particles (and of the moving walls' paths) grown by 2h, and upwards
  // (against gravity) by its own size.
  for (Index a = 0; a < n; ++a)
    for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], f.x[a][d]), hi[d] = std::max(hi[d], f.x[a][d]);
  if (g_norm > 0) {
    scene.up = (-1.0 / g_norm) * g;
    scene.rim = -std::numeric_limits<Real>::max();
    for (int corner = 0; corner < (1 << D); ++corner) {  // the box's highest corner
      Vec<D> c;
      for (int d = 0; d < D; ++d) c[d] = (corner >> d) & 1 ? hi[d] : lo[d];
      scene.rim = std::max(scene.rim, dot(c, scene.up));
    }
    // Less one kernel support: a particle that leaves the box sideways within 2h of the walls' top has
    // come over their top corner (the Walhorn obstacle's spray left at 0.16 mm below the top row at
    // 0.649 s); one that leaks through a wall lower down still stops the run.
    scene.rim -= f.fluid_kernel().support();
  }
  for (int d = 0; d < D; ++d) {
    const Real margin = f.fluid_kernel().support();
    scene.domain_lo[d] = period.axis[d] ? -std::numeric_limits<Real>::max() : lo[d] - margin;
    scene.domain_hi[d] = period.axis[d] ? std::numeric_limits<Real>::max() : hi[d] + margin;
    if (!period.axis[d] && g_norm > 0 && g[d] < 0) scene.domain_hi[d] += hi[d] - lo[d];
    if (!period.axis[d] && g_norm > 0 && g[d] > 0) scene.domain_lo[d] -= hi[d] - lo[d];
  }

  for (std::size_t pi = 0; pi < spec.probes.size(); ++pi) {
    const ProbeSpec& p = spec.probes[pi];
    if (p.type == ProbeType::displacement || p.type == ProbeType::structure_pressure) continue;
    if (p.type == ProbeType::force) {  // the loader checked that the body is a wall or a structure
      const auto body =
          std::find_if(spec.bodies.begin(), spec.bodies.end(), [&](const BodySpec& b) { return b.name == p.body; });
      scene.force_probes.push_back({p.name, static_cast<Index>(body - spec.bodies.begin())});
      f.wall_force = f.wall_force || body->kind == ParticleKind::wall;
      continue;
    }
    const Vec<D> point = to_vec<D>(p.point);
    if (p.type == ProbeType::pressure || p.type == ProbeType::velocity) {
      Real nearest = std::numeric_limits<Real>::max();
      for (Index a = 0; a < n; ++a) nearest = std::min(nearest, norm2(period.delta(point, f.x[a])));
      if (std::sqrt(nearest) > f.fluid_kernel().support())
        problems.push_back(file + ": probes[" + std::to_string(pi) + "].point: probe '" + p.name +
                           "' is farther than the kernel support from every fluid and wall particle");
    }
    scene.fluid_probes.push_back({p.name, p.type, point});
  }
}

}  // namespace

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
  const Real dx = spec.dx;
  Scene<D> scene;
  TlsphSetup<D> s;  // in creation order; sorted by cell at the end
  FluidSetup<D> fluid;

  const Resolutions resolutions(spec);
  if (resolutions.levels() > kMaxLevels)
    throw CaseError({file + ": bodies: " + std::to_string(resolutions.levels()) +
                     " particle spacings (the case's dx and the structures' own); at most " +
                     std::to_string(kMaxLevels) + " are supported"});
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi)
    if (spec.bodies[bi].spacing(dx) > dx)
      problems.push_back(file + ": bodies[" + std::to_string(bi) + "].dx: " + std::to_string(spec.bodies[bi].dx) +
                         " m is coarser than the case's dx = " + std::to_string(dx) +
                         " m; a structure may be finer than the water, not coarser");
  check_meshes_in_tank<D>(spec, file, problems);
  if (!problems.empty()) throw CaseError(problems);
  warn_thin_structures<D>(spec, resolutions, file, scene.warnings);
  for (const auto& m : spec.materials) s.materials.push_back(elastic_material(m, D));
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& body = spec.bodies[bi];
    const std::string key = "bodies[" + std::to_string(bi) + "]";
    const Real spacing = body.spacing(dx);
    const int level = resolutions.level(body);
    const auto points = fill_body<D>(body, spacing);
    const Real volume = cell_volume<D>(body.shape, spacing);
    if (points.empty()) {
      problems.push_back(file + ": " + key + ".shape: no particles at a spacing of " + std::to_string(spacing) +
                         " m (the shape is smaller than the particle spacing)");
      continue;
    }
    if (body.kind != ParticleKind::structure) {
      add_fluid_body<D>(spec, bi, points, level, fluid);
      continue;
    }
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
        problems.push_back(file + ": " + key + ".clamps[" + std::to_string(c) +
                           "]: the clamp region holds no particle of the body");
  }
  const Index n = static_cast<Index>(s.X.size());
  scene.has_structure = spec.stages.structure && n > 0;
  scene.has_fluid = spec.stages.fluid;
  if (spec.stages.structure && n == 0 && problems.empty())
    problems.push_back(file + ": bodies: the case has no structure particles (set stages.structure = false)");
  if (s.motions.size() > static_cast<std::size_t>(kMaxMotions))
    problems.push_back(file + ": bodies: " + std::to_string(s.motions.size()) +
                       " structures with moving clamps; at most " + std::to_string(kMaxMotions) + " are supported");
  if (scene.has_fluid) finish_fluid<D>(spec, scene, fluid, s, problems);

  // Loads: per-particle acceleration at full load.
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
        const Shape region = grown(load.region, 0.5 * body->spacing(dx));
        for (Index a = 0; a < n; ++a)
          if (s.body[a] == bi && !s.fixed[a] && region.contains(to_array(s.X[a]), D)) targets.push_back(a);
      }
      if (targets.empty())
        problems.push_back(file + ": " + key + ".region: no free particle of body '" + load.body + "' is loaded");
      // A total force F shared by the loaded particles, f_i = F / n; or a traction t on each particle's
      // cell face, f_i = t s^(D-1) (s the body's spacing). Then a_i = f_i / m_i.
      const Vec<D> force = load.type == LoadType::traction
                               ? std::pow(body->spacing(dx), D - 1) * to_vec<D>(load.traction)
                               : (1.0 / static_cast<Real>(targets.size())) * to_vec<D>(load.force);
      for (Index a : targets) field.acc[a] = (1.0 / (s.materials[s.material[a]].density * s.volume[a])) * force;
    }
    s.loads.push_back(std::move(field));
  }

  if (!problems.empty()) throw CaseError(problems);

  // Sort particles by cell for memory locality; keep the creation index as stable id.
  CellList<D> cells;
  s.kernels = resolutions.kernels<D>(spec.kernel);
  cells.build(s.X, s.kernels.largest_support());
  const std::vector<Index>& order = cells.order();
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
  scene.structure_id = order;
  scene.structure_body = s.body;
  std::vector<Index> sorted_slot(n);  // creation index -> index after sorting
  for (Index k = 0; k < n; ++k) sorted_slot[order[k]] = k;
  for (Index& i : fluid.structure_index)
    if (i >= 0) i = sorted_slot[i];

  // Structure probes: the structure particle nearest the point, which must lie within its spacing of the
  // body.
  for (std::size_t pi = 0; pi < spec.probes.size(); ++pi) {
    const ProbeSpec& p = spec.probes[pi];
    if (p.type != ProbeType::displacement && p.type != ProbeType::structure_pressure) continue;
    const Vec<D> point = to_vec<D>(p.point);
    Real best = std::numeric_limits<Real>::max();
    Index arg = -1;
    for (Index a = 0; a < n; ++a) {
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
