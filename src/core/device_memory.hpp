#pragma once
// Device memory for the CUDA backend, usable from host-compiled code. Without CUDA
// (ISPH_HAVE_CUDA undefined) cuda_devices() is 0 and allocation throws, unless the debug device is on
// (core/device_emulation.hpp): then the memory is its own, in either build.
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/parallel.hpp"

namespace isph {

int cuda_devices();  // number of usable CUDA devices (0 when none, or not built)
void* device_allocate(std::size_t bytes);
void device_free(void* p);
// The host side may be ordinary or managed memory (the copies let the runtime tell which).
void copy_host_to_device(void* dst, const void* src, std::size_t bytes);
void copy_device_to_host(void* dst, const void* src, std::size_t bytes);
// CUDA managed memory: one address that the host and the device both read and write (the driver moves
// the pages to whichever touches them). For state that the device steps and the host reads for output.
// An allocation that would take the managed memory held beyond 80 % of the device's throws.
void* managed_allocate(std::size_t bytes);
std::size_t device_memory_bytes();              // the current device's memory (0 without CUDA)
void managed_free(void* p, std::size_t bytes);  // bytes: as allocated
// Whether a kernel can read p: device or managed memory (a null pointer, an empty array's, counts as
// readable). False for ordinary host memory, and always without CUDA.
bool device_accessible(const void* p);

// The allocator of StateVector: ordinary host memory, or managed memory when made with
// device_visible = true. Copies, moves and swaps carry the allocator along, so that an array assigned
// from a device-visible one is device-visible too. A device-visible array's new elements are not
// value-initialised (resize(n) and StateVector(n, allocator) leave them as the memory has them), so that
// growing an array that a launch fills next does not first write its new pages on the host, moving them
// there and back; such an array is written by a launch, or given a value (resize(n, v), assign), before
// it is read. The debug device fills new memory with 0xFF bytes, NaN in every double, so that a read of
// an element never written shows in its results.
template <class T>
struct StateAllocator {
  using value_type = T;
  using propagate_on_container_copy_assignment = std::true_type;
  using propagate_on_container_move_assignment = std::true_type;
  using propagate_on_container_swap = std::true_type;
  bool device_visible = false;

  StateAllocator() = default;
  explicit StateAllocator(bool visible) : device_visible(visible) {}
  template <class U>
  StateAllocator(const StateAllocator<U>& o) : device_visible(o.device_visible) {}
  T* allocate(std::size_t n) {
    return device_visible ? static_cast<T*>(managed_allocate(n * sizeof(T))) : std::allocator<T>{}.allocate(n);
  }
  void deallocate(T* p, std::size_t n) {
    if (device_visible)
      managed_free(p, n * sizeof(T));
    else
      std::allocator<T>{}.deallocate(p, n);
  }
  template <class U>
  void construct(U* p) {
    if (device_visible)
      ::new (static_cast<void*>(p)) U;
    else
      ::new (static_cast<void*>(p)) U();
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const StateAllocator<U>& o) const {
    return device_visible == o.device_visible;
  }
};

// Per-particle state of a solver that may step on the device (structure/tlsph.hpp).
template <class T>
using StateVector = std::vector<T, StateAllocator<T>>;

// Sizes v to n elements for a launch to overwrite: when n outgrows the capacity, the old contents are
// dropped, not copied by the host into the new allocation, and a quarter more is reserved, so that an
// array whose size wanders (the PPE's entries, step by step) is seldom reallocated.
template <class T>
void resize_for_overwrite(StateVector<T>& v, std::size_t n) {
  if (n > v.capacity()) {
    StateVector<T> fresh(v.get_allocator());
    fresh.reserve(n + n / 4);
    v.swap(fresh);
  }
  v.resize(n);
}

// One element that a launch on exec wrote, read on the host: on the cuda device by an explicit copy,
// so that no page of managed memory moves to the host for it.
template <class T>
T read_back(const Exec& exec, const T* p) {
  if (exec.device != Device::cuda) return *p;
  T value;
  copy_device_to_host(&value, p, sizeof(T));
  return value;
}

// Moves v's contents into managed memory (the device can then read and write it).
template <class T>
void make_device_visible(StateVector<T>& v) {
  v = StateVector<T>(v.begin(), v.end(), StateAllocator<T>(true));
}

// Launches recorded once on a stream of their own and replayed as one CUDA graph: many small launches
// (a structure's substep) then cost one launch. On the debug device the recorded function is called
// again at each replay. Without either, making one throws.
class LaunchGraph {
 public:
  LaunchGraph();
  ~LaunchGraph();
  LaunchGraph(const LaunchGraph&) = delete;
  LaunchGraph& operator=(const LaunchGraph&) = delete;

