#pragma once
// The two time loops behind run_case (sim/run.hpp): a run with a fluid (ISPH or WCSPH, alone or
// coupled with structures: sim/run_fluid.cpp) and a structure-only run (TLSPH: sim/run_structure.cpp),
// and what they share besides the RunFrame.
#include <array>
#include <cstdio>
#include <string>

#include "sim/phase_timer.hpp"
#include "sim/run.hpp"
#include "sim/run_frame.hpp"
#include "sim/scene.hpp"

namespace isph {

template <int D>
RunResult run_fluid(const CaseSpec& spec, const RunOptions& opt, Scene<D>& scene, PhaseTimer& timer);
template <int D>
RunResult run_structure(const CaseSpec& spec, const RunOptions& opt, Scene<D>& scene, PhaseTimer& timer);

// Snapshot fields hold three components whatever the dimension (z = 0 in 2D).
template <int D>
void put_vector(SnapshotField& field, Index k, const Vec<D>& v) {
  for (int d = 0; d < D; ++d) field.data[3 * k + d] = v[d];
}

// The message for a structure particle that became non-finite or ran away.
template <int D>
std::string structure_divergence_message(const Scene<D>& scene, Index bad, Real t, long long step) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "structure particle %d (id %d) became non-finite or moved more than 10 body lengths at t = %.6g s "
                "(step %lld); try a smaller structure.courant",
                bad, scene.structure_id[bad], t, step);
  return buf;
}

}  // namespace isph
