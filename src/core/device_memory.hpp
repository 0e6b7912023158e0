#pragma once
// Device memory for the CUDA backend, usable from host-compiled code. Without CUDA
// (ISPH_HAVE_CUDA undefined) cuda_devices() is 0 and allocation throws.
#include <cstddef>
#include <stdexcept>
#include <utility>
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
  explicit DeviceArray(std::size_t n) : n_(n) { p_ = static_cast<T*>(device_allocate(n_ * sizeof(T))); }
  explicit DeviceArray(const std::vector<T>& host) : DeviceArray(host.size()) { upload(host); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  DeviceArray(DeviceArray&& o) noexcept : p_(o.p_), n_(o.n_) { o.p_ = nullptr, o.n_ = 0; }
  DeviceArray& operator=(DeviceArray&& o) noexcept {
    std::swap(p_, o.p_), std::swap(n_, o.n_);
    return *this;
  }
  ~DeviceArray() { device_free(p_); }
  T* data() { return p_; }
  const T* data() const { return p_; }
  std::size_t size() const { return n_; }
  // Makes the array host's copy, reallocating only when the size changes.
  void assign(const std::vector<T>& host) {
    if (host.size() != n_) *this = DeviceArray(host.size());
    upload(host);
  }
  // At least n elements (a scratch buffer: grows, never shrinks; the contents are not kept).
  void grow_to(std::size_t n) {
    if (n_ < n) *this = DeviceArray(n);
  }
  // Copies host into the array; the sizes must agree.
  void upload(const std::vector<T>& host) {
    if (host.size() != n_) throw std::invalid_argument("DeviceArray::upload: size mismatch");
    copy_host_to_device(p_, host.data(), n_ * sizeof(T));
  }
  void download(std::vector<T>& host) const {
    host.resize(n_);
    copy_device_to_host(host.data(), p_, n_ * sizeof(T));
  }
  std::vector<T> to_host() const {
    std::vector<T> h;
    download(h);
    return h;
  }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0;
};

}  // namespace isph
