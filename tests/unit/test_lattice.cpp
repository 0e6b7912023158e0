// Particle generation (src/geometry/lattice.hpp): a shape filled on its lattice holds the particles
// whose cells tile it, the particles' volumes add up to the shape's, and a load region grows by the
// margin asked.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/lattice.hpp"

using namespace isph;

namespace {

Shape rectangle(double x0, double y0, double x1, double y1) {
  Shape s;
  s.type = ShapeType::rectangle;
  s.min = {x0, y0, 0};
  s.max = {x1, y1, 0};
  return s;
}

}  // namespace

// Cell-centred (offset 1/2) on a lattice through the origin, a 1 m x 0.5 m rectangle at s = 0.1 m holds
// 10 x 5 particles, the first at (0.05, 0.05): their cells tile it exactly.
TEST(Lattice, CellCentredRectangleHoldsTheParticlesWhoseCellsTileIt) {
  const auto points = fill_lattice<2>(rectangle(0, 0, 1, 0.5), {0, 0, 0}, {0.5, 0.5, 0}, 0.1);
  ASSERT_EQ(points.size(), 50u);
  double lowest = 1e9, area = 0;
  for (const auto& p : points) {
    EXPECT_GT(p[0], 0);
    EXPECT_LT(p[0], 1);
    EXPECT_GT(p[1], 0);
    EXPECT_LT(p[1], 0.5);
    lowest = std::min(lowest, p[0] + p[1]);
    area += cell_volume<2>(rectangle(0, 0, 1, 0.5), 0.1);
  }
  EXPECT_NEAR(lowest, 0.1, 1e-12);
  EXPECT_NEAR(area, 0.5, 1e-12);
}

// In 3D a box 0.2 m on each side at s = 0.05 m: 4 x 4 x 4 particles of 1.25e-4 m^3, the box's volume.
TEST(Lattice, BoxVolumeIsTheSumOfItsCells) {
  Shape box;
  box.type = ShapeType::box;
  box.min = {0, 0, 0};
  box.max = {0.2, 0.2, 0.2};
  BodySpec body;
  body.shape = box;
  body.lattice_offset = {0.5, 0.5, 0.5};
  const auto points = body_particles<3>(body, 0.05);
  ASSERT_EQ(points.size(), 64u);
  EXPECT_NEAR(points.size() * cell_volume<3>(box, 0.05), 0.008, 1e-15);
}

// A wedge (10 deg deadrise, panels 0.04 m thick, 0.6 m half breadth) on its own sheared lattice: 60
// columns a side at s = 0.01 m, each holding round(t / (s cos b)) = 4 particles, and the particles' cells
// make the two panels' area, 2 x 0.6 m x t / cos b (a shear keeps areas).
TEST(Lattice, WedgeCellsMakeThePanelsArea) {
  Shape wedge;
  wedge.type = ShapeType::wedge;
  wedge.apex = {1.5, 1.0, 0};
  wedge.half_breadth = 0.6;
  wedge.deadrise = 10;
  wedge.thickness = 0.04;
  BodySpec body;
  body.shape = wedge;
  const auto points = body_particles<2>(body, 0.01);
  ASSERT_EQ(points.size(), 2u * 60u * 4u);
  const double vertical = 0.04 / std::cos(10 * M_PI / 180);
  EXPECT_NEAR(points.size() * cell_volume<2>(wedge, 0.01), 2 * 0.6 * vertical, 1e-12);
  for (const auto& p : points) EXPECT_TRUE(wedge.contains({p[0], p[1], 0}, 2)) << p[0] << " " << p[1];
}

// A circle of radius 0.05 m on rings at s = 0.01 m (Turek & Hron's cylinder at D/10): five rings at
// r = 0.045, 0.035, ..., 0.005 holding round(2 pi r / s) = 28, 22, 16, 9, 3 particles; the outer ring s/2
// inside the circle, every particle s/2 or more inside it, and the cells' area, 78 s^2, pi R^2 to 0.7 %.
TEST(Lattice, RingsFillACircleWithASmoothSurface) {
  Shape circle;
  circle.type = ShapeType::circle;
  circle.center = {0.2, 0.2, 0};
  circle.radius = 0.05;
  BodySpec body;
  body.shape = circle;
  body.lattice = LatticeType::rings;
  const double s = 0.01;
  const auto points = body_particles<2>(body, s);
  ASSERT_EQ(points.size(), 78u);
  int outer = 0;
  double nearest = 1e9;
  for (std::size_t a = 0; a < points.size(); ++a) {
    const double r = std::hypot(points[a][0] - 0.2, points[a][1] - 0.2);
    EXPECT_LE(r, 0.045 + 1e-12);
    if (std::abs(r - 0.045) < 1e-12) ++outer;
    for (std::size_t b = a + 1; b < points.size(); ++b)
      nearest = std::min(nearest, std::hypot(points[a][0] - points[b][0], points[a][1] - points[b][1]));
  }
  EXPECT_EQ(outer, 28);
  EXPECT_NEAR(points.size() * cell_volume<2>(circle, s), M_PI * 0.05 * 0.05, 0.007 * M_PI * 0.05 * 0.05);
  EXPECT_GT(nearest, 0.85 * s);  // the innermost ring's three, 0.87 s apart; every other pair s or more
}

// An edge load's region grows by half a spacing on every side, a cylinder's at both ends.
TEST(Lattice, GrownShapeMovesEveryFaceOut) {
  const Shape g = grown(rectangle(0, 0, 1, 0.5), 0.05);
  EXPECT_DOUBLE_EQ(g.min[0], -0.05);
  EXPECT_DOUBLE_EQ(g.max[1], 0.55);
  Shape c;
  c.type = ShapeType::cylinder;
  c.base = {0, 0, 0};
  c.axis = {0, 0, 1};
  c.radius = 0.1;
  const Shape gc = grown(c, 0.05);
  EXPECT_DOUBLE_EQ(gc.radius, 0.15);
  EXPECT_DOUBLE_EQ(gc.base[2], -0.05);
  EXPECT_DOUBLE_EQ(gc.axis[2], 1.1);
}
