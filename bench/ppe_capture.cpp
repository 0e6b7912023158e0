// Captures the pressure Poisson system of a real case (docs/SOLVERS.md, "Captured PPEs"): loads the
// case with the --set overrides, runs STEPS - 1 ISPH steps, assembles the next step's PPE and writes
// it to FILE with its right-hand side, the solve's start (the last pressure) and each row's particle
// kind and surface class, so that solvers can be compared on the matrix the time loop solves
// (isph_ppe_bench --matrix FILE).
//
//   isph_ppe_capture CASE --out FILE [--steps N] [--set key=value]...
//
// The file's layout: bench/captured_ppe.hpp.
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/captured_ppe.hpp"
#include "io/case_loader.hpp"
#include "sim/isph.hpp"
#include "sim/phase_timer.hpp"
#include "sim/scene.hpp"

using namespace isph;

namespace {

template <int D>
void capture(const CaseSpec& spec, int steps, const std::string& path) {
  Scene<D> scene = build_scene<D>(spec);
  IsphSolver<D> solver(std::move(scene.fluid));
  PhaseTimer timer;
  for (int s = 1; s < steps; ++s) {
    const FluidStepReport r = solver.step(solver.time_step(), timer);
    std::fprintf(stderr, "step %d: %lld iterations (%s)%s\n", s, static_cast<long long>(r.ppe_iterations),
                 r.ppe_solver.c_str(), r.ppe_failed ? ", failed" : "");
    if (r.ppe_failed) throw std::runtime_error("the PPE of step " + std::to_string(s) + " was not solved");
  }
  solver.begin_step(solver.time_step(), timer);
  const CsrMatrix& A = solver.ppe_matrix();
  const auto& ps = solver.particles();
  const Index rows = A.rows;
  std::vector<std::uint8_t> kind(rows), cls(rows);
  for (Index a = 0; a < rows; ++a) {
    kind[a] = static_cast<std::uint8_t>(ps.kind[a]);
    cls[a] = static_cast<std::uint8_t>(solver.surface_class()[a]);
  }
  bench::write_captured_ppe(path, D, A, solver.ppe_rhs(), {ps.pressure.data(), ps.pressure.size()}, kind, cls);
  std::fprintf(stderr, "%s: %lld rows, %lld nonzeros (%d-D, step %d)\n", path.c_str(), static_cast<long long>(rows),
               static_cast<long long>(A.row_offset[rows]), D, steps);
}

}  // namespace

int main(int argc, char** argv) {
  std::string case_path, out_path;
  std::vector<std::string> overrides;
  int steps = 3;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if ((arg == "--out" || arg == "--set" || arg == "--steps") && a + 1 < argc) {
      const std::string value = argv[++a];
      if (arg == "--out")
        out_path = value;
      else if (arg == "--set")
        overrides.push_back(value);
      else
        steps = std::stoi(value);
    } else if (arg.rfind("--", 0) != 0 && case_path.empty()) {
      case_path = arg;
    } else {
      std::fprintf(stderr, "isph_ppe_capture: unknown argument '%s'\n", arg.c_str());
      return 2;
    }
  }
  if (case_path.empty() || out_path.empty() || steps < 1) {
    std::fprintf(stderr, "usage: isph_ppe_capture CASE --out FILE [--steps N >= 1] [--set key=value]...\n");
    return 2;
  }
  try {
    const CaseSpec spec = load_case(case_path, overrides);
    if (spec.dimension == 3)
      capture<3>(spec, steps, out_path);
    else
      capture<2>(spec, steps, out_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "isph_ppe_capture: %s\n", e.what());
    return 1;
  }
  return 0;
}
