#include "io/case.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace

// Only the first `dimension` components count.
bool Shape::contains(const std::array<double, 3>& p, int dimension) const {
  return is_ball(type) ? ball_contains(*this, p, dimension) : box_contains(*this, p, dimension);
}

}  // namespace isph
