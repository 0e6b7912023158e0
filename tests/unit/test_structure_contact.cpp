// The penetration diagnostic (BodyContact, structure/interaction.hpp): on a block of structure
// particles tilted as the elastic gate's free end is when the water runs out under it, and on the
// concave corner of a tank's walls.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/neighbour_search.hpp"
#include "core/parallel.hpp"
#include "structure/interaction.hpp"

using namespace isph;

namespace {

constexpr Real dx = 1.0;

// BodyContact's verdict on every particle of the set, against the particles of kind `body`: inside or
// not, and how far behind the body's surface.
struct Verdict {
  std::vector<unsigned char> inside;
  std::vector<Real> depth;
};

Verdict contact_verdict(const std::vector<Vec<2>>& x, const std::vector<FluidKind>& kind,
                        const std::vector<Vec<2>>& normal, const std::vector<Real>& depth, FluidKind body) {
  const Index n = static_cast<Index>(x.size());
  const auto kernel = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2 * dx);
  const NeighbourList nl = build_neighbour_list<2>(x, kernel.support());
  std::vector<Real> volume(n, dx * dx), distance(n);
  std::vector<Vec<2>> zero(n, Vec<2>::zero());
  const OperatorView<2> op{n, x.data(), volume.data(), nl.offset.data(), nl.index.data(), kernel};
  const FluidView<2> view{op, kind.data(), zero.data(), zero.data(), normal.data(), depth.data(), dx};
  Verdict verdict{std::vector<unsigned char>(n, 2), std::vector<Real>(n, -1)};
  parallel_for(Exec{}, n, BodyContact<2>{view, body, verdict.inside.data(), distance.data(), verdict.depth.data()});
  return verdict;
}

// A block of cols x rows structure particles whose lower-left corner particle sits at the origin,
// turned by `tilt` about it, with the set-up's surface data: the unit normal of the nearest face
// (the left face for the corner column) and the depth below it; then the fluid points.
struct TiltedBlock {
  std::vector<Vec<2>> x;
  std::vector<FluidKind> kind;
  std::vector<Vec<2>> normal;
  std::vector<Real> depth;
  Index structure_count = 0;

  TiltedBlock(int cols, int rows, Real tilt) {
    const Real c = std::cos(tilt), s = std::sin(tilt);
    auto turn = [&](Vec<2> p) { return Vec<2>{{c * p[0] - s * p[1], s * p[0] + c * p[1]}}; };
    for (int i = 0; i < cols; ++i)
      for (int j = 0; j < rows; ++j) {
        x.push_back(turn(Vec<2>{{i * dx, j * dx}}));
        kind.push_back(FluidKind::structure);
        const Real to_left = i, to_bottom = j, to_right = cols - 1 - i, to_top = rows - 1 - j;
        const Real nearest = std::fmin(std::fmin(to_left, to_bottom), std::fmin(to_right, to_top));
        Vec<2> n = nearest == to_left     ? Vec<2>{{-1, 0}}
                   : nearest == to_bottom ? Vec<2>{{0, -1}}
                   : nearest == to_right  ? Vec<2>{{1, 0}}
                                          : Vec<2>{{0, 1}};
        normal.push_back(turn(n));
        depth.push_back((nearest + 0.5) * dx);
      }
    structure_count = static_cast<Index>(x.size());
  }
  // A fluid particle at p given in the block's own (untilted) frame.
  void add_fluid(Vec<2> local, Real tilt) {
    const Real c = std::cos(tilt), s = std::sin(tilt);
    x.push_back(Vec<2>{{c * local[0] - s * local[1], s * local[0] + c * local[1]}});
    kind.push_back(FluidKind::fluid);
    normal.push_back(Vec<2>::zero());
    depth.push_back(0);
  }

  std::vector<unsigned char> inside() const {
    return contact_verdict(x, kind, normal, depth, FluidKind::structure).inside;
  }
};

