// Captures the pressure Poisson system of a real case (docs/SOLVERS.md, "The dam-break PPE"): loads the
// case with the --set overrides, runs STEPS - 1 ISPH steps, assembles the next step's PPE and writes
// it to FILE with its right-hand side, the solve's start (the last pressure) and each row's particle
// kind and surface class, so that solvers can be compared on the matrix the time loop solves
// (isph_ppe_bench --matrix FILE).
//
//   isph_ppe_capture CASE --out FILE [--steps N] [--set key=value]...
//
// File layout (little-endian): "ISPHPPE1", int64 rows, int64 nonzeros, int64 dimension, int32 row_offset[rows + 1],
// int32 col[nonzeros], float64 val[nonzeros], float64 rhs[rows], float64 start[rows],
// uint8 kind[rows] (FluidKind), uint8 class[rows] (SurfaceClass).
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/case_loader.hpp"
#include "sim/isph.hpp"
#include "sim/phase_timer.hpp"
#include "sim/scene.hpp"

using namespace isph;

namespace {

template <class T>
void put(std::ofstream& out, const T* data, std::size_t count) {
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(sizeof(T) * count));
}

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
  const std::int64_t rows = A.rows, nonzeros = A.row_offset[A.rows], dimension = D;
  std::vector<std::uint8_t> kind(rows), cls(rows);
  for (Index a = 0; a < rows; ++a) {
    kind[a] = static_cast<std::uint8_t>(ps.kind[a]);
    cls[a] = static_cast<std::uint8_t>(solver.surface_class()[a]);
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
  out.write("ISPHPPE1", 8);
  put(out, &rows, 1);
  put(out, &nonzeros, 1);
  put(out, &dimension, 1);
  put(out, A.row_offset.data(), rows + 1);
  put(out, A.col.data(), nonzeros);
  put(out, A.val.data(), nonzeros);
  put(out, solver.ppe_rhs().data(), rows);
  put(out, ps.pressure.data(), rows);
  put(out, kind.data(), rows);
  put(out, cls.data(), rows);
  if (!out) throw std::runtime_error("writing " + path + " failed");
  std::fprintf(stderr, "%s: %lld rows, %lld nonzeros (%d-D, step %d)\n", path.c_str(), static_cast<long long>(rows),
               static_cast<long long>(nonzeros), D, steps);
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