  // Launches that go to this graph's stream without waiting (to record them, or to run them directly).
  Exec exec() const { return Exec{Device::cuda, stream_, false}; }
  // Records what `launches` sends to exec() as the graph (replacing the one recorded before). The debug
  // device keeps `launches` and calls it at each replay, so it must capture what it uses by value.
  void record(const std::function<void(const Exec&)>& launches);
  bool recorded() const { return graph_ != nullptr || host_launches_ != nullptr; }
  // Runs the recorded graph on the stream (without waiting).
  void replay();
  // Waits for everything sent to the stream.
  void synchronize();

 private:
  void release();
  void* stream_ = nullptr;                          // cudaStream_t
  void* graph_ = nullptr;                           // cudaGraphExec_t
  std::function<void(const Exec&)> host_launches_;  // the debug device's "graph"
};

// An array in device memory, filled from and read back into host arrays (ordinary or managed memory).
template <class T>
class DeviceArray {
 public:
  DeviceArray() = default;
  explicit DeviceArray(std::size_t n) : n_(n), capacity_(n) { p_ = static_cast<T*>(device_allocate(n_ * sizeof(T))); }
  explicit DeviceArray(const std::vector<T>& host) : DeviceArray(host.size()) { upload(host); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  DeviceArray(DeviceArray&& o) noexcept : p_(o.p_), n_(o.n_), capacity_(o.capacity_) {
    o.p_ = nullptr, o.n_ = o.capacity_ = 0;
  }
  DeviceArray& operator=(DeviceArray&& o) noexcept {
    std::swap(p_, o.p_), std::swap(n_, o.n_), std::swap(capacity_, o.capacity_);
    return *this;
  }
  ~DeviceArray() { device_free(p_); }
  T* data() { return p_; }
  const T* data() const { return p_; }
  std::size_t size() const { return n_; }
  // Makes the array host's copy. It is reallocated only when host outgrows the allocation, with a
  // quarter more room: a copy of the PPE, whose size changes every step, then seldom allocates (and a
  // cudaFree waits for the whole device).
  void assign(std::span<const T> host) {
    if (host.size() > capacity_) *this = DeviceArray(host.size() + host.size() / 4);
    n_ = host.size();
    upload(host);
  }
  // n elements, reallocated (with a quarter more room) only when n outgrows the allocation; the contents
  // are not kept (work vectors whose size follows the particles').
  void resize(std::size_t n) {
    if (n > capacity_) *this = DeviceArray(n + n / 4);
    n_ = n;
  }
  // At least n elements (a scratch buffer: grows, never shrinks; the contents are not kept).
  void grow_to(std::size_t n) {
    if (n_ >= n) return;
    if (capacity_ < n) *this = DeviceArray(n);
    n_ = n;
  }
  // Copies host into the array; the sizes must agree.
  void upload(std::span<const T> host) {
    if (host.size() != n_) throw std::invalid_argument("DeviceArray::upload: size mismatch");
    copy_host_to_device(p_, host.data(), n_ * sizeof(T));
  }
  // Copies the array into host; the sizes must agree.
  void download(std::span<T> host) const {
    if (host.size() != n_) throw std::invalid_argument("DeviceArray::download: size mismatch");
    copy_device_to_host(host.data(), p_, n_ * sizeof(T));
  }
  // Resizes host to the array's size first.
  void download(std::vector<T>& host) const {
    host.resize(n_);
    download(std::span<T>(host));
  }
  std::vector<T> to_host() const {
    std::vector<T> h;
    download(h);
    return h;
  }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0, capacity_ = 0;  // elements in use, and allocated
};

}  // namespace isph
