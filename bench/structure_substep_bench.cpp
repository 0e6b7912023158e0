// Structure substep benchmark: the cost of one RK4 substep of a TLSPH block under the fluid's
// interaction field, with that field's power after each substep (the coupling's work, sim/coupling.hpp),
// on the host (all OpenMP threads) and, when a device is visible, on the GPU three ways:
//   launches  the RK4 step's launches one by one, the host waiting for each substep and reading the
//             power back (step() and interaction_power() per substep, graphs off);
//   graph     the same with the RK4 step replayed as a CUDA graph (structure/tlsph.hpp): the coupled
//             step's pattern before advance();
//   queued    advance(): graph replays and power sums queued on one stream, the host waiting once for
//             all the substeps of the run (what a coupled fluid step does).
// Small structures substepped many times per fluid step are launch-bound on a GPU; this shows from
// which size the device pays and what the graph and the queue save. Prints a markdown table
// (docs/PERFORMANCE.md).
//
//   build/isph_substep_bench [--steps S] [PARTICLES...]   (default: 540 5e3 5e4 5e5 2e6)
//
// The block: 12 rows of particles at dx = 10 mm (columns = PARTICLES / 12), the first three columns
// clamped, an aluminium-like material, hourglass control on (three neighbour loops per evaluation),
// a small bending velocity field, a uniform interaction field. Each size runs S substeps (default 200,
// fewer for large blocks: about 2e7 particle-steps in all, at least 10) after 5 warm-up substeps; the
// device rows also give the largest difference of the positions and of the work from the host's.
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
  s.kernels = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2 * dx);
  s.hourglass = 0.5;
  s.gravity = {{0.0, -9.81}};
  return s;
}

enum class Mode { host, launches, graph, queued };

struct Timing {
  double particles = 0, pairs = 0;
  double seconds_per_step = 0;
  double work = 0;  // the interaction's work over the timed substeps
  std::vector<Vec<2>> x;
};

Timing run(const TlsphSetup<2>& setup, Mode mode, int steps) {
  TlsphSolver<2> solver(setup, Exec{mode == Mode::host ? Device::cpu : Device::cuda});
  solver.use_graphs(mode != Mode::launches);
  solver.set_interaction(std::vector<Vec<2>>(setup.X.size(), Vec<2>{{1.5, -4.0}}));
  const Real dt = solver.stable_dt(0.5);
  const int warm_up = 5;  // module load, graph recording
  solver.advance(0, warm_up * dt, warm_up);
  const Real t0 = warm_up * dt;
  Timing t;
  const auto start = std::chrono::steady_clock::now();
  if (mode == Mode::host || mode == Mode::queued) {
    t.work = solver.advance(t0, steps * dt, steps);
  } else {
    const Real h = steps * dt / steps;  // advance's substep, to the bit
    Real power = solver.interaction_power();
    for (int k = 0; k < steps; ++k) {
      solver.step(t0 + k * h, h);
      const Real next = solver.interaction_power();
      t.work += 0.5 * h * (power + next);
      power = next;
    }
  }
  t.seconds_per_step = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / steps;
  t.particles = solver.size();
  t.pairs = solver.pairs();
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
    if (arg == "--steps" && a + 1 < argc)
      fixed_steps = std::max(1, std::atoi(argv[++a]));
    else if (arg == "-h" || arg == "--help") {
      std::printf("usage: isph_substep_bench [--steps S] [PARTICLES...]\n");
      return 0;
    } else
      sizes.push_back(std::atof(arg.c_str()));
  }
  if (sizes.empty()) sizes = {540, 5e3, 5e4, 5e5, 2e6};
  const bool gpu = cuda_devices() > 0;
  std::printf(
      "<!-- isph_substep_bench: %d OpenMP threads, %s; RK4 with hourglass control, 12 evaluations of "
      "three neighbour loops per step -->\n",
      omp_get_max_threads(), gpu ? "CUDA device visible" : "no CUDA device");
  std::printf(
      "| particles | pairs | device | substeps | time per RK4 substep [us] | particle-steps/s | pair evaluations/s | "
      "largest |x - x_host| [m] | work vs host |\n");
  std::printf("|---:|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (double size : sizes) {
    const TlsphSetup<2> setup = block(size);
    const int steps = fixed_steps > 0 ? fixed_steps : std::clamp(static_cast<int>(2e7 / setup.X.size()), 10, 200);
    const auto row = [&](const char* device, const Timing& t, const std::string& position, const std::string& work) {
      // four evaluations per RK4 step, three neighbour loops each with hourglass control
      std::printf("| %.0f | %.0f | %s | %d | %.1f | %.3e | %.3e | %s | %s |\n", t.particles, t.pairs, device, steps,
                  1e6 * t.seconds_per_step, t.particles / t.seconds_per_step, 12 * t.pairs / t.seconds_per_step,
                  position.c_str(), work.c_str());
      std::fflush(stdout);
    };
    const Timing host = run(setup, Mode::host, steps);
    row("cpu", host, "", "");
    if (!gpu) continue;
    for (auto [mode, name] : {std::pair{Mode::launches, "cuda, launches"}, std::pair{Mode::graph, "cuda, graph"},
                              std::pair{Mode::queued, "cuda, queued"}}) {
      const Timing device = run(setup, mode, steps);
      char position[32], work[32];
      std::snprintf(position, sizeof position, "%.1e", largest_difference(device.x, host.x));
      std::snprintf(work, sizeof work, "%.1e", std::abs(device.work - host.work) / std::abs(host.work));
      row(name, device, position, work);
    }
  }
  return 0;
}
