// The penetration diagnostic (StructureContact, structure/interaction.hpp) on a block of structure
// particles tilted as the elastic gate's free end is when the water runs out under it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/neighbour_search.hpp"
#include "core/parallel.hpp"
#include "structure/interaction.hpp"

using namespace isph;

namespace {

constexpr Real dx = 1.0;

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
        Vec<2> n = nearest == to_left ? Vec<2>{{-1, 0}} : nearest == to_bottom ? Vec<2>{{0, -1}}
                   : nearest == to_right ? Vec<2>{{1, 0}} : Vec<2>{{0, 1}};
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
    const Index n = static_cast<Index>(x.size());
    const auto kernel = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2 * dx);
    const NeighbourList nl = build_neighbour_list<2>(x, kernel.support());
    std::vector<Real> volume(n, dx * dx), distance(n);
    std::vector<Vec<2>> zero(n, Vec<2>::zero());
    const OperatorView<2> op{n, x.data(), volume.data(), nl.offset.data(), nl.index.data(), kernel};
    const FluidView<2> view{op, kind.data(), zero.data(), zero.data(), normal.data(), depth.data(), dx};
    std::vector<unsigned char> in(n, 2);
    parallel_for(Exec{}, n, StructureContact<2>{view, in.data(), distance.data()});
    return in;
  }
};

}  // namespace

// Each fluid point is judged by where it lies against the block's faces (the surface lies dx/2
// beyond the outer particles): inside when it has crossed a face, outside otherwise.
TEST(StructureContact, InsideMeansBehindTheSurfaceOfTheBody) {
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
