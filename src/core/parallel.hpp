#pragma once
// The one launcher for particle loops. A loop is a plain-data functor with
//   ISPH_HD void operator()(Index i) const;
// that reads neighbours and writes only particle i. parallel_for runs it with OpenMP on the host,
// or as a CUDA kernel when the calling translation unit is compiled by nvcc and the device is cuda.
// Beside it, the collective primitives the time step and the AMG set-up need: a reduction, a prefix
// sum and a stable sort by key. On the debug device (core/device_emulation.hpp) the cuda device's
// launches run on the host, with its memory open to them.
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/device_emulation.hpp"
#include "core/types.hpp"

#if defined(__CUDACC__)
#include <cuda_runtime.h>
#include <thrust/execution_policy.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>
#include <thrust/sort.h>
#include <thrust/transform_reduce.h>
#endif

namespace isph {

enum class Device { cpu, cuda };

inline const char* device_name(Device d) { return d == Device::cpu ? "cpu" : device_emulated() ? "debug" : "cuda"; }

// Loops shorter than this run on one thread on the host: a parallel region costs more than it saves
// there, and far more when the cores are oversubscribed (every barrier then waits for a time slice).
inline constexpr Index kMinParallelLoop = 2048;

struct Exec {
  Device device = Device::cpu;
  void* stream = nullptr;                  // cuda: the stream (cudaStream_t) launches go to; null: the default stream
  bool wait = true;                        // cuda: wait for each launch to finish (false: the caller synchronizes)
  Index parallel_from = kMinParallelLoop;  // host: the shortest loop run on all threads
};

#if defined(__CUDACC__)
template <class F>
__global__ void particle_loop_kernel(F f, Index n) {
  const Index i = static_cast<Index>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

// Launches f over [0, n) on the current CUDA device, on exec's stream, and waits for it unless told not
// to; throws on a launch error.
template <class F>
void cuda_parallel_for(const Exec& exec, Index n, const F& f) {
  if (n <= 0) return;
  constexpr int block = 256;
  const int grid = static_cast<int>((n + block - 1) / block);
  const auto stream = static_cast<cudaStream_t>(exec.stream);
  particle_loop_kernel<<<grid, block, 0, stream>>>(f, n);
  cudaError_t err = cudaGetLastError();
  if (err == cudaSuccess && exec.wait) err = cudaStreamSynchronize(stream);
  if (err != cudaSuccess) throw std::runtime_error(std::string("CUDA launch failed: ") + cudaGetErrorString(err));
}
#endif

[[noreturn]] inline void not_compiled_for_cuda(const char* what) {
  throw std::runtime_error(std::string(what) + ": not compiled for CUDA (build with nvcc)");
}

// Whether exec's launches go to a GPU (the cuda device, with the debug device off).
inline bool on_gpu(const Exec& exec) { return exec.device == Device::cuda && !device_emulated(); }

// A launch run by the host: on the debug device, its memory is open for the launch's length.
class HostLaunch {
 public:
  explicit HostLaunch(const Exec& exec) {
    if (exec.device == Device::cuda) open_.emplace();
  }

 private:
  std::optional<EmulatedLaunch> open_;
};

template <class F>
void parallel_for(const Exec& exec, Index n, const F& f) {
  if (on_gpu(exec)) {
#if defined(__CUDACC__)
    cuda_parallel_for(exec, n, f);
    return;
#else
    not_compiled_for_cuda("parallel_for");
#endif
  }
  const HostLaunch launch(exec);
#pragma omp parallel for schedule(static) if (n >= exec.parallel_from)
  for (Index i = 0; i < n; ++i) f(i);
}

// f over the entries of an index list (a subset of a particle set): f(list[i]) for i < count, or f over
// [0, n) when list is null.
template <class F>
struct OnList {
  const Index* list;
  F f;
  ISPH_HD void operator()(Index i) const { f(list[i]); }
};
template <class F>
void parallel_for_listed(const Exec& exec, Index n, const Index* list, Index count, const F& f) {
  if (list)
    parallel_for(exec, count, OnList<F>{list, f});
  else
    parallel_for(exec, n, f);
}

// Combinations for parallel_reduce. Only exact ones are offered (max and min of any type, sums of
// integers), so that a result does not depend on the thread count, the order or the device.
struct MaxOf {
  template <class T>
  ISPH_HD T operator()(T a, T b) const {
    return a < b ? b : a;
  }
};
struct MinOf {
  template <class T>
  ISPH_HD T operator()(T a, T b) const {
    return b < a ? b : a;
  }
};
struct IntegerSum {
  template <class T>
  ISPH_HD T operator()(T a, T b) const {
    static_assert(std::is_integral_v<T>, "IntegerSum: a floating-point sum would depend on the order");
    return a + b;
  }
};

// The values of a per-particle array, as a functor Index -> Real (for parallel_reduce and ordered_sum).
struct ScalarAt {
  const Real* value;
  ISPH_HD Real operator()(Index i) const { return value[i]; }
};

// out[i] = in[i].
template <class T>
struct CopyElements {
  const T* in;
  T* out;
  ISPH_HD void operator()(Index i) const { out[i] = in[i]; }
};

// out[i] = value.
template <class T>
struct SetElements {
  T* out;
  T value;
  ISPH_HD void operator()(Index i) const { out[i] = value; }
};

// combine over i in [0, n) of value(i), starting from identity (value: a functor Index -> T).
template <class T, class F, class Combine>
T parallel_reduce(const Exec& exec, Index n, T identity, const F& value, const Combine& combine) {
  if (on_gpu(exec)) {
#if defined(__CUDACC__)
    return thrust::transform_reduce(thrust::device, thrust::counting_iterator<Index>(0),
                                    thrust::counting_iterator<Index>(n), value, identity, combine);
#else
    not_compiled_for_cuda("parallel_reduce");
#endif
  }
  const HostLaunch launch(exec);
  T result = identity;
#pragma omp parallel if (n >= exec.parallel_from)
  {
    T local = identity;
#pragma omp for schedule(static) nowait
    for (Index i = 0; i < n; ++i) local = combine(local, value(i));
#pragma omp critical(isph_parallel_reduce)
    result = combine(result, local);
  }
  return result;
}

// The first particle (lowest index) that `select` accepts, or -1.
template <class Select>
struct IndexIfSelected {
  Select select;
  Index none;
  ISPH_HD Index operator()(Index a) const { return select(a) ? a : none; }
};
template <class Select>
Index first_particle(const Exec& exec, Index n, Select select) {
  const Index first = parallel_reduce(exec, n, n, IndexIfSelected<Select>{select, n}, MinOf{});
  return first < n ? first : -1;
}

// v[i] = v[0] + ... + v[i] for i in [0, n): turns counts into the ends of CSR rows.
inline void inclusive_scan(const Exec& exec, Index* v, Index n) {
  if (on_gpu(exec)) {
#if defined(__CUDACC__)
    thrust::inclusive_scan(thrust::device, v, v + n, v);
    return;
#else
    not_compiled_for_cuda("inclusive_scan");
#endif
  }
  const HostLaunch launch(exec);
  for (Index i = 1; i < n; ++i) v[i] += v[i - 1];
}

// start[c] = the first position of n sorted keys whose key is >= c (a lower bound), launched over c in
// [0, key_bound]: where each key's run starts, as the row offsets of a CSR structure.
struct KeyStarts {
  const Index* sorted_key;
  Index n;
  Index* start;
  ISPH_HD void operator()(Index c) const {
    Index lo = 0, hi = n;
    while (lo < hi) {
      const Index mid = lo + (hi - lo) / 2;
      if (sorted_key[mid] < c)
        lo = mid + 1;
      else
        hi = mid;
    }
    start[c] = lo;
  }
};

// Reorders values by their keys, which lie in [0, key_bound), keeping the order of equal keys; the keys
// end up sorted too. A counting sort on the host, thrust's stable sort on the device.
inline void stable_sort_by_key(const Exec& exec, Index* keys, Index* values, Index n, Index key_bound) {
  if (on_gpu(exec)) {
#if defined(__CUDACC__)
    thrust::stable_sort_by_key(thrust::device, keys, keys + n, values);
    return;
#else
    not_compiled_for_cuda("stable_sort_by_key");
#endif
  }
  const HostLaunch launch(exec);
  std::vector<Index> next(static_cast<std::size_t>(key_bound) + 1, 0), sorted_keys(n), sorted_values(n);
  for (Index i = 0; i < n; ++i) ++next[keys[i] + 1];
  for (Index k = 0; k < key_bound; ++k) next[k + 1] += next[k];  // next[k]: where key k's first entry goes
  for (Index i = 0; i < n; ++i) {
    const Index to = next[keys[i]]++;
    sorted_keys[to] = keys[i];
    sorted_values[to] = values[i];
  }
  std::copy(sorted_keys.begin(), sorted_keys.end(), keys);
  std::copy(sorted_values.begin(), sorted_values.end(), values);
}

}  // namespace isph
