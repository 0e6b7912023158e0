// Structure substep benchmark: the cost of one RK4 step of a TLSPH block on the host (all OpenMP
// threads) and, when a device is visible, on the GPU with its launches one by one and replayed as a
// CUDA graph (structure/tlsph.hpp). Small structures substepped many times per fluid step are
// launch-bound on a GPU; this shows from which size the device pays and what the graph saves.
// Prints a markdown table (docs/PERFORMANCE.md).
//
//   build/isph_substep_bench [--steps S] [PARTICLES...]   (default: 540 5e3 5e4 5e5 2e6)
//
// The block: 12 rows of particles at dx = 10 mm (columns = PARTICLES / 12), the first three columns
// clamped, an aluminium-like material, hourglass control on (three neighbour loops per evaluation),
// a small bending velocity field. Each size runs S steps (default 200, fewer for large blocks: about
// 2e7 particle-steps in all, at least 10 steps) after 5 warm-up steps; the device rows also give the largest
// difference of the positions from the host's after the same steps.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/device_memory.hpp"
#include "structure/tlsph.hpp"

using namespace isph;

namespace {

TlsphSetup<2> block(double particles) {
  const int rows = 12;
  const int columns = std::max(4, static_cast<int>(std::lround(particles / rows)));
  const Real dx = 0.01, length = columns * dx;
  TlsphSetup<2> s;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < rows; ++j) {
      const Vec<2> X{{(i + 0.5) * dx, (j + 0.5) * dx}};
      s.X.push_back(X);
      s.v.push_back({{0.0, 0.5 * std::sin(3.14159 * X[0] / length)}});
      s.volume.push_back(dx * dx);
      s.material.push_back(0);
      s.body.push_back(0);
      s.fixed.push_back(i < 3);
    }
  const Real E = 6.8e10, nu = 0.34, rho = 2700;
  const Real mu = E / (2 * (1 + nu)), lambda_plane_stress = E * nu / (1 - nu * nu);
  s.materials.push_back({rho, lambda_plane_stress, mu, E});
  s.kernel = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2 * dx);
  s.hourglass = 0.5;
  s.gravity = {{0.0, -9.81}};
  return s;
}

struct Timing {
  double particles = 0, pairs = 0;
  double seconds_per_step = 0;
  std::vector<Vec<2>> x;
};

Timing run(const TlsphSetup<2>& setup, Exec exec, bool graphs, int steps) {
  TlsphSolver<2> solver(setup, exec);
  solver.use_graphs(graphs);
  const Real dt = solver.stable_dt(0.5);
  int k = 0;
  for (; k < 5; ++k) solver.step(k * dt, dt);  // warm-up (module load, graph recording)
  const auto start = std::chrono::steady_clock::now();
  for (; k < 5 + steps; ++k) solver.step(k * dt, dt);
  Timing t;
  t.particles = solver.size();
  t.pairs = solver.pairs();
  t.seconds_per_step = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / steps;
  t.x.assign(solver.position().begin(), solver.position().end());
  return t;
}

double largest_difference(const std::vector<Vec<2>>& a, const std::vector<Vec<2>>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::sqrt(norm2(a[i] - b[i])));
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  int fixed_steps = 0;
  std::vector<double> sizes;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--steps" && a + 1 < argc) fixed_steps = std::max(1, std::atoi(argv[++a]));
    else if (arg == "-h" || arg == "--help") {
      std::printf("usage: isph_substep_bench [--steps S] [PARTICLES...]\n");
      return 0;
    } else sizes.push_back(std::atof(arg.c_str()));
  }
  if (sizes.empty()) sizes = {540, 5e3, 5e4, 5e5, 2e6};
  const bool gpu = cuda_devices() > 0;
  std::printf("<!-- isph_substep_bench: %d OpenMP threads, %s; RK4 with hourglass control, 12 evaluations of "
              "three neighbour loops per step -->\n",
              omp_get_max_threads(), gpu ? "CUDA device visible" : "no CUDA device");
  std::printf("| particles | pairs | device | steps | time per RK4 step [us] | particle-steps/s | pair evaluations/s | "
              "largest |x - x_host| [m] |\n");
  std::printf("|---:|---:|---|---:|---:|---:|---:|---:|\n");
  for (double size : sizes) {
    const TlsphSetup<2> setup = block(size);
    const int steps = fixed_steps > 0 ? fixed_steps : std::clamp(static_cast<int>(2e7 / setup.X.size()), 10, 200);
    const auto row = [&](const char* device, const Timing& t, const std::string& difference) {
      // four evaluations per RK4 step, three neighbour loops each with hourglass control
      std::printf("| %.0f | %.0f | %s | %d | %.1f | %.3e | %.3e | %s |\n", t.particles, t.pairs, device, steps,
                  1e6 * t.seconds_per_step, t.particles / t.seconds_per_step, 12 * t.pairs / t.seconds_per_step,
                  difference.c_str());
      std::fflush(stdout);
    };
    const Timing host = run(setup, Exec{}, false, steps);
    row("cpu", host, "");
    if (gpu) {
      for (bool graphs : {false, true}) {
        const Timing device = run(setup, Exec{Device::cuda}, graphs, steps);
        char difference[32];
        std::snprintf(difference, sizeof difference, "%.1e", largest_difference(device.x, host.x));
        row(graphs ? "cuda, graph" : "cuda, launches", device, difference);
      }
    }
  }
  return 0;
}
