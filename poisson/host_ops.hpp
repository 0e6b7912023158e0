#pragma once
// The host's Ops for the project's Krylov solver and its AMG (poisson/krylov.hpp lists what an Ops
// supplies): vectors in ordinary memory, loops through the launcher with OpenMP. The native backend
// (native_solver.cpp) and the tests use it.
#include <algorithm>
#include <span>
#include <vector>

#include "poisson/linear_solver.hpp"
#include "poisson/sparse_functors.hpp"

namespace isph {

class HostOps {
 public:
  using Vector = std::vector<double>;
  template <class T>
  using Array = std::vector<T>;
  template <class T>
  Array<T> array(std::size_t n) const {
    return Array<T>(n);
  }
  template <class T>
  std::vector<T> to_host(const T* p, std::size_t n) const {
    return std::vector<T>(p, p + n);
  }
  template <class T>
  Array<T> from_host(std::vector<T> v) const {
    return v;
  }
  static constexpr Device device = Device::cpu;
  Exec exec() const { return Exec{device}; }
  Vector vector(int n) const { return Vector(static_cast<std::size_t>(n)); }
  static void resize(Vector& v, int n) { v.resize(static_cast<std::size_t>(n)); }
  static double* data(Vector& v) { return v.data(); }
  static const double* data(const Vector& v) { return v.data(); }
  void upload(std::span<const double> h, Vector& v) const { v.assign(h.begin(), h.end()); }
  template <class T>
  void assign(Array<T>& a, std::span<const T> h) const {
    a.assign(h.begin(), h.end());
  }
  void download(const Vector& v, std::span<double> h) const { std::copy(v.begin(), v.end(), h.begin()); }
  void set_matrix(const CsrMatrix& A) { A_ = A; }
  CsrView matrix() const { return {A_.rows, A_.row_offset.data(), A_.col.data(), A_.val.data()}; }
  void spmv(const Vector& x, Vector& y) const {
    parallel_for(exec(), A_.rows,
                 CsrRowProduct{.row_offset = A_.row_offset.data(),
                               .col = A_.col.data(),
                               .val = A_.val.data(),
                               .x = x.data(),
                               .y = y.data()});
  }
  // Summed in fixed blocks, then the block sums in order: the result does not depend on the threads.
  double dot(const Vector& x, const Vector& y) {
    constexpr Index block = 4096;
    const auto n = static_cast<Index>(x.size());
    const Index blocks = (n + block - 1) / block;
    std::vector<double>& partial = partial_sums_;  // kept between calls: no allocation per product
    partial.resize(blocks);
#pragma omp parallel for schedule(static) if (blocks > 1)
    for (Index k = 0; k < blocks; ++k) {
      double s = 0;
      for (Index i = k * block; i < std::min(n, (k + 1) * block); ++i) s += x[i] * y[i];
      partial[k] = s;
    }
    double s = 0;
    for (double e : partial) s += e;
    return s;
  }
  void release() {}  // the copy of A stays: the next set_matrix() assigns into its storage

 private:
  CsrMatrix A_;
  std::vector<double> partial_sums_;  // dot(): one sum per block
};

}  // namespace isph
