// The launcher's collective primitives on the GPU against the host: parallel_reduce (max, min,
// integer sum), the ordered floating-point sum (the same bits) and inclusive_scan, on fresh random
// data of several sizes; and the guard that keeps managed memory within the card.
// Skipped without a CUDA device.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/device_memory.hpp"
#include "core/ordered_sum.hpp"
#include "core/parallel.hpp"
#include "gpu_skip.hpp"

using namespace isph;

namespace {
struct IntAt {
  const Index* v;
  ISPH_HD Index operator()(Index i) const { return v[i]; }
};
}  // namespace

TEST(DevicePrimitives, ReduceAndScanMatchTheHost) {
  ISPH_SKIP_WITHOUT_GPU();
  std::random_device seed;
  std::mt19937 rng(seed());
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<Index> small(0, 40);
  for (Index n : {1, 1000, 1 << 20}) {
    std::vector<double> v(n);
    std::vector<Index> k(n);
    for (Index i = 0; i < n; ++i) v[i] = normal(rng), k[i] = small(rng);
    const DeviceArray<double> dv(v);
    const DeviceArray<Index> dk(k);
    const Exec gpu{Device::cuda}, host{};
    EXPECT_EQ(parallel_reduce(gpu, n, -1e300, ScalarAt{dv.data()}, MaxOf{}),
              parallel_reduce(host, n, -1e300, ScalarAt{v.data()}, MaxOf{}));
    EXPECT_EQ(parallel_reduce(gpu, n, 1e300, ScalarAt{dv.data()}, MinOf{}),
              parallel_reduce(host, n, 1e300, ScalarAt{v.data()}, MinOf{}));
    EXPECT_EQ(parallel_reduce(gpu, n, Index{0}, IntAt{dk.data()}, IntegerSum{}),
              parallel_reduce(host, n, Index{0}, IntAt{k.data()}, IntegerSum{}));
    StateVector<double> device_partial(StateAllocator<double>(true)), host_partial;
    EXPECT_EQ(ordered_sum(gpu, n, ScalarAt{dv.data()}, device_partial),
              ordered_sum(host, n, ScalarAt{v.data()}, host_partial))
        << n;
    DeviceArray<Index> scanned(k);  // the scan works in place
    inclusive_scan(gpu, scanned.data(), n);
    inclusive_scan(host, k.data(), n);
    EXPECT_EQ(scanned.to_host(), k) << n;
  }
}

// Managed memory beyond the card could hang the GPU: a request for more than the guard's share of the
// device is refused with an error, also when memory already held takes it there, and succeeds once
// that memory is released (the pages are never touched: nothing is moved).
TEST(DevicePrimitives, ManagedMemoryBeyondTheCardIsRefused) {
  ISPH_SKIP_WITHOUT_GPU();
  const std::size_t total = device_memory_bytes();
  ASSERT_GT(total, 0u);
  EXPECT_THROW(managed_allocate(total), std::runtime_error);
  const std::size_t half = total / 2;
  void* held = managed_allocate(half);
  EXPECT_THROW(managed_allocate(half), std::runtime_error);
  managed_free(held, half);
  void* again = managed_allocate(half);
  EXPECT_NE(again, nullptr);
  managed_free(again, half);
}
