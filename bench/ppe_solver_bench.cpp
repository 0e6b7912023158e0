// PPE solver benchmark: every available backend / method / preconditioner on a manufactured PPE-like
// system, at the given numbers of unknowns. Prints a markdown table (docs/SOLVERS.md).
//
//   build/isph_ppe_bench [--stencil 5|9|21] [--tol 1e-8] [--max-iterations 1000] [--skip-over 300]
//                        [--only SUBSTRING] [--spmv-only] [--verbose] [SIZE...]   (default sizes: 1e4 1e5 1e6)
//   build/isph_ppe_bench --matrix FILE [--matrix FILE]... [--tol T] [--only SUBSTRING]
//
// With --matrix, the systems are PPEs captured from the time loop (bench/ppe_capture.cpp), each solved
// from the captured start (the last step's pressure) by every combination, three times: the table gives
// the faster of the last two solves (the first pays MPI's and hypre's start-up), its set-up (copy and
// preconditioner) and Krylov iterations separately.
//
// The system: an n x n grid (n = round(sqrt(SIZE))), a non-symmetric convection-diffusion M-matrix with
// the given stencil (21 points, the default, is about the 20-30 neighbours of a 2D SPH particle):
// a_ij = -w(r_ij) (1 + 0.6 cos theta_ij) for the neighbours inside the grid, with per-entry +-20 % jitter,
// a_ii = sum |a_ij| (row sum zero, Neumann-like at the walls); identity rows on the top row(s) (the free
// surface) and on every 97th row (splashed particles); b = A x*.
// A combination whose predicted time (from the previous size, scaled by size^1.5) exceeds --skip-over
// seconds is skipped. Times are wall seconds of the whole solve() call: copies, set-up and iterations.
// The cuda backend is included when a device is visible. A second table times the SpMV alone (the
// host's CSR product and, with a device, cuSPARSE's) against the least traffic of a CSR product
// (12 bytes per nonzero, 4 per row offset, x read and y written once) and the measured copy bandwidth.
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/captured_ppe.hpp"
#include "core/device_memory.hpp"
#include "poisson/cuda_solver.hpp"
#include "poisson/krylov.hpp"
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

constexpr int spmv_repeats = 50;

struct HostSpmv {
  std::vector<double> y;
  double seconds = 0;  // per product
};

// The native backend's product (CsrRowProduct through the launcher), timed over `repeats` products.
HostSpmv host_spmv(const CsrMatrix& A, const std::vector<double>& x, int repeats) {
  HostSpmv r;
  r.y.assign(A.rows, 0.0);
  const CsrRowProduct product{A.row_offset.data(), A.col.data(), A.val.data(), x.data(), r.y.data()};
  parallel_for(Exec{}, A.rows, product);  // warm-up
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < repeats; ++k) parallel_for(Exec{}, A.rows, product);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / repeats;
  return r;
}

// Bytes per second of memcpy of 512 MiB (read and write counted), each OpenMP thread copying its own
// slice, as the SpMV's threads read their own rows.
double host_copy_bandwidth() {
  const std::size_t bytes = std::size_t{512} << 20;
  std::vector<unsigned char> from(bytes, 1), to(bytes, 0);
  const auto copy = [&] {
#pragma omp parallel
    {
      const std::size_t threads = omp_get_num_threads(), t = omp_get_thread_num();
      const std::size_t begin = bytes * t / threads, end = bytes * (t + 1) / threads;
      std::memcpy(to.data() + begin, from.data() + begin, end - begin);
    }
  };
  copy();  // warm-up
  constexpr int copies = 4;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < copies; ++k) copy();
  return 2.0 * bytes * copies / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void bench_captured(const std::vector<std::string>& paths, const std::vector<SolverSettings>& combos) {
  std::printf(
      "| system | D | unknowns | nonzeros | solver | set-up [s] | solve [s] | total [s] | iterations | rel. residual | "
      "converged |\n");
  std::printf("|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---|\n");
  std::fflush(stdout);
  for (const std::string& path : paths) {
    const bench::CapturedPpe sys = bench::read_captured_ppe(path);
    const std::string file = path.substr(path.find_last_of('/') + 1);
    for (SolverSettings settings : combos) {
      settings.dimension = sys.dimension;
      auto solver = make_linear_solver(settings);
      SolveReport r;
      for (int pass = 0; pass < 3; ++pass) {
        std::vector<double> x = sys.start;
        const SolveReport this_pass = solver->solve(sys.A, sys.b, x);
        if (pass == 1 || (pass == 2 && this_pass.seconds < r.seconds)) r = this_pass;
      }
      std::printf("| %s | %d | %d | %zu | %s | %.3f | %.3f | %.3f | %d | %.2e | %s |\n", file.c_str(), sys.dimension,
                  sys.A.rows, sys.A.col.size(), solver->name().c_str(), r.setup_seconds, r.seconds - r.setup_seconds,
                  r.seconds, r.iterations, r.relative_residual, r.converged ? "yes" : "no");
      if (!r.converged) std::printf("<!-- %s: %s -->\n", solver->name().c_str(), r.message.c_str());
      std::fflush(stdout);
    }
  }
}

