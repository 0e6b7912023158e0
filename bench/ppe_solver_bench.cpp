// PPE solver benchmark: every available backend / method / preconditioner on a manufactured PPE-like
// system, at the given numbers of unknowns. Prints a markdown table (docs/SOLVERS.md).
//
//   build/isph_ppe_bench [--stencil 5|9|21] [--tol 1e-8] [--max-iterations 1000] [--skip-over 300]
//                        [--only SUBSTRING] [--verbose] [SIZE...]   (default sizes: 1e4 1e5 1e6)
//
// The system: an n x n grid (n = round(sqrt(SIZE))), a non-symmetric convection-diffusion M-matrix with
// the given stencil (21 points, the default, is about the 20-30 neighbours of a 2D SPH particle):
// a_ij = -w(r_ij) (1 + 0.6 cos theta_ij) for the neighbours inside the grid, with per-entry +-20 % jitter,
// a_ii = sum |a_ij| (row sum zero, Neumann-like at the walls); identity rows on the top row(s) (the free
// surface) and on every 97th row (splashed particles); b = A x*.
// A combination whose predicted time (from the previous size, scaled by size^1.5) exceeds --skip-over
// seconds is skipped. Times are wall seconds of the whole solve() call: copies, set-up and iterations.
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "poisson/linear_solver.hpp"
#include "poisson/manufactured_system.hpp"

using namespace isph;

namespace {

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "isph_ppe_bench: %s\nusage: isph_ppe_bench [--stencil 5|9|21] [--tol T] [--max-iterations N] "
               "[--skip-over SECONDS] [--only SUBSTRING] [--verbose] [SIZE...]\n",
               why);
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  int stencil = 21, max_iterations = 1000;
  double tol = 1e-8, skip_over = 300;
  std::string only;
  bool verbose = false;
  std::vector<double> sizes;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto value = [&]() -> std::string {
      if (a + 1 >= argc) usage(("missing value after " + arg).c_str());
      return argv[++a];
    };
    try {
      if (arg == "--stencil") stencil = std::stoi(value());
      else if (arg == "--tol") tol = std::stod(value());
      else if (arg == "--max-iterations") max_iterations = std::stoi(value());
      else if (arg == "--skip-over") skip_over = std::stod(value());
      else if (arg == "--only") only = value();
      else if (arg == "--verbose") verbose = true;
      else if (arg == "-h" || arg == "--help") usage("help");
      else sizes.push_back(std::stod(arg));
    } catch (const std::logic_error&) {
      usage(("bad value for " + arg).c_str());
    }
  }
  if (stencil != 5 && stencil != 9 && stencil != 21) usage("--stencil must be 5, 9 or 21");
  if (sizes.empty()) sizes = {1e4, 1e5, 1e6};

  std::vector<SolverSettings> combos;
  for (const char* backend : {"eigen", "hypre"}) {
    if (std::string(backend) == "hypre" && !hypre_available()) continue;
    for (const char* method : {"bicgstab", "gmres"})
      for (const char* pre : std::string(backend) == "eigen" ? std::vector<const char*>{"jacobi", "ilu", "none"}
                                                             : std::vector<const char*>{"boomeramg", "jacobi", "none"}) {
        SolverSettings s;
        s.backend = backend;
        s.method = method;
        s.preconditioner = pre;
        s.tolerance = tol;
        s.max_iterations = max_iterations;
        if (only.empty() || make_linear_solver(s)->name().find(only) != std::string::npos) combos.push_back(s);
      }
  }

  std::printf("<!-- isph_ppe_bench: %s, %d OpenMP threads, %d-point stencil, tolerance %.0e, max %d iterations -->\n",
              cpu_model().c_str(), omp_get_max_threads(), stencil, tol, max_iterations);
  std::printf("| unknowns | nonzeros | solver | setup+solve [s] | iterations | rel. residual | error vs x* | converged |\n");
  std::printf("|---:|---:|---|---:|---:|---:|---:|---|\n");
  std::fflush(stdout);

  std::map<std::string, std::pair<double, double>> last;  // solver name -> (unknowns, seconds)
  for (double size : sizes) {
    const int n = std::max(3, static_cast<int>(std::lround(std::sqrt(size))));
    const ManufacturedSystem p = manufactured_ppe_system(n, stencil);
    const double N = p.A.rows;
    for (const auto& s : combos) {
      auto solver = make_linear_solver(s);
      const std::string name = solver->name();
      if (auto it = last.find(name); it != last.end()) {
        const double predicted = it->second.second * std::pow(N / it->second.first, 1.5);
        if (predicted > skip_over) {
          std::printf("| %d | %zu | %s | skipped (predicted %.0f s) | | | | |\n", p.A.rows, p.A.col.size(), name.c_str(),
                      predicted);
          std::fflush(stdout);
          continue;
        }
      }
      std::vector<double> x(p.b.size(), 0.0);
      const SolveReport r = solver->solve(p.A, p.b, x);
      last[name] = {N, r.seconds};
      std::printf("| %d | %zu | %s | %.3f | %d | %.2e | %.2e | %s |\n", p.A.rows, p.A.col.size(), name.c_str(),
                  r.seconds, r.iterations, r.relative_residual, relative_difference(x, p.x_star),
                  r.converged ? "yes" : "no");
      if (verbose) std::printf("<!-- %s: %s -->\n", name.c_str(), r.message.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}
