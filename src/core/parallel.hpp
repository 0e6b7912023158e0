#pragma once
// The one launcher for particle loops. A loop is a plain-data functor with
//   ISPH_HD void operator()(Index i) const;
// that reads neighbours and writes only particle i. parallel_for runs it with OpenMP on the host,
// or as a CUDA kernel when the calling translation unit is compiled by nvcc and the device is cuda.
#include <stdexcept>
#include <string>

#include "core/types.hpp"

#if defined(__CUDACC__)
#include <cuda_runtime.h>
#endif

namespace isph {

enum class Device { cpu, cuda };

inline const char* device_name(Device d) { return d == Device::cpu ? "cpu" : "cuda"; }

struct Exec {
  Device device = Device::cpu;
};

#if defined(__CUDACC__)
template <class F>
__global__ void particle_loop_kernel(F f, Index n) {
  const Index i = static_cast<Index>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

// Launches f over [0, n) on the current CUDA device and waits for it; throws on a launch error.
template <class F>
void cuda_parallel_for(Index n, const F& f) {
  if (n <= 0) return;
  constexpr int block = 256;
  const int grid = static_cast<int>((n + block - 1) / block);
  particle_loop_kernel<<<grid, block>>>(f, n);
  cudaError_t err = cudaGetLastError();
  if (err == cudaSuccess) err = cudaDeviceSynchronize();
  if (err != cudaSuccess) throw std::runtime_error(std::string("CUDA launch failed: ") + cudaGetErrorString(err));
}
#endif

inline constexpr Index kMinParallelLoop = 2048;

template <class F>
void parallel_for(const Exec& exec, Index n, const F& f) {
  if (exec.device == Device::cuda) {
#if defined(__CUDACC__)
    cuda_parallel_for(n, f);
    return;
#else
    throw std::runtime_error("parallel_for: this loop was not compiled for CUDA (build with nvcc)");
#endif
  }
  // Small loops run on one thread: a parallel region costs more than it saves there, and far more
  // when the cores are oversubscribed (every barrier then waits for a time slice).
#pragma omp parallel for schedule(static) if (n >= kMinParallelLoop)
  for (Index i = 0; i < n; ++i) f(i);
}

}  // namespace isph
