#include "geometry/lattice.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace isph {

namespace {

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

// A 2D circle of radius R on rings at r_k = R - (k + 1/2) s, each holding n_k = round(2 pi r_k / s)
// particles (at least one) at angles 2 pi (j + k/2) / n_k: alternate rings are turned by half a pitch.
// Each particle stands for s times its ring's pitch 2 pi r_k / n_k, within 0.5 / n_k of s^2.
template <int D>
std::vector<Vec<D>> fill_rings(const Shape& circle, Real s) {
  std::vector<Vec<D>> points;
  constexpr Real two_pi = 2 * std::numbers::pi;
  for (int k = 0; circle.radius - (k + 0.5) * s > 0; ++k) {
    const Real r = circle.radius - (k + 0.5) * s;
    const int n = std::max(1, static_cast<int>(std::lround(two_pi * r / s)));
    for (int j = 0; j < n; ++j) {
      const Real angle = two_pi * (j + 0.5 * (k % 2)) / n;
      Vec<D> p = Vec<D>::zero();
      p[0] = circle.center[0] + r * std::cos(angle);
      p[1] = circle.center[1] + r * std::sin(angle);
      points.push_back(p);
    }
  }
  return points;
}

}  // namespace

template <int D>
std::vector<Vec<D>> fill_lattice(const Shape& shape, const std::array<double, 3>& origin,
                                 const std::array<double, 3>& offset, Real s) {
  Vec<D> lo, hi;
  shape_bounds<D>(shape, lo, hi);
  int first[D], count[D];
  for (int d = 0; d < D; ++d) {
    first[d] = static_cast<int>(std::floor((lo[d] - origin[d]) / s)) - 1;
    count[d] = static_cast<int>(std::ceil((hi[d] - lo[d]) / s)) + 3;
  }
  std::vector<Vec<D>> points;
  int idx[D] = {};
  while (true) {
    Vec<D> p;
    for (int d = 0; d < D; ++d) p[d] = origin[d] + (first[d] + idx[d] + offset[d]) * s;
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

template <int D>
std::vector<Vec<D>> body_particles(const BodySpec& body, Real s) {
  if (body.shape.type == ShapeType::wedge) return fill_wedge<D>(body.shape, s);
  if (body.lattice == LatticeType::rings) return fill_rings<D>(body.shape, s);
  return fill_lattice<D>(body.shape, body.lattice_origin, body.lattice_offset, s);
}

template <int D>
Real cell_volume(const Shape& shape, Real s) {
  if (shape.type == ShapeType::wedge) return s * wedge_lattice(shape, s).pitch;
  return D == 2 ? s * s : s * s * s;
}

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

#define ISPH_LATTICE(D)                                                                    \
  template std::vector<Vec<D>> fill_lattice<D>(const Shape&, const std::array<double, 3>&, \
                                               const std::array<double, 3>&, Real);        \
  template std::vector<Vec<D>> body_particles<D>(const BodySpec&, Real);                   \
  template Real cell_volume<D>(const Shape&, Real);
ISPH_LATTICE(2)
ISPH_LATTICE(3)
#undef ISPH_LATTICE

}  // namespace isph
