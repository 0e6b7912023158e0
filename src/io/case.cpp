#include "io/case.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "io/stl_mesh.hpp"

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

double dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Within the radius of the axis, and between the planes of the two ends.
bool cylinder_contains(const Shape& s, const std::array<double, 3>& p) {
  double scale = s.radius;
  for (int k = 0; k < 3; ++k) scale = std::max({scale, std::abs(s.base[k]), std::abs(s.base[k] + s.axis[k])});
  const double tol = kRelativeTolerance * scale;
  const double length = std::sqrt(dot(s.axis, s.axis));
  const std::array<double, 3> r = {p[0] - s.base[0], p[1] - s.base[1], p[2] - s.base[2]};
  const double along = dot(r, s.axis) / length;  // distance from the base's plane
  if (along < -tol || along > length + tol) return false;
  double off2 = 0.0;  // squared distance from the axis
  for (int k = 0; k < 3; ++k) {
    const double off = r[k] - along * s.axis[k] / length;
    off2 += off * off;
  }
  return off2 <= (s.radius + tol) * (s.radius + tol);
}

}  // namespace

double Shape::vertical_thickness() const { return thickness / std::cos(deadrise * std::numbers::pi / 180.0); }
double Shape::slope() const { return std::tan(deadrise * std::numbers::pi / 180.0); }

// Only the first `dimension` components count.
bool Shape::contains(const std::array<double, 3>& p, int dimension) const {
  if (type == ShapeType::wedge) return wedge_contains(*this, p);
  if (type == ShapeType::cylinder) return cylinder_contains(*this, p);
  if (type == ShapeType::stl) return mesh.mesh && mesh.mesh->inside(p);  // no mesh: its file was refused
  return is_ball(type) ? ball_contains(*this, p, dimension) : box_contains(*this, p, dimension);
}

std::pair<std::array<double, 3>, std::array<double, 3>> Shape::bounding_box(int dimension) const {
  std::array<double, 3> lo{}, hi{};
  for (int k = 0; k < dimension; ++k) {
    switch (type) {
      case ShapeType::rectangle:
      case ShapeType::box:
        lo[k] = min[k], hi[k] = max[k];
        break;
      case ShapeType::circle:
      case ShapeType::sphere:
        lo[k] = center[k] - radius, hi[k] = center[k] + radius;
        break;
      case ShapeType::wedge:  // from the keel up to the chines' inner corners
        lo[k] = k == 0 ? apex[0] - half_breadth : apex[1];
        hi[k] = k == 0 ? apex[0] + half_breadth : apex[1] + half_breadth * slope() + vertical_thickness();
        break;
      case ShapeType::cylinder: {  // each end's disc reaches radius * sin(angle between the axis and axis k)
        const double reach = radius * std::sqrt(std::max(0.0, 1.0 - axis[k] * axis[k] / dot(axis, axis)));
        lo[k] = std::min(base[k], base[k] + axis[k]) - reach;
        hi[k] = std::max(base[k], base[k] + axis[k]) + reach;
        break;
      }
      case ShapeType::stl:  // no mesh: its file was refused
        if (mesh.mesh) lo[k] = mesh.mesh->lo()[k], hi[k] = mesh.mesh->hi()[k];
        break;
    }
  }
  return {lo, hi};
}

}  // namespace isph
