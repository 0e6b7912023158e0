// The wall faces of a scene's fluid set-up: each wall particle's normal and depth below the wall's
// surface (the no-slip condition and the impermeability of Project need them), and the check that each
// wall is thick enough for the kernel support of the fluid beside it.
#include <cmath>
#include <cstdio>

#include "core/neighbour_search.hpp"
#include "io/schema.hpp"
#include "sim/scene_parts.hpp"

namespace isph {

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
// A wall body filled on rings (io/case.hpp LatticeType) is a circle of radius R about c instead: a
// particle at distance r from c lies R - r below the surface along n = (x - c)/r, exactly, where the
// lattice's free sites would give a staircase's faces; those deeper than the support keep n = 0.
// Returns 1 for the particles check_wall_thickness leaves out: the corners (normals bisecting two or
// more faces) and the walls on rings; 0 for the others.
template <int D>
std::vector<unsigned char> wall_surface_geometry(const CaseSpec& spec, FluidSetup<D>& f,
                                                 const std::vector<unsigned char>& structure_fixed,
                                                 const std::vector<Real>& spacing, Real support,
                                                 const Periodicity<D>& period, const Vec<D>& gravity) {
  const Index n = static_cast<Index>(f.x.size());
  f.wall_normal.assign(n, Vec<D>::zero());
  f.wall_depth.assign(n, 0);
  std::vector<unsigned char> unchecked(n, 0);
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
  if (boundary.empty()) return unchecked;
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
    const bool wall = f.kind[a] == FluidKind::wall;
    if (wall && spec.bodies[f.body[a]].lattice == LatticeType::rings) {
      const Shape& circle = spec.bodies[f.body[a]].shape;
      const Vec<D> r = f.x[a] - to_vec<D>(circle.center);
      const Real distance = std::sqrt(norm2(r));
      const Real depth = circle.radius - distance;
      if (depth < support && distance > 0) f.wall_normal[a] = (1.0 / distance) * r, f.wall_depth[a] = depth;
      unchecked[a] = 1;
      continue;
    }
    const Real s = spacing[f.level[a]];
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
    const bool corner = ties > 1 && len > 1e-9 * dist;
    unchecked[a] = corner;
    f.wall_normal[a] = corner ? (1.0 / len) * sum : (1.0 / dist) * first;
    f.wall_depth[a] = dist - 0.5 * s;
  }
  return unchecked;
}

// Every wall must be thick enough to fill the kernel support of the fluid beside it: behind each
// particle of a wall's first layer there must be wall particles down to a depth of 2h. Corners are left
// out: a corner is as thick as the faces it joins, which are checked, and along its diagonal normal the
// lattice's particles lie sqrt(2) dx apart, the second of them beyond the support. So are walls on rings,
// which are as thick as their radius.
template <int D>
void check_wall_thickness(const CaseSpec& spec, const FluidSetup<D>& f, const std::vector<unsigned char>& unchecked,
                          Real support, const Periodicity<D>& period, const std::string& file,
                          std::vector<std::string>& problems) {
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi)
    if (spec.bodies[bi].lattice == LatticeType::rings && spec.bodies[bi].shape.radius < support)
      problems.push_back(file + ": bodies[" + std::to_string(bi) +
                         "].shape.radius: " + shortest_number(spec.bodies[bi].shape.radius) +
                         " m is less than the kernel support 2h = " + shortest_number(support) +
                         " m; a wall on rings must fill it (use the cartesian lattice, or a finer dx)");
  const Real dx = spec.dx;
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
    if (!(norm2(nrm) > 0) || f.wall_depth[a] > 0.75 * dx || unchecked[a]) continue;  // not on the first layer's faces
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

#define ISPH_WALL_FACES(D)                                                                                        \
  template std::vector<unsigned char> wall_surface_geometry<D>(                                                   \
      const CaseSpec&, FluidSetup<D>&, const std::vector<unsigned char>&, const std::vector<Real>&, Real,         \
      const Periodicity<D>&, const Vec<D>&);                                                                      \
  template void check_wall_thickness<D>(const CaseSpec&, const FluidSetup<D>&, const std::vector<unsigned char>&, \
                                        Real, const Periodicity<D>&, const std::string&, std::vector<std::string>&);
ISPH_WALL_FACES(2)
ISPH_WALL_FACES(3)
#undef ISPH_WALL_FACES

}  // namespace isph
