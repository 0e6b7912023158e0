#pragma once
// Particle generation: a body's shape filled on its lattice (io/case.hpp Shape, BodySpec), the volume
// each particle stands for, and the shapes the scene derives from a case's (a load region grown by half
// a spacing). The scene (sim/scene.cpp) assembles the particles of every body from these.
#include <vector>

#include "core/types.hpp"
#include "io/case.hpp"

namespace isph {

// Bounding box of a shape in the first D components.
template <int D>
void shape_bounds(const Shape& s, Vec<D>& lo, Vec<D>& hi) {
  const auto [low, high] = s.bounding_box(D);
  lo = to_vec<D>(low), hi = to_vec<D>(high);
}

// Lattice points origin + (i + offset) s inside the shape.
template <int D>
std::vector<Vec<D>> fill_lattice(const Shape& shape, const std::array<double, 3>& origin,
                                 const std::array<double, 3>& offset, Real s);
// A body's particles at spacing s: its shape filled on its lattice, a wedge on its own (docs/CASES.md,
// shapes).
template <int D>
std::vector<Vec<D>> body_particles(const BodySpec& body, Real s);
// The volume of each particle of a body of spacing s.
template <int D>
Real cell_volume(const Shape& shape, Real s);
// The shape grown by `margin` on every side (an edge load takes the particles whose lattice cell
// touches its region: centres within dx/2 of it).
Shape grown(Shape s, Real margin);

}  // namespace isph
