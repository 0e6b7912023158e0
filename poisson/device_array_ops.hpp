#pragma once
// What the Ops over device arrays share (poisson/krylov.hpp lists what an Ops supplies): vectors and the
// AMG's arrays are DeviceArrays, and the loops run on the cuda device. The cuda backend (cuda_solver.cu)
// adds cuSPARSE's product and cuBLAS's dot products; the debug device's (debug_device_solver.cpp) adds
// the launcher's.
#include <span>
#include <vector>

#include "core/device_memory.hpp"

namespace isph {

class DeviceArrayOps {
 public:
  using Vector = DeviceArray<double>;
  template <class T>
  using Array = DeviceArray<T>;
  template <class T>
  Array<T> array(std::size_t n) const {
    return Array<T>(n);
  }
  template <class T>
  std::vector<T> to_host(const T* p, std::size_t n) const {
    std::vector<T> h(n);
    copy_device_to_host(h.data(), p, n * sizeof(T));
    return h;
  }
  template <class T>
  Array<T> from_host(const std::vector<T>& v) const {
    return Array<T>(v);
  }
  static constexpr Device device = Device::cuda;
  Exec exec() const { return Exec{device}; }
  Vector vector(int n) const { return Vector(static_cast<std::size_t>(n)); }
  static void resize(Vector& v, int n) { v.resize(static_cast<std::size_t>(n)); }
  static double* data(Vector& v) { return v.data(); }
  static const double* data(const Vector& v) { return v.data(); }
  void upload(std::span<const double> h, Vector& v) const { v.upload(h); }
  template <class T>
  void assign(Array<T>& a, std::span<const T> h) const {
    a.assign(h);
  }
  void download(const Vector& v, std::span<double> h) const { v.download(h); }
};

}  // namespace isph
