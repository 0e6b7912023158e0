#include "core/device_memory.hpp"

#include <unistd.h>

#include <atomic>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/device_emulation.hpp"

#if defined(ISPH_HAVE_CUDA)
#include <cuda_runtime.h>
#endif

namespace isph {

// Each call goes to the debug device when it is on (core/device_emulation.hpp), else to the GPU: the
// gpu_* functions, which without the CUDA backend have no device to give.
namespace {

#if defined(ISPH_HAVE_CUDA)
void check(cudaError_t err, const char* what) {
  if (err != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(err));
}

int gpu_devices() {
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) return 0;
  return n;
}
void* gpu_allocate(std::size_t bytes) {
  void* p = nullptr;
  check(cudaMalloc(&p, bytes), "cudaMalloc");
  return p;
}
void gpu_free(void* p) {
  if (p) cudaFree(p);
}
void gpu_copy(void* dst, const void* src, std::size_t bytes) {
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyDefault), "cudaMemcpy");
}
std::size_t gpu_memory_bytes() {
  std::size_t free_bytes = 0, total = 0;
  check(cudaMemGetInfo(&free_bytes, &total), "cudaMemGetInfo");
  return total;
}

std::atomic<std::size_t> live_managed_bytes{0};

// Managed memory beyond the card's own would be paged in and out of it; that can hang the GPU, not only
// this process. So the managed memory held at once is kept under kManagedShare of the device's memory;
// the rest is left to plain allocations (the solvers' device copies), which fail cleanly when full.
void* gpu_managed_allocate(std::size_t bytes) {
  constexpr double kManagedShare = 0.8;
  const std::size_t total = gpu_memory_bytes();
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
void gpu_managed_free(void* p, std::size_t bytes) {
  if (!p) return;
  cudaFree(p);
  live_managed_bytes -= bytes;
}
bool gpu_accessible(const void* p) {
  if (!p) return true;
  cudaPointerAttributes a{};
  if (cudaPointerGetAttributes(&a, p) != cudaSuccess) {
    cudaGetLastError();  // clear the sticky error of an unknown pointer
    return false;
  }
  return a.type == cudaMemoryTypeDevice || a.type == cudaMemoryTypeManaged;
}
#else
[[noreturn]] void no_backend() { throw std::runtime_error("this build has no CUDA backend"); }
int gpu_devices() { return 0; }
void* gpu_allocate(std::size_t) { no_backend(); }
void gpu_free(void*) {}
void gpu_copy(void*, const void*, std::size_t) { no_backend(); }
std::size_t gpu_memory_bytes() { return 0; }
void* gpu_managed_allocate(std::size_t) { no_backend(); }
void gpu_managed_free(void*, std::size_t) {}
bool gpu_accessible(const void*) { return false; }
#endif

// A copy on the debug device: its memory open, as a copy engine reads and writes it.
void emulated_copy(void* dst, const void* src, std::size_t bytes) {
  const EmulatedLaunch copy;
  std::memcpy(dst, src, bytes);
}

}  // namespace

int cuda_devices() { return device_emulated() ? 1 : gpu_devices(); }
void* device_allocate(std::size_t bytes) { return device_emulated() ? emulated_allocate(bytes) : gpu_allocate(bytes); }
void device_free(void* p) { device_emulated() ? emulated_free(p) : gpu_free(p); }
void copy_host_to_device(void* dst, const void* src, std::size_t bytes) {
  device_emulated() ? emulated_copy(dst, src, bytes) : gpu_copy(dst, src, bytes);
}
void copy_device_to_host(void* dst, const void* src, std::size_t bytes) {
  device_emulated() ? emulated_copy(dst, src, bytes) : gpu_copy(dst, src, bytes);
}
std::size_t device_memory_bytes() {
  return device_emulated() ? static_cast<std::size_t>(sysconf(_SC_PHYS_PAGES)) * sysconf(_SC_PAGESIZE)
                           : gpu_memory_bytes();
}
void* managed_allocate(std::size_t bytes) {
  return device_emulated() ? emulated_allocate(bytes) : gpu_managed_allocate(bytes);
}
void managed_free(void* p, std::size_t bytes) { device_emulated() ? emulated_free(p) : gpu_managed_free(p, bytes); }
bool device_accessible(const void* p) { return device_emulated() ? emulated_accessible(p) : gpu_accessible(p); }

// On the debug device a graph is the recorded function itself, called again at each replay.
LaunchGraph::LaunchGraph() {
  if (device_emulated()) return;
#if defined(ISPH_HAVE_CUDA)
  cudaStream_t s = nullptr;
  check(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "cudaStreamCreate");
  stream_ = s;
#else
  throw std::runtime_error("LaunchGraph: this build has no CUDA backend");
#endif
}
LaunchGraph::~LaunchGraph() {
  release();
#if defined(ISPH_HAVE_CUDA)
  if (stream_) cudaStreamDestroy(static_cast<cudaStream_t>(stream_));
#endif
}
void LaunchGraph::release() {
#if defined(ISPH_HAVE_CUDA)
  if (graph_) cudaGraphExecDestroy(static_cast<cudaGraphExec_t>(graph_));
#endif
  graph_ = nullptr;
  host_launches_ = nullptr;
}
void LaunchGraph::record(const std::function<void(const Exec&)>& launches) {
  release();
  if (device_emulated()) {
    host_launches_ = launches;
    return;
  }
#if defined(ISPH_HAVE_CUDA)
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
#endif
}
void LaunchGraph::replay() {
  if (!recorded()) throw std::logic_error("LaunchGraph::replay: nothing recorded");
  if (host_launches_) return host_launches_(exec());
#if defined(ISPH_HAVE_CUDA)
  check(cudaGraphLaunch(static_cast<cudaGraphExec_t>(graph_), static_cast<cudaStream_t>(stream_)), "cudaGraphLaunch");
#endif
}
void LaunchGraph::synchronize() {
#if defined(ISPH_HAVE_CUDA)
  if (stream_) check(cudaStreamSynchronize(static_cast<cudaStream_t>(stream_)), "cudaStreamSynchronize");
#endif
}

}  // namespace isph
