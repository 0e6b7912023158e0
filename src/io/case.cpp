#include "io/case.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace isph {

namespace {

// Points exactly on a face (lattice points computed as origin + (i + offset) dx) carry round-off
// relative to the coordinates' magnitude, so faces are widened by this fraction of that magnitude.
constexpr double kRelativeTolerance = 1e-12;

bool box_contains(const Shape& s, const std::array<double, 3>& p, int dimension) {
  for (int k = 0; k < dimension; ++k) {
    const double tol = kRelativeTolerance * std::max(std::abs(s.min[k]), std::abs(s.max[k]));
    if (p[k] < s.min[k] - tol || p[k] > s.max[k] + tol) return false;
  }
  return true;
}

bool ball_contains(const Shape& s, const std::array<double, 3>& p, int dimension) {
  double scale = s.radius;
  double distance2 = 0.0;
  for (int k = 0; k < dimension; ++k) {
    scale = std::max(scale, std::abs(s.center[k]));
    distance2 += (p[k] - s.center[k]) * (p[k] - s.center[k]);
  }
  const double reach = s.radius + kRelativeTolerance * scale;
  return distance2 <= reach * reach;
}

// A V of two panels rising from the keel at the deadrise angle: |x - apex_x| <= half_breadth and the
// point lies between a panel's outer face, y = apex_y + |x - apex_x| tan(deadrise), and its inner face a
// vertical thickness / cos(deadrise) above it.
bool wedge_contains(const Shape& s, const std::array<double, 3>& p) {
  const double scale = std::max({std::abs(s.apex[0]), std::abs(s.apex[1]), s.half_breadth});
  const double tol = kRelativeTolerance * scale;
  const double across = std::abs(p[0] - s.apex[0]);
  const double above = p[1] - s.apex[1] - across * s.slope();
  return across <= s.half_breadth + tol && above >= -tol && above <= s.vertical_thickness() + tol;
}

}  // namespace

double Shape::vertical_thickness() const { return thickness / std::cos(deadrise * std::numbers::pi / 180.0); }
double Shape::slope() const { return std::tan(deadrise * std::numbers::pi / 180.0); }

// Only the first `dimension` components count.
bool Shape::contains(const std::array<double, 3>& p, int dimension) const {
  if (type == ShapeType::wedge) return wedge_contains(*this, p);
  return is_ball(type) ? ball_contains(*this, p, dimension) : box_contains(*this, p, dimension);
}

}  // namespace isph