// The walls of a tank's lower-left corner, three layers thick on the lattice, the fluid's first lattice
// site at (dx/2, dx/2): the floor's and the side wall's faces lie along y = 0 and x = 0. Each wall
// particle's normal points to its nearest fluid lattice site q, its depth is |q - x| - dx/2 (as the
// set-up gives them, sim/scene.cpp).
Verdict tank_corner_verdict(Vec<2> fluid) {
  std::vector<Vec<2>> x, normal;
  std::vector<Real> depth;
  for (int i = -3; i < 8; ++i)
    for (int j = -3; j < 8; ++j) {
      if (i >= 0 && j >= 0) continue;
      x.push_back(Vec<2>{{(i + 0.5) * dx, (j + 0.5) * dx}});
      const Vec<2> to_fluid{{(std::max(i, 0) - i) * dx, (std::max(j, 0) - j) * dx}};
      const Real dist = std::sqrt(norm2(to_fluid));
      normal.push_back((1.0 / dist) * to_fluid);
      depth.push_back(dist - 0.5 * dx);
    }
  std::vector<FluidKind> kind(x.size(), FluidKind::wall);
  x.push_back(fluid);
  kind.push_back(FluidKind::fluid);
  normal.push_back(Vec<2>::zero());
  depth.push_back(0);
  return contact_verdict(x, kind, normal, depth, FluidKind::wall);
}

}  // namespace

// Each fluid point is judged by where it lies against the block's faces (the surface lies dx/2
// beyond the outer particles): inside when it has crossed a face, outside otherwise.
TEST(BodyContact, InsideMeansBehindTheSurfaceOfTheBody) {
  const Real tilt = 0.3;  // the gate's end turned by ~17 degrees, as at t = 0.044 s
  TiltedBlock block(8, 4, tilt);
  struct Case {
    Vec<2> local;
    bool inside;
    const char* what;
  };
  const std::vector<Case> cases{
      {{{3.5, -1.0}}, false, "on the lattice below the bottom face (dx/2 beyond the surface)"},
      {{{3.5, -0.25}}, true, "dx/4 behind the bottom face"},
      {{{-0.25, 1.5}}, true, "dx/4 behind the left face"},
      {{{-1.0, 1.5}}, false, "on the lattice beside the left face"},
      {{{3.5, 1.5}}, true, "amid the block"},
      {{{0.6, -1.15}}, false, "below the corner, beside the bottom face"},
      // The case met in the gate run at t = 0.0444 s: water running out a dx below the end face, under
      // the corner particle, the only structure particle within 1.5 dx, whose normal is the side face's.
      {{{0.15, -1.45}}, false, "a dx below the surface, under the corner particle"},
      {{{-0.9, -0.9}}, false, "off the corner, diagonally"},
  };
  for (const Case& c : cases) {
    TiltedBlock b = block;
    b.add_fluid(c.local, tilt);
    const auto in = b.inside();
    EXPECT_EQ(in.back(), c.inside ? 1 : 0) << c.what;
    for (Index s = 0; s < b.structure_count; ++s) EXPECT_EQ(in[s], 0);  // structure particles are not judged
  }
}

// In a tank's concave corner the walls' colour is 3/4 at the corner point: a fluid particle pressed
// into the corner has c > 1/2 (0.54 at 0.3 dx from both faces) but is in front of the nearest wall
// particle's face, so it is outside; one that has crossed the floor's face is inside, in the corner or
// away from it.
TEST(BodyContact, TankCornerOnTheLatticeIsOutside) {
  struct Case {
    Vec<2> at;
    Real depth;  // behind the surface; 0: outside
    const char* what;
  };
  const std::vector<Case> cases{
      {{{0.5, 0.5}}, 0, "the corner's lattice site"},
      {{{0.3, 0.3}}, 0, "pressed into the corner, 0.3 dx from both faces"},
      {{{0.15, 0.15}}, 0, "0.15 dx from both faces"},
      {{{4.5, 0.5}}, 0, "on the lattice above the floor"},
      {{{4.5, 0.2}}, 0, "0.2 dx above the floor's face"},
      {{{4.5, -0.25}}, 0.25, "dx/4 below the floor's face"},
      {{{0.5, -0.25}}, 0.25, "dx/4 below the floor's face, in the corner"},
      {{{4.5, -1.5}}, 1.5, "amid the floor's layers"},
  };
  for (const Case& c : cases) {
    const Verdict v = tank_corner_verdict(c.at);
    EXPECT_EQ(v.inside.back(), c.depth > 0 ? 1 : 0) << c.what;
    EXPECT_NEAR(v.depth.back(), c.depth * dx, 1e-12) << c.what;
    for (std::size_t w = 0; w + 1 < v.inside.size(); ++w) EXPECT_EQ(v.depth[w], 0);  // walls are not judged
  }
}
