// The GPU build of the cell list and the neighbour list (core/device_neighbour_search.hpp).
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_reduce.cuh>
#include <cub/device/device_scan.cuh>
#include <stdexcept>
#include <string>

#include "core/device_neighbour_search.hpp"

namespace isph {
namespace {

void check(cudaError_t err, const char* what) {
  if (err != cudaSuccess)
    throw std::runtime_error(std::string("device neighbour search: ") + what + ": " + cudaGetErrorString(err));
}

// Fills an output array with 0xFF bytes (index -1) before a stage writes it, so that an element the
// stage leaves unwritten cannot pass for a result (the device tests compare every element).
template <class T>
void poison(DeviceArray<T>& a) {
  check(cudaMemset(a.data(), 0xFF, a.size() * sizeof(T)), "memset");
}

template <int D>
struct CopyComponent {
  const Vec<D>* x;
  int d;
  Real* out;
  ISPH_HD void operator()(Index i) const { out[i] = x[i][d]; }
};

template <int D>
struct CellKey {
  CellGrid<D> grid;
  const Vec<D>* x;
  Index* key;
  Index* identity;
  ISPH_HD void operator()(Index i) const {
    key[i] = grid.cell_of(x[i]);
    identity[i] = i;
  }
};

}  // namespace

template <int D>
void DeviceCellList<D>::build(const Vec<D>* x, Index n, Real radius, const Periodicity<D>& period) {
  if (device_emulated()) return build_on_debug_device(x, n, radius, period);
  if (cuda_devices() == 0) throw std::runtime_error("DeviceCellList: no CUDA device is visible");
  x_ = x;
  radius_ = radius;
  period_ = period;
  const Exec gpu{Device::cuda};

  // Bounding box: one min and one max reduction per axis (2D reductions come back to the host).
  Vec<D> lo = Vec<D>::zero(), hi = Vec<D>::zero();
  if (n > 0) {
    component_.grow_to(n);
    extreme_.grow_to(2);
    std::size_t bytes = 0;
    check(cub::DeviceReduce::Min(nullptr, bytes, component_.data(), extreme_.data(), n), "reduce size");
    scratch_.grow_to(bytes);
    for (int d = 0; d < D; ++d) {
      parallel_for(gpu, n, CopyComponent<D>{x, d, component_.data()});
      std::size_t b = scratch_.size();
      check(cub::DeviceReduce::Min(scratch_.data(), b, component_.data(), extreme_.data(), n), "min");
      b = scratch_.size();
      check(cub::DeviceReduce::Max(scratch_.data(), b, component_.data(), extreme_.data() + 1, n), "max");
      const std::vector<Real> e = extreme_.to_host();
      lo[d] = e[0];
      hi[d] = e[1];
    }
  }
  grid_ = make_cell_grid(lo, hi, radius, period);

  // Keys, then a stable radix sort of (key, index): the order of the host's stable counting sort.
  if (key_.size() != static_cast<std::size_t>(n)) {
    key_ = DeviceArray<Index>(n), sorted_key_ = DeviceArray<Index>(n);
    identity_ = DeviceArray<Index>(n), sorted_ = DeviceArray<Index>(n);
  }
  poison(sorted_);
  parallel_for(gpu, n, CellKey<D>{grid_, x, key_.data(), identity_.data()});
  int bits = 1;
  while ((Index{1} << bits) <= grid_.cells && bits < 31) ++bits;
  std::size_t bytes = 0;
  check(cub::DeviceRadixSort::SortPairs(nullptr, bytes, key_.data(), sorted_key_.data(), identity_.data(),
                                        sorted_.data(), n, 0, bits),
        "sort size");
  scratch_.grow_to(bytes);
  bytes = scratch_.size();
  check(cub::DeviceRadixSort::SortPairs(scratch_.data(), bytes, key_.data(), sorted_key_.data(), identity_.data(),
                                        sorted_.data(), n, 0, bits),
        "sort");
  cell_start_.grow_to(static_cast<std::size_t>(grid_.cells) + 1);
  poison(cell_start_);
  parallel_for(gpu, grid_.cells + 1, KeyStarts{sorted_key_.data(), n, cell_start_.data()});
}

template <int D>
DeviceNeighbourList device_neighbour_list(const DeviceCellList<D>& cells, Index n, const int* group,
                                          const LevelReach& levels) {
  if (device_emulated()) return debug_device_neighbour_list(cells, n, group, levels);
  const Exec gpu{Device::cuda};
  DeviceNeighbourList list;
  list.offset = DeviceArray<Index>(static_cast<std::size_t>(n) + 1);
  poison(list.offset);
  DeviceArray<Index> count(n);
  parallel_for(gpu, n, CountNeighbours<D>{cells.view(group, levels), count.data()});
  check(cudaMemset(list.offset.data(), 0, sizeof(Index)), "memset");
  std::size_t bytes = 0;
  check(cub::DeviceScan::InclusiveSum(nullptr, bytes, count.data(), list.offset.data() + 1, n), "scan size");
  DeviceArray<unsigned char> scratch(bytes);
  check(cub::DeviceScan::InclusiveSum(scratch.data(), bytes, count.data(), list.offset.data() + 1, n), "scan");
  Index pairs = 0;
  copy_device_to_host(&pairs, list.offset.data() + n, sizeof(Index));
  list.index = DeviceArray<Index>(static_cast<std::size_t>(pairs));
  poison(list.index);
  parallel_for(gpu, n, FillNeighbours<D>{cells.view(group, levels), list.offset.data(), list.index.data()});
  return list;
}

template class DeviceCellList<2>;
template class DeviceCellList<3>;
template DeviceNeighbourList device_neighbour_list<2>(const DeviceCellList<2>&, Index, const int*, const LevelReach&);
template DeviceNeighbourList device_neighbour_list<3>(const DeviceCellList<3>&, Index, const int*, const LevelReach&);

}  // namespace isph
