#pragma once
// Open boundaries of the fluid (issue 55; docs/CASES.md `open_boundaries`, docs/VALIDATION.md sections
// 34-35): an inlet or an outlet is a plane with a unit normal n into the fluid and a buffer of
// particles behind it, a few particle spacings thick, after the buffer zones of Lastiwka, Basa &
// Quinlan (2009, Int. J. Numer. Meth. Fluids 61:709) and Tafuni et al. (2018, CMAME 342:604).
//
// The buffer particles are boundary particles of the wall kind to every stage of the step, so that the
// fluid beside the plane has a full kernel support, the viscous term sees the buffer's velocity, and
// neither shifting nor the projection moves them:
//  - an inlet's move at the prescribed velocity U(x, t) n; their PPE rows are the wall rows (Adami et al.
//    2012), the Neumann condition dp/dn = rho (g - dU/dt) · n of a prescribed velocity. One that crosses
//    the plane becomes fluid with its velocity, and a new buffer particle (a new stable id) takes its
//    place a buffer's thickness behind (x - L n);
//  - fluid that crosses an outlet's plane joins its buffer, whose particles take the velocity the fluid
//    has beside the plane, row by row (OutletVelocityPass: zero gradient along n); the buffer's PPE rows
//    are Dirichlet, p = the outlet's pressure; a particle is removed at the far side.
// The exchange runs after each fluid step (ParticleSet::exchange_open_boundaries), on the host, in
// particle order, so that runs repeat exactly; snapshots carry each particle's boundary and the next
// stable id, so that a restart recreates the particles an inlet made (ParticleSet::restore).
#include <string>
#include <vector>

#include "core/expression.hpp"
#include "core/types.hpp"
#include "io/case.hpp"

namespace isph {

template <int D>
struct OpenZone {
  std::string name;
  bool outlet = false;
  Vec<D> point = Vec<D>::zero();   // on the plane
  Vec<D> normal = Vec<D>::zero();  // unit, into the fluid
  Real thickness = 0;              // of the buffer, layers * dx
  Expression velocity;             // inlet: U(x, y, z, t) before scale and ramp
  Real scale = 1;                  // inlet: flow_rate over the flow of `velocity`
  Real ramp_time = 0;              // inlet
  Real pressure = 0;               // outlet

  // How far x lies behind the plane (> 0 in the buffer's direction).
  Real depth(const Vec<D>& x) const { return -dot(x - point, normal); }
  // The inlet's speed along n at x and t: scale * ramp(t) * U(x, t), ramp = (1 - cos(pi t / T)) / 2 until T.
  Real speed(const Vec<D>& x, Real t) const;
  // Whether the inflow no longer changes in time at t (a profile without t, past its ramp).
  bool steady_at(Real t) const { return !velocity.uses_time() && t >= ramp_time; }
};

// Flows through one open boundary over a run (a restart counts anew), for summary.json.
struct OpenZoneFlow {
  long long crossed = 0;       // particles that crossed the plane (into the fluid at an inlet, out at an outlet)
  Real volume_crossed = 0;     // their volume
  Real volume_prescribed = 0;  // inlet: the time integral of the buffer's flow, sum_buffer V u·n / L
  long long removed = 0;       // outlet: particles removed at the buffer's far side
};

// The zones of a case: the plane's normal normalised, the buffer thickness (layers * dx, by default
// the kernel's support plus one spacing) and the compiled profile.
template <int D>
std::vector<OpenZone<D>> open_zones(const CaseSpec& spec, Real support);

}  // namespace isph
