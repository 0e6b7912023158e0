#pragma once
// The plain view of the fluid and wall particles that the ISPH functors read (seed 001 §2.1).
// One particle set: fluid, wall and structure particles, told apart by `kind`. To the fluid, a
// structure particle is a wall particle that moves: the boundary particles (walls and structures) carry
// a velocity and an acceleration (prescribed for walls, from TLSPH for structures) and, from the set-up
// (sim/scene.cpp), the unit normal of the boundary surface nearest to them (pointing into the fluid)
// and their depth below that surface; a structure's normals turn with its deformation.
#include "core/types.hpp"
#include "kernels/operators.hpp"

namespace isph {

enum class FluidKind : unsigned char { fluid = 0, wall = 1, structure = 2 };

// Free-surface classes of seed 001 Fig. 2.
enum class SurfaceClass : unsigned char { interior = 0, near_surface = 1, surface = 2, splash = 3 };

// The PPE row of an open boundary's buffer particles (sim/open_boundary.hpp): an outlet's is Dirichlet
// at its pressure; an inlet's is a wall row.
struct OpenZoneRow {
  bool outlet = false;
  Real pressure = 0;
};

template <int D>
struct FluidView {
  OperatorView<D> op;  // positions, volumes, CSR neighbours, kernel, periodicity
  const FluidKind* kind;
  const Vec<D>* wall_velocity;      // velocity of wall and structure particles
  const Vec<D>* wall_acceleration;  // their acceleration
  const Vec<D>* wall_normal;        // walls: unit normal of the nearest wall surface, into the fluid
  const Real* wall_depth;           // walls: distance below that surface
  Real dx;
  const Index* open_zone = nullptr;        // buffer particles: their open boundary (-1: none); null without any
  const OpenZoneRow* open_rows = nullptr;  // per open boundary

  ISPH_HD bool is_fluid(Index a) const { return kind[a] == FluidKind::fluid; }
  ISPH_HD bool is_structure(Index a) const { return kind[a] == FluidKind::structure; }
  // An open boundary's buffer particle: it carries the flow's velocity, not a wall's.
  ISPH_HD bool is_open(Index a) const { return open_zone && open_zone[a] >= 0; }
  ISPH_HD bool is_outlet(Index a) const { return is_open(a) && open_rows[open_zone[a]].outlet; }

  // How much wall particle w stands in for fluid around fluid particle a, in [0, 1]: the presence of a
  // fluid particle at w's mirror image across its wall surface, m = x_w + 2 d_w n_w, judged from a's
  // fluid neighbours (m is always closer to a than w is). 1 when a fluid particle lies within dx/2 of m,
  // 0 beyond dx, a cosine ramp between. A wet wall completes the kernel support of the fluid next to
  // it; a dry wall (above a free surface) must not, or the fluid where a free surface meets a wall is
  // not seen as a free surface.
  ISPH_HD Real wall_wetness(Index a, Index w) const {
    constexpr Real pi = 3.14159265358979323846;
    const Vec<D> n = wall_normal[w];
    if (!(norm2(n) > 0)) return 0;
    const Vec<D> m = (2 * wall_depth[w]) * n - op.r(a, w);  // m - x_a
    Real nearest2 = norm2(m);
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      if (is_fluid(b)) nearest2 = fmin(nearest2, norm2(m + op.r(a, b)));
    }
    const Real q = sqrt(nearest2) / dx;
    if (q <= 0.5) return 1;
    if (q >= 1) return 0;
    return 0.5 * (1 + cos(pi * (q - 0.5) / 0.5));
  }

  // sum_b (V_b / V_a) W_ab over a's neighbours and a itself (walls complete the support): a's number
  // density times V_a, lattice_kernel_sum on a regular lattice of a's spacing. A neighbour counts with its
  // volume's share, so that the smaller particles of a finer structure count less; `beside_structure`
  // says whether one is a structure particle (on a lattice of its own, not the fluid's).
  ISPH_HD Real kernel_sum(Index a, bool& beside_structure) const {
    Real s = op.own_kernel(a).value(0);
    beside_structure = false;
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      beside_structure = beside_structure || is_structure(b);
      s += (op.volume[b] / op.volume[a]) * op.kernel(a, b).value(sqrt(norm2(op.r(a, b))));
    }
    return s;
  }

  // The neighbour of a nearest to it among those `keep(b)` accepts, or -1; its squared distance in r2.
  template <class Keep>
  ISPH_HD Index nearest_neighbour(Index a, Keep keep, Real& r2) const {
    Index nearest = -1;
    r2 = 1e300;
    for (Index k = op.nbr_offset[a]; k < op.nbr_offset[a + 1]; ++k) {
      const Index b = op.nbr[k];
      if (!keep(b)) continue;
      const Real d2 = norm2(op.r(a, b));
      if (d2 < r2) r2 = d2, nearest = b;
    }
    return nearest;
  }

  // How far particle a lies beyond the surface of boundary particle b, along b's normal (negative:
  // on b's side of the surface, inside the wall or structure).
  ISPH_HD Real beyond_surface(Index a, Index b) const { return dot(op.r(a, b), wall_normal[b]) - wall_depth[b]; }

  // Weight of neighbour b in the free-surface measures of fluid particle a (div r, grad Psi).
  ISPH_HD Real surface_weight(Index a, Index b) const { return is_fluid(b) || is_open(b) ? 1 : wall_wetness(a, b); }

  // The velocity a fluid particle a sees at neighbour b. For a wall particle this is the no-slip
  // extension of Morris et al. (1997, J. Comput. Phys. 136:214): u_b = U_w - (d_b / d_a)(u_a - U_w),
  // with d_b the wall particle's depth and d_a the fluid particle's distance from the same wall
  // surface (at least dx/2), which extends a velocity profile that is linear in the wall-normal
  // distance and equals U_w on the wall exactly, so the viscous term of a linear shear is zero.
  // An open boundary's buffer particle is seen with its own velocity.
  ISPH_HD Vec<D> velocity_seen(Index a, Index b, const Vec<D>* u) const {
    if (is_fluid(b) || is_open(b)) return is_fluid(b) ? u[b] : wall_velocity[b];
    const Vec<D> uw = wall_velocity[b];
    return uw - (no_slip_gain(a, b) - 1) * (u[a] - uw);
  }
  // d(u_a - u_b)/dU_b of the velocity a sees at boundary particle b: 1 + d_b / d_a (1 for fluid and
  // buffer particles).
  ISPH_HD Real no_slip_gain(Index a, Index b) const {
    if (is_fluid(b) || is_open(b)) return 1;
    return 1 + wall_depth[b] / fmax(beyond_surface(a, b), 0.5 * dx);
  }

  // The free-slip (mirror) extension instead: the wall particle carries a's velocity relative to the
  // wall with the wall-normal component reversed, so the extended field has no jump in the tangential
  // velocity across the wall. Used where a smooth field is extrapolated (the Taylor correction after
  // shifting), not where the wall's shear acts (the viscous term).
  ISPH_HD Vec<D> velocity_mirrored(Index a, Index b, const Vec<D>* u) const {
    if (is_fluid(b)) return u[b];
    if (is_open(b)) return wall_velocity[b];
    const Vec<D> n = wall_normal[b];
    const Vec<D> rel = u[a] - wall_velocity[b];
    return wall_velocity[b] + rel - (2 * dot(rel, n)) * n;
  }
};

}  // namespace isph
