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

using namespace isph;

namespace {

struct Problem {
  CsrMatrix A;
  std::vector<double> x_star, b;
};

Problem manufactured(int n, int stencil) {
  const int r2max = stencil == 5 ? 1 : stencil == 9 ? 2 : 5;
  const int ring = stencil == 21 ? 2 : 1;
  std::vector<std::pair<int, int>> offsets;
  for (int dj = -2; dj <= 2; ++dj)
    for (int di = -2; di <= 2; ++di)
      if ((di || dj) && di * di + dj * dj <= r2max) offsets.emplace_back(di, dj);

  Problem p;
  const int N = n * n;
  p.A.rows = N;
  p.A.row_offset.resize(N + 1);
  p.A.row_offset[0] = 0;
  p.A.col.reserve(static_cast<std::size_t>(N) * (offsets.size() + 1));
  p.A.val.reserve(p.A.col.capacity());
  p.x_star.resize(N);
  const double h = 1.0 / (n - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i * h, y = j * h;
      p.x_star[j * n + i] = std::sin(std::numbers::pi * x) * std::cos(2 * std::numbers::pi * y) + x * y + 1.0;
    }
  const double ex = 1.0 / std::sqrt(1.25), ey = 0.5 / std::sqrt(1.25);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int row = j * n + i;
      if (j >= n - ring || row % 97 == 0) {
        p.A.col.push_back(row);
        p.A.val.push_back(1.0);
      } else {
        const std::size_t at = p.A.col.size();
        p.A.col.push_back(row);
        p.A.val.push_back(0.0);
        double diag = 0;
        for (const auto& [di, dj] : offsets) {
          if (i + di < 0 || i + di >= n || j + dj < 0 || j + dj >= n) continue;
          const double r2 = di * di + dj * dj;
          const double cos_theta = (di * ex + dj * ey) / std::sqrt(r2);
          const double jitter = 1.0 + 0.2 * std::sin(12.9898 * row + 78.233 * (5 * dj + di));
          const double a = -(1.0 / r2) * (1.0 + 0.6 * cos_theta) * jitter;
          p.A.col.push_back((j + dj) * n + (i + di));
          p.A.val.push_back(a);
          diag -= a;
        }
        p.A.val[at] = diag;
      }
      p.A.row_offset[row + 1] = static_cast<int>(p.A.col.size());
    }
  p.b.assign(N, 0.0);
#pragma omp parallel for schedule(static)
  for (int r = 0; r < N; ++r)
    for (int k = p.A.row_offset[r]; k < p.A.row_offset[r + 1]; ++k) p.b[r] += p.A.val[k] * p.x_star[p.A.col[k]];
  return p;
}

double relative_error(const std::vector<double>& x, const std::vector<double>& ref) {
  double d = 0, s = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    d += (x[i] - ref[i]) * (x[i] - ref[i]);
    s += ref[i] * ref[i];
  }
  return std::sqrt(d / s);
}

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
    const Problem p = manufactured(n, stencil);
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
                  r.seconds, r.iterations, r.relative_residual, relative_error(x, p.x_star),
                  r.converged ? "yes" : "no");
      if (verbose) std::printf("<!-- %s: %s -->\n", name.c_str(), r.message.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}
