// The cell list and neighbour list built on the GPU against the host's, on fresh random particle
// clouds: the same order by cell and the same CSR list, element by element (one algorithm, whose
// primitives differ: thrust's sort and scan on the GPU). Skipped without a CUDA device.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/neighbour_search.hpp"
#include "gpu_skip.hpp"

using namespace isph;

namespace {

// A jittered lattice with a few particles outside it (spray), shuffled so that the sort has work.
std::vector<Vec<2>> random_cloud(unsigned seed, int columns, int rows, Real dx) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-0.3, 0.3);
  std::vector<Vec<2>> x;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < rows; ++j) x.push_back({{(i + 0.5 + u(rng)) * dx, (j + 0.5 + u(rng)) * dx}});
  for (int k = 0; k < 20; ++k) x.push_back({{columns * dx * (0.5 + u(rng)), rows * dx * (1.5 + u(rng))}});
  std::shuffle(x.begin(), x.end(), rng);
  return x;
}

template <class T>
void expect_equal(const StateVector<T>& host, const StateVector<T>& d, const char* what) {
  ASSERT_EQ(d.size(), host.size()) << what;
  std::size_t mismatches = 0;
  for (std::size_t k = 0; k < host.size(); ++k) mismatches += d[k] != host[k];
  EXPECT_EQ(mismatches, 0u) << what;
}

}  // namespace

TEST(DeviceNeighbours, CellListAndNeighbourListMatchTheHost) {
  ISPH_SKIP_WITHOUT_GPU();
  const Real dx = 0.01, radius = 2.4 * dx;
  for (unsigned seed : {31u, 32u, 33u}) {
    for (bool periodic : {false, true}) {
      const auto x = random_cloud(seed, 90, 40, dx);
      const auto n = static_cast<Index>(x.size());
      Periodicity<2> period;
      if (periodic) {
        period.axis[0] = true;
        period.lo[0] = 0;
        period.length[0] = 90 * dx;
      }
      std::vector<Vec<2>> inside = x;  // a periodic axis needs every particle inside the period
      for (auto& p : inside) p = period.wrap(p);
      std::vector<int> group(n);
      for (Index i = 0; i < n; ++i) group[i] = i % 7 == 0;

      CellList<2> host;
      host.build(inside, radius, period);
      const NeighbourList host_list = neighbour_list(host, n, group.data());

      const StateVector<Vec<2>> on_device(inside.begin(), inside.end(), StateAllocator<Vec<2>>(true));
      const StateVector<int> dgroup(group.begin(), group.end(), StateAllocator<int>(true));
      CellList<2> device(Exec{Device::cuda});
      device.build(on_device.data(), n, radius, period);
      expect_equal(host.order(), device.order(), "order");
      const NeighbourList device_list = neighbour_list(device, n, dgroup.data());
      expect_equal(host_list.offset, device_list.offset, "offset");
      expect_equal(host_list.index, device_list.index, "index");
    }
  }
}
