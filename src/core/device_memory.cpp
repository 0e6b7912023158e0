#include "core/device_memory.hpp"

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
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice), "cudaMemcpy to device");
}
void copy_device_to_host(void* dst, const void* src, std::size_t bytes) {
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost), "cudaMemcpy to host");
}
#else
int cuda_devices() { return 0; }
void* device_allocate(std::size_t) { throw std::runtime_error("this build has no CUDA backend"); }
void device_free(void*) {}
void copy_host_to_device(void*, const void*, std::size_t) { throw std::runtime_error("this build has no CUDA backend"); }
void copy_device_to_host(void*, const void*, std::size_t) { throw std::runtime_error("this build has no CUDA backend"); }
#endif

}  // namespace isph
