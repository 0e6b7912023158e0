// Neighbour-pass benchmark: pair evaluations per second of one neighbour pass, on the host and, when a
// device is visible, on the GPU, for 2D particle blocks of the given sizes. Prints a markdown table
// (docs/PERFORMANCE.md).
//
//   build/isph_pair_bench [--repeats R] [SIZE...]      (default sizes: 1e4 1e5 1e6 4e6)
//
// The block: a square lattice of SIZE particles at spacing dx = 1 with ±0.2 dx jitter; cubic B-spline,
// h = 1.2 dx, so a search radius of 2.4 dx and about 18 neighbours per particle. The pass timed is the
// corrected pressure gradient (kernels/operators.hpp: CorrectedGradient, Eq. 2 of seed 001), the
// projection's loop: per pair a kernel gradient, a minimum-image difference and an axpy. One *pair
// evaluation* is one visit of one neighbour pair. The neighbour-list build (cell list and CSR list) is
// timed too. With a device, the GPU gradient is checked against the host's (largest relative
// difference printed in the table).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/device_memory.hpp"
#include "core/neighbour_search.hpp"
#include "kernels/operators.hpp"

using namespace isph;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct Block {
  std::vector<Vec<2>> x;
  std::vector<Real> volume, f;
};

Block make_block(double size) {
  const int side = std::max(4, static_cast<int>(std::lround(std::sqrt(size))));
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> jitter(-0.2, 0.2);
  Block b;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      const Vec<2> p{{i + jitter(rng), j + jitter(rng)}};
      b.x.push_back(p);
      b.volume.push_back(1.0);
      b.f.push_back(std::sin(0.05 * p[0]) + 0.3 * p[1]);
    }
  return b;
}

struct PassResult {
  double build_seconds = 0, pass_seconds = 0;
  Index pairs = 0;
  std::vector<Vec<2>> grad;
};

PassResult host_pass(const Block& b, const SmoothingKernel<2>& kernel, int repeats) {
  PassResult r;
  const auto n = static_cast<Index>(b.x.size());
  const Exec host{};
  auto start = Clock::now();
  CellList<2> cells;
  cells.build(b.x, kernel.support());
  const NeighbourList list = neighbour_list(cells, n);
  r.build_seconds = seconds_since(start);
  r.pairs = list.pairs();
  const OperatorView<2> v{n, b.x.data(), b.volume.data(), list.offset.data(), list.index.data(), kernel};
  std::vector<Mat<2>> L(n);
  parallel_for(host, n, GradientCorrection<2>{v, L.data()});
  r.grad.resize(n);
  const CorrectedGradient<2> pass{v, L.data(), b.f.data(), r.grad.data()};
  parallel_for(host, n, pass);  // warm-up
  start = Clock::now();
  for (int k = 0; k < repeats; ++k) parallel_for(host, n, pass);
  r.pass_seconds = seconds_since(start) / repeats;
  return r;
}

#if defined(__CUDACC__)
PassResult device_pass(const Block& b, const SmoothingKernel<2>& kernel, int repeats) {
  PassResult r;
  const auto n = static_cast<Index>(b.x.size());
  const Exec gpu{Device::cuda};
  DeviceArray<Vec<2>> x(b.x);
  DeviceArray<Real> volume(b.volume), f(b.f);
  CellList<2> cells(gpu);
  cells.build(x.data(), n, kernel.support());  // warm-up (thrust and context start-up)
  auto start = Clock::now();
  cells.build(x.data(), n, kernel.support());
  const NeighbourList list = neighbour_list(cells, n);
  r.build_seconds = seconds_since(start);
  r.pairs = static_cast<Index>(list.index.size());
  const OperatorView<2> v{n, x.data(), volume.data(), list.offset.data(), list.index.data(), kernel};
  DeviceArray<Mat<2>> L(n);
  DeviceArray<Vec<2>> grad(n);
  parallel_for(gpu, n, GradientCorrection<2>{v, L.data()});
  const CorrectedGradient<2> pass{v, L.data(), f.data(), grad.data()};
  parallel_for(gpu, n, pass);  // warm-up; every launch waits for its kernel
  start = Clock::now();
  for (int k = 0; k < repeats; ++k) parallel_for(gpu, n, pass);
  r.pass_seconds = seconds_since(start) / repeats;
  r.grad = grad.to_host();
  return r;
}

double largest_relative_difference(const std::vector<Vec<2>>& a, const std::vector<Vec<2>>& b) {
  double scale = 0, worst = 0;
  for (const auto& g : b) scale = std::max(scale, std::sqrt(norm2(g)));
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::sqrt(norm2(a[i] - b[i])));
  return scale > 0 ? worst / scale : worst;
}
#endif

void print_row(const char* device, const Block& b, const PassResult& r, const std::string& check) {
  const double n = static_cast<double>(b.x.size());
  std::printf("| %.0f | %d | %.1f | %s | %.2f | %.3f | %.3e | %s |\n", n, r.pairs, r.pairs / n, device,
              1e3 * r.build_seconds, 1e3 * r.pass_seconds, r.pairs / r.pass_seconds, check.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 20;
  std::vector<double> sizes;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--repeats" && a + 1 < argc)
      repeats = std::max(1, std::atoi(argv[++a]));
    else if (arg == "-h" || arg == "--help") {
      std::printf("usage: isph_pair_bench [--repeats R] [SIZE...]\n");
      return 0;
    } else
      sizes.push_back(std::atof(arg.c_str()));
  }
  if (sizes.empty()) sizes = {1e4, 1e5, 1e6, 4e6};
  const auto kernel = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2);
  const bool gpu = cuda_devices() > 0;
  std::printf("<!-- isph_pair_bench: %d OpenMP threads, %s, %d repeats of the corrected-gradient pass -->\n",
              omp_get_max_threads(), gpu ? "CUDA device visible" : "no CUDA device", repeats);
  std::printf(
      "| particles | pairs | per particle | device | neighbour list build [ms] | pass [ms] | pair evaluations/s | GPU "
      "vs host |\n");
  std::printf("|---:|---:|---:|---|---:|---:|---:|---|\n");
  for (double size : sizes) {
    const Block b = make_block(size);
    const PassResult host = host_pass(b, kernel, repeats);
    print_row("cpu", b, host, "");
#if defined(__CUDACC__)
    if (gpu) {
      const PassResult device = device_pass(b, kernel, repeats);
      char check[64];
      std::snprintf(check, sizeof check, "max rel. diff %.1e", largest_relative_difference(device.grad, host.grad));
      print_row("cuda", b, device, check);
    }
#endif
  }
  return 0;
}