[[noreturn]] void usage(const char* why) {
  std::fprintf(
      stderr,
      "isph_ppe_bench: %s\nusage: isph_ppe_bench [--stencil 5|9|21] [--tol T] [--max-iterations N] "
      "[--skip-over SECONDS] [--only SUBSTRING] [--spmv-only] [--verbose] [SIZE...]\n"
      "       isph_ppe_bench --matrix FILE [--matrix FILE]... [--tol T] [--max-iterations N] [--only SUBSTRING]\n",
      why);
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  int stencil = 21, max_iterations = 1000;
  double tol = 1e-8, skip_over = 300;
  std::string only;
  bool verbose = false, spmv_only = false;
  std::vector<double> sizes;
  std::vector<std::string> matrices;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto value = [&]() -> std::string {
      if (a + 1 >= argc) usage(("missing value after " + arg).c_str());
      return argv[++a];
    };
    try {
      if (arg == "--stencil")
        stencil = std::stoi(value());
      else if (arg == "--tol")
        tol = std::stod(value());
      else if (arg == "--max-iterations")
        max_iterations = std::stoi(value());
      else if (arg == "--skip-over")
        skip_over = std::stod(value());
      else if (arg == "--only")
        only = value();
      else if (arg == "--verbose")
        verbose = true;
      else if (arg == "--matrix")
        matrices.push_back(value());
      else if (arg == "--spmv-only")
        spmv_only = true;
      else if (arg == "-h" || arg == "--help")
        usage("help");
      else
        sizes.push_back(std::stod(arg));
    } catch (const std::logic_error&) {
      usage(("bad value for " + arg).c_str());
    }
  }
  if (stencil != 5 && stencil != 9 && stencil != 21) usage("--stencil must be 5, 9 or 21");
  if (sizes.empty()) sizes = {1e4, 1e5, 1e6};

  const bool gpu = cuda_devices() > 0;
  std::vector<SolverSettings> combos;
  for (const auto& entry : enum_names(SolverBackend{})) {
    const SolverBackend backend = entry.value;
    if ((backend == SolverBackend::hypre && !hypre_available()) || (backend == SolverBackend::cuda && !gpu)) continue;
    for (const auto method : solver_methods(backend))
      for (const auto pre : solver_preconditioners(backend)) {
        SolverSettings s;
        s.backend = backend;
        s.method = method;
        s.preconditioner = pre;
        s.tolerance = tol;
        s.max_iterations = max_iterations;
        if (only.empty() || make_linear_solver(s)->name().find(only) != std::string::npos) combos.push_back(s);
      }
  }

  if (!matrices.empty()) {
    std::printf("<!-- isph_ppe_bench: %s, %d OpenMP threads, captured systems, tolerance %.0e, max %d iterations -->\n",
                cpu_model().c_str(), omp_get_max_threads(), tol, max_iterations);
    try {
      bench_captured(matrices, combos);
    } catch (const std::runtime_error& e) {
      usage(e.what());
    }
    return 0;
  }
  std::printf("<!-- isph_ppe_bench: %s, %d OpenMP threads, %d-point stencil, tolerance %.0e, max %d iterations -->\n",
              cpu_model().c_str(), omp_get_max_threads(), stencil, tol, max_iterations);
  if (!spmv_only) {
    std::printf(
        "| unknowns | nonzeros | solver | setup+solve [s] | iterations | rel. residual | error vs x* | converged |\n");
    std::printf("|---:|---:|---|---:|---:|---:|---:|---|\n");
  }
  std::fflush(stdout);

  std::map<std::string, std::pair<double, double>> last;  // solver name -> (unknowns, seconds)
  for (double size : spmv_only ? std::vector<double>{} : sizes) {
    const int n = std::max(3, static_cast<int>(std::lround(std::sqrt(size))));
    const ManufacturedSystem p = manufactured_ppe_system(n, stencil);
    const double N = p.A.rows;
    for (const auto& s : combos) {
      auto solver = make_linear_solver(s);
      const std::string name = solver->name();
      if (auto it = last.find(name); it != last.end()) {
        const double predicted = it->second.second * std::pow(N / it->second.first, 1.5);
        if (predicted > skip_over) {
          std::printf("| %d | %zu | %s | skipped (predicted %.0f s) | | | | |\n", p.A.rows, p.A.col.size(),
                      name.c_str(), predicted);
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

  // SpMV alone, on the same matrices: achieved bandwidth against the least traffic of a CSR product.
  std::printf(
      "%s| unknowns | nonzeros | SpMV | time per product [ms] | achieved [GB/s] | copy bandwidth [GB/s] | fraction |\n",
      spmv_only ? "" : "\n");
  std::printf("|---:|---:|---|---:|---:|---:|---:|\n");
  for (double size : sizes) {
    const int n = std::max(3, static_cast<int>(std::lround(std::sqrt(size))));
    const ManufacturedSystem p = manufactured_ppe_system(n, stencil);
    const double bytes = 12.0 * p.A.val.size() + 4.0 * (p.A.rows + 1) + 16.0 * p.A.rows;
    const auto row = [&](const char* what, double seconds, double copy) {
      std::printf("| %d | %zu | %s | %.4f | %.1f | %.1f | %.2f |\n", p.A.rows, p.A.col.size(), what, 1e3 * seconds,
                  bytes / seconds / 1e9, copy / 1e9, bytes / seconds / copy);
      std::fflush(stdout);
    };
    const HostSpmv host = host_spmv(p.A, p.x_star, spmv_repeats);
    row("host (OpenMP CSR rows)", host.seconds, host_copy_bandwidth());
    if (gpu) {
      const int chosen = vector_csr_lanes(double(p.A.val.size()) / p.A.rows);
      const struct {
        SpmvAlgorithm algorithm;
        int lanes;
      } variants[] = {{SpmvAlgorithm::reproducible, 0},
                      {SpmvAlgorithm::default_csr, 0},
                      {SpmvAlgorithm::vector_csr, 4},
                      {SpmvAlgorithm::vector_csr, 8},
                      {SpmvAlgorithm::vector_csr, 16}};
      for (const auto& v : variants) {
        const SpmvMeasurement m = measure_cuda_spmv(p.A, p.x_star, spmv_repeats, v.algorithm, v.lanes);
        if (relative_difference(m.y, host.y) > 1e-12) std::printf("<!-- device and host products differ -->\n");
        const std::string name =
            v.algorithm == SpmvAlgorithm::reproducible  ? "cuSPARSE CSR_ALG2 (reproducible; the solver's)"
            : v.algorithm == SpmvAlgorithm::default_csr ? "cuSPARSE CSR_ALG1 (default)"
                                                        : "vector CSR, " + std::to_string(v.lanes) + " lanes per row" +
                                                              (v.lanes == chosen ? " (its choice)" : "");
        row(name.c_str(), m.seconds_per_product, m.copy_bandwidth);
      }
    }
  }
  return 0;
}
