#pragma once
// The cell-linked list and the CSR neighbour list built on the GPU from positions in device memory
// (CUB radix sort by cell key, cell ranges by binary search, counts and fills by the host's functors).
// The grid, the stable order by cell and the list are those of CellList and neighbour_list
// (core/neighbour_search.hpp), so both devices see the same neighbours in the same order.
// Without the CUDA backend, or without a device, build() throws std::runtime_error. On the debug device
// (core/device_emulation.hpp) the host's CellList and neighbour_list build them, copied to its memory.
#include "core/device_memory.hpp"
#include "core/neighbour_search.hpp"

namespace isph {

template <int D>
class DeviceCellList {
 public:
  // x: n positions in device memory, kept by pointer until the next build.
  void build(const Vec<D>* x, Index n, Real radius, const Periodicity<D>& period = {});
  // Device pointers, for functors launched on the device.
  CellListView<D> view(const int* group = nullptr, const LevelReach& levels = {}) const {
    return {grid_, cell_start_.data(), sorted_.data(), x_, group, radius_ * radius_, period_, levels};
  }
  const DeviceArray<Index>& order() const { return sorted_; }  // particle indices ordered by cell

 private:
  void build_on_debug_device(const Vec<D>* x, Index n, Real radius, const Periodicity<D>& period);

  CellGrid<D> grid_;
  Periodicity<D> period_;
  const Vec<D>* x_ = nullptr;
  Real radius_ = 0;
  DeviceArray<Index> key_, sorted_key_, identity_, sorted_, cell_start_;
  DeviceArray<Real> component_, extreme_;
  DeviceArray<unsigned char> scratch_;  // CUB's temporary storage
};

struct DeviceNeighbourList {
  DeviceArray<Index> offset;  // n + 1
  DeviceArray<Index> index;   // offset[n] pairs
};

template <int D>
DeviceNeighbourList device_neighbour_list(const DeviceCellList<D>& cells, Index n, const int* group = nullptr,
                                          const LevelReach& levels = {});
template <int D>
DeviceNeighbourList debug_device_neighbour_list(const DeviceCellList<D>& cells, Index n, const int* group,
                                                const LevelReach& levels);

}  // namespace isph
