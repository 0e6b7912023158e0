#pragma once
// The energy books of a run (docs/RELIABILITY.md, "Energy books"): energy.csv's total, the mechanical
// energy of fluid and structure less the work the moving walls, clamps and loads did on them, may only
// fall (viscosity, shifting's small errors and the solvers' dissipation take energy out). A run whose
// total rises above its first value by more than kCreationBound times the case's energy scale has
// created energy from nothing: it has diverged, whatever its other checks say.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>

#include "core/types.hpp"

namespace isph {

// The energy a case holds that motion can release, against the gravity g: the potential energy of
// particles of masses m at x above the lowest of them, sum_a m_a (-g.x_a) - (sum_a m_a) min_b (-g.x_b).
template <int D, typename Mass>
Real releasable_potential_energy(std::span<const Vec<D>> x, Mass&& mass, const Vec<D>& g) {
  Real total = 0, total_mass = 0, lowest = 0;
  bool any = false;
  for (std::size_t a = 0; a < x.size(); ++a) {
    const Real m = mass(a);
    if (m <= 0) continue;
    const Real height_energy = -dot(g, x[a]);  // per unit mass
    lowest = any ? std::min(lowest, height_energy) : height_energy;
    any = true;
    total += m * height_energy;
    total_mass += m;
  }
  return any ? total - total_mass * lowest : 0;
}

class EnergyBooks {
 public:
  // The fraction of the case's energy scale a run may create before it is stopped. The healthy runs
  // measured stay below 0.09 (0.070 on the dam-break stability map; 0.086 on the shipped dam break
  // before its burst); the runs known to diverge pass it on their way to 10^3-10^7 (docs/RELIABILITY.md).
  static constexpr Real kCreationBound = 0.25;

  EnergyBooks() = default;
  // Opens the books at the run's start: its total energy, and the energy it holds that motion can
  // release (releasable potential, kinetic and strain energy).
  EnergyBooks(Real initial_total, Real initial_energy)
      : initial_total_(initial_total), initial_energy_(initial_energy) {}
  // A restarted run's books, continued from its snapshot's attributes (the peak so far included, so
  // that summary.json reports the whole run's).
  static EnergyBooks continued(Real initial_total, Real initial_energy, Real largest_work, Real peak_created) {
    EnergyBooks books(initial_total, initial_energy);
    books.largest_work_ = largest_work;
    books.peak_created_ = peak_created;
    return books;
  }

  // The scale against which created energy is measured: the energy the case started with, and the
  // largest work its moving boundaries have done so far, either way.
  Real scale() const { return initial_energy_ + largest_work_; }
  // Energy created so far, as a fraction of the scale (negative where energy was lost).
  Real created_fraction(Real total) const { return scale() > 0 ? (total - initial_total_) / scale() : 0; }

  // Posts a row of energy.csv (its total and its boundary work); returns the reason the run must stop
  // when the books no longer balance.
  std::optional<std::string> post(Real t, Real total, Real boundary_work) {
    largest_work_ = std::max(largest_work_, std::fabs(boundary_work));
    const Real created = created_fraction(total);
    if (!(created <= kCreationBound) || !std::isfinite(total)) {  // a NaN total fails too
      char buf[320];
      std::snprintf(
          buf, sizeof buf,
          "energy created from nothing at t = %.6g s: the total energy (energy.csv) rose by %.3g J, %.3g times "
          "the case's energy scale %.3g J, beyond the bound %.2g",
          t, total - initial_total_, created, scale(), kCreationBound);
      return std::string(buf);
    }
    peak_created_ = std::max(peak_created_, created);
    return std::nullopt;
  }
  Real peak_created_fraction() const { return peak_created_; }
  Real initial_total() const { return initial_total_; }
  Real initial_energy() const { return initial_energy_; }
  Real largest_work() const { return largest_work_; }

 private:
  Real initial_total_ = 0;
  Real initial_energy_ = 0;
  Real largest_work_ = 0;
  Real peak_created_ = 0;
};

}  // namespace isph
