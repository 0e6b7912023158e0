#pragma once
// Device memory for the CUDA backend, usable from host-compiled code. Without CUDA
// (ISPH_HAVE_CUDA undefined) cuda_devices() is 0 and allocation throws.
#include <cstddef>
#include <vector>

namespace isph {

int cuda_devices();  // number of usable CUDA devices (0 when none, or not built)
void* device_allocate(std::size_t bytes);
void device_free(void* p);
void copy_host_to_device(void* dst, const void* src, std::size_t bytes);
void copy_device_to_host(void* dst, const void* src, std::size_t bytes);

// An array in device memory, filled from and read back into host vectors.
template <class T>
class DeviceArray {
 public:
  DeviceArray() = default;
  explicit DeviceArray(const std::vector<T>& host) : n_(host.size()) {
    p_ = static_cast<T*>(device_allocate(n_ * sizeof(T)));
    copy_host_to_device(p_, host.data(), n_ * sizeof(T));
  }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  ~DeviceArray() { device_free(p_); }
  T* data() { return p_; }
  std::vector<T> to_host() const {
    std::vector<T> h(n_);
    copy_device_to_host(h.data(), p_, n_ * sizeof(T));
    return h;
  }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0;
};

}  // namespace isph
