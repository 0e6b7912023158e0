#include "core/device_memory.hpp"

#include <atomic>
#include <stdexcept>
#include <string>

#if defined(ISPH_HAVE_CUDA)
#include <cuda_runtime.h>
#endif

namespace isph {

#if defined(ISPH_HAVE_CUDA)
namespace {
void check(cudaError_t err, const char* what) {
  if (err != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(err));
}
}  // namespace

int cuda_devices() {
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) return 0;
  return n;
}
void* device_allocate(std::size_t bytes) {
  void* p = nullptr;
  check(cudaMalloc(&p, bytes), "cudaMalloc");
  return p;
}
void device_free(void* p) {
  if (p) cudaFree(p);
}
void copy_host_to_device(void* dst, const void* src, std::size_t bytes) {
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyDefault), "cudaMemcpy to device");
}
void copy_device_to_host(void* dst, const void* src, std::size_t bytes) {
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyDefault), "cudaMemcpy to host");
}
namespace {
std::atomic<std::size_t> live_managed_bytes{0};
}  // namespace
std::size_t device_memory_bytes() {
  std::size_t free_bytes = 0, total = 0;
  check(cudaMemGetInfo(&free_bytes, &total), "cudaMemGetInfo");
  return total;
}
// Managed memory beyond the card's own would be paged in and out of it; that can hang the GPU, not only
// this process. So the managed memory held at once is kept under kManagedShare of the device's memory;
// the rest is left to plain allocations (the solvers' device copies), which fail cleanly when full.
void* managed_allocate(std::size_t bytes) {
  constexpr double kManagedShare = 0.8;
  const std::size_t total = device_memory_bytes();
  const std::size_t held = live_managed_bytes.load();
  if (static_cast<double>(held + bytes) > kManagedShare * static_cast<double>(total)) {
    constexpr double GiB = 1024.0 * 1024 * 1024;
    throw std::runtime_error("managed memory: " + std::to_string((held + bytes) / GiB) + " GiB would exceed " +
                             std::to_string(kManagedShare * 100) + " % of the device's " + std::to_string(total / GiB) +
                             " GiB; run fewer particles, or a device with more memory");
  }
  void* p = nullptr;
  check(cudaMallocManaged(&p, bytes), "cudaMallocManaged");
  live_managed_bytes += bytes;
  return p;
}
void managed_free(void* p, std::size_t bytes) {
  if (!p) return;
  cudaFree(p);
  live_managed_bytes -= bytes;
}
bool device_accessible(const void* p) {
  if (!p) return true;
  cudaPointerAttributes a{};
  if (cudaPointerGetAttributes(&a, p) != cudaSuccess) {
    cudaGetLastError();  // clear the sticky error of an unknown pointer
    return false;
  }
  return a.type == cudaMemoryTypeDevice || a.type == cudaMemoryTypeManaged;
}

LaunchGraph::LaunchGraph() {
  cudaStream_t s = nullptr;
  check(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "cudaStreamCreate");
  stream_ = s;
}
LaunchGraph::~LaunchGraph() {
  release();
  cudaStreamDestroy(static_cast<cudaStream_t>(stream_));
}
void LaunchGraph::release() {
  if (graph_) cudaGraphExecDestroy(static_cast<cudaGraphExec_t>(graph_));
  graph_ = nullptr;
}
void LaunchGraph::record(const std::function<void(const Exec&)>& launches) {
  release();
  const auto s = static_cast<cudaStream_t>(stream_);
  check(cudaStreamBeginCapture(s, cudaStreamCaptureModeThreadLocal), "cudaStreamBeginCapture");
  cudaGraph_t graph = nullptr;
  try {
    launches(exec());
  } catch (...) {
    cudaStreamEndCapture(s, &graph);
    if (graph) cudaGraphDestroy(graph);
    throw;
  }
  check(cudaStreamEndCapture(s, &graph), "cudaStreamEndCapture");
  cudaGraphExec_t instance = nullptr;
  const cudaError_t err = cudaGraphInstantiate(&instance, graph, 0);
  cudaGraphDestroy(graph);
  check(err, "cudaGraphInstantiate");
  graph_ = instance;
}
void LaunchGraph::replay() {
  if (!graph_) throw std::logic_error("LaunchGraph::replay: nothing recorded");
  check(cudaGraphLaunch(static_cast<cudaGraphExec_t>(graph_), static_cast<cudaStream_t>(stream_)), "cudaGraphLaunch");
}
void LaunchGraph::synchronize() { check(cudaStreamSynchronize(static_cast<cudaStream_t>(stream_)), "cudaStreamSynchronize"); }
#else
int cuda_devices() { return 0; }
void* device_allocate(std::size_t) { throw std::runtime_error("this build has no CUDA backend"); }
void device_free(void*) {}
void copy_host_to_device(void*, const void*, std::size_t) { throw std::runtime_error("this build has no CUDA backend"); }
void copy_device_to_host(void*, const void*, std::size_t) { throw std::runtime_error("this build has no CUDA backend"); }
std::size_t device_memory_bytes() { return 0; }
void* managed_allocate(std::size_t) { throw std::runtime_error("this build has no CUDA backend"); }
void managed_free(void*, std::size_t) {}
bool device_accessible(const void*) { return false; }
LaunchGraph::LaunchGraph() { throw std::runtime_error("LaunchGraph: this build has no CUDA backend"); }
LaunchGraph::~LaunchGraph() = default;
void LaunchGraph::release() {}
void LaunchGraph::record(const std::function<void(const Exec&)>&) {}
void LaunchGraph::replay() {}
void LaunchGraph::synchronize() {}
#endif

}  // namespace isph
