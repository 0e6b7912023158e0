// The debug device's memory (core/device_emulation.hpp): new memory reads as 0xFF bytes, the host's
// touches between launches are counted once per page until the next launch closes the pages again,
// and a launch's own accesses are not counted; and a DeviceArray, there as on a GPU, keeps its
// allocation while what it is given fits. Each check runs in a child process (EXPECT_EXIT), since
// the debug device, once on, stays on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/device_memory.hpp"
#include "core/parallel.hpp"

using namespace isph;

namespace {

struct Fill {
  double* v;
  double value;
  void operator()(Index i) const { v[i] = value; }
};

// Exits 0 when the counts are those described at the top, with a distinct code for each way they are not.
[[noreturn]] void check_touch_counts() {
  enable_device_emulation();
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  const Index n = static_cast<Index>(3 * page / sizeof(double));  // three pages
  auto* v = static_cast<double*>(device_allocate(n * sizeof(double)));
  const long long start = emulated_host_touches();
  unsigned char first = 0;
  {
    const EmulatedLaunch open;
    std::memcpy(&first, v, 1);
  }
  if (first != 0xFF) std::_Exit(2);                     // new memory is poisoned
  if (emulated_host_touches() != start) std::_Exit(3);  // inside a launch: not counted
  parallel_for(Exec{Device::cuda}, n, Fill{v, 1.0});    // a launch on the debug device
  if (emulated_host_touches() != start) std::_Exit(4);
  for (Index i = 0; i < n; ++i) v[i] += 1;                  // the host, between launches
  if (emulated_host_touches() != start + 3) std::_Exit(5);  // each page once
  v[0] += 1;
  if (emulated_host_touches() != start + 3) std::_Exit(6);  // still open until the next launch
  parallel_for(Exec{Device::cuda}, 1, Fill{v, 0.0});
  v[n - 1] += 1;
  if (emulated_host_touches() != start + 4) std::_Exit(7);  // closed again by the launch
  if (v[n - 1] != 3.0 || v[0] != 0.0) std::_Exit(8);        // and the values are the program's
  if (!device_accessible(v) || device_accessible(&first)) std::_Exit(9);
  std::_Exit(0);
}

// Exits 0 when a DeviceArray refilled with fewer or a few more elements keeps its allocation (the PPE's
// copy, whose size changes every step), holds what it was given, and reallocates only past its room.
[[noreturn]] void check_array_reuse() {
  enable_device_emulation();
  const auto filled = [](std::size_t n) {
    std::vector<int> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<int>(3 * i + n);
    return v;
  };
  DeviceArray<int> a;
  a.assign(filled(1000));
  const int* first = a.data();
  for (std::size_t n : {500, 1200, 1000}) {
    a.assign(filled(n));
    if (a.data() != first) std::_Exit(2);
    if (a.size() != n || a.to_host() != filled(n)) std::_Exit(3);
  }
  a.assign(filled(1300));  // beyond 1000 + 1000/4
  if (a.size() != 1300 || a.to_host() != filled(1300)) std::_Exit(4);
  std::_Exit(0);
}

}  // namespace

TEST(DebugDeviceMemory, DeviceArrayKeepsItsAllocationWhileTheDataFits) {
  EXPECT_EXIT(check_array_reuse(), ::testing::ExitedWithCode(0), "");
}

TEST(DebugDeviceMemory, CountsTheHostsTouchesBetweenLaunchesOncePerPage) {
  EXPECT_EXIT(check_touch_counts(), ::testing::ExitedWithCode(0), "");
}
