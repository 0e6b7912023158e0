#include "sim/open_boundary.hpp"

#include <cmath>

namespace isph {

template <int D>
Real OpenZone<D>::speed(const Vec<D>& x, Real t) const {
  constexpr Real pi = 3.14159265358979323846;
  const Real ramp = ramp_time > 0 && t < ramp_time ? 0.5 * (1 - std::cos(pi * t / ramp_time)) : 1;
  return scale * ramp * velocity(x[0], x[1], D == 3 ? x[D - 1] : 0.0, t);
}

template <int D>
std::vector<OpenZone<D>> open_zones(const CaseSpec& spec, Real support) {
  std::vector<OpenZone<D>> zones;
  for (const OpenBoundarySpec& o : spec.open_boundaries) {
    OpenZone<D> z;
    z.name = o.name;
    z.outlet = o.type == OpenBoundaryType::outlet;
    z.point = to_vec<D>(o.point);
    z.normal = to_vec<D>(o.normal);
    z.normal = (1 / std::sqrt(norm2(z.normal))) * z.normal;
    const int layers = o.layers > 0 ? o.layers : static_cast<int>(std::ceil(support / spec.dx - 1e-9)) + 1;
    z.thickness = layers * spec.dx;
    if (!z.outlet) z.velocity = Expression::parse(o.velocity);
    z.ramp_time = o.ramp_time;
    z.pressure = o.pressure;
    zones.push_back(z);
  }
  return zones;
}

template struct OpenZone<2>;
template struct OpenZone<3>;
template std::vector<OpenZone<2>> open_zones<2>(const CaseSpec&, Real);
template std::vector<OpenZone<3>> open_zones<3>(const CaseSpec&, Real);

}  // namespace isph
