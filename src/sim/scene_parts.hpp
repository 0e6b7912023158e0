#pragma once
// What the scene's assembly (sim/scene.cpp) shares with its fluid part (sim/scene_fluid.cpp) and its
// wall faces (sim/scene_walls.cpp): the particle spacings of a case and the per-body steps.
#include <string>
#include <vector>

#include "core/periodic.hpp"
#include "io/case.hpp"
#include "kernels/operators.hpp"
#include "sim/scene.hpp"

namespace isph {

// The particle spacings of a case, finest first: the levels of the kernel table (kernels/operators.hpp
// KernelTable). The case's dx is the fluid's and the walls'; a structure body may be finer (its own dx,
// or the case's dx / refinement). Bodies of equal spacing share a level.
struct Resolutions {
  std::vector<Real> spacing;  // ascending: level l has the spacing spacing[l]
  Real dx = 0;
  explicit Resolutions(const CaseSpec& spec) : dx(spec.dx) {
    spacing.push_back(spec.dx);
    for (const auto& b : spec.bodies) spacing.push_back(b.spacing(spec.dx));
    std::sort(spacing.begin(), spacing.end());
    spacing.erase(std::unique(spacing.begin(), spacing.end()), spacing.end());
  }
  int levels() const { return static_cast<int>(spacing.size()); }
  int level(const BodySpec& b) const {
    return static_cast<int>(std::find(spacing.begin(), spacing.end(), b.spacing(dx)) - spacing.begin());
  }
  int fluid_level() const { return level_of(dx); }
  int level_of(Real s) const {
    return static_cast<int>(std::find(spacing.begin(), spacing.end(), s) - spacing.begin());
  }
  template <int D>
  KernelTable<D> kernels(const KernelSpec& k) const {
    KernelTable<D> table;
    table.levels = levels();
    for (int l = 0; l < levels(); ++l) table.kernel[l] = SmoothingKernel<D>::make(k.type, k.h_factor * spacing[l]);
    return table;
  }
};

// Whether q lies outside the box [lo, hi] on a non-periodic axis, the box being open against gravity
// (a tank is open at its top).
template <int D>
bool outside_open_box(const Vec<D>& q, const Vec<D>& lo, const Vec<D>& hi, const Vec<D>& gravity,
                      const Periodicity<D>& period) {
  for (int d = 0; d < D; ++d)
    if (!period.axis[d] && ((q[d] < lo[d] && !(gravity[d] > 0)) || (q[d] > hi[d] && !(gravity[d] < 0)))) return true;
  return false;
}

template <int D>
Periodicity<D> periodicity(const PeriodicSpec& p) {
  Periodicity<D> period;
  for (int d = 0; d < D; ++d) {
    period.axis[d] = p.axis(d);
    period.lo[d] = p.lo(d);
    period.length[d] = p.hi(d) - p.lo(d);
  }
  return period;
}

// The initial velocity of a particle at X (a uniform field or a beam's first bending mode).
template <int D>
Vec<D> initial_velocity(const InitialVelocitySpec& iv, const Vec<D>& X);

// Appends a fluid or wall body's lattice points to the fluid set-up.
template <int D>
void add_fluid_body(const CaseSpec& spec, std::size_t bi, const std::vector<Vec<D>>& points, int level,
                    FluidSetup<D>& f);
// Appends a structure particle of the given volume to the fluid set-up, where it acts as a moving
// boundary (coupled cases).
template <int D>
void add_structure_particle(const Vec<D>& x, const Vec<D>& v, Index structure_index, Real volume, int level,
                            std::size_t body, FluidSetup<D>& f);
// Checks the fluid set-up and completes it: material, overlaps, containment, wall geometry, the
// reference velocity of Eq. 49, the escape box and the fluid probes.
template <int D>
void finish_fluid(const CaseSpec& spec, Scene<D>& scene, FluidSetup<D>& f, const TlsphSetup<D>& structure,
                  std::vector<std::string>& problems);

// The wall faces (sim/scene_walls.cpp): each wall particle's normal and depth below the surface (exact
// for walls on rings); returns 1 for the particles the thickness check leaves out (corners, rings). Then
// the check that every wall fills the kernel support (a wall on rings by its radius).
template <int D>
std::vector<unsigned char> wall_surface_geometry(const CaseSpec& spec, FluidSetup<D>& f,
                                                 const std::vector<unsigned char>& structure_fixed,
                                                 const std::vector<Real>& spacing, Real support,
                                                 const Periodicity<D>& period, const Vec<D>& gravity);
template <int D>
void check_wall_thickness(const CaseSpec& spec, const FluidSetup<D>& f, const std::vector<unsigned char>& unchecked,
                          Real support, const Periodicity<D>& period, const std::string& file,
                          std::vector<std::string>& problems);

}  // namespace isph
