// The device cell list and neighbour list on the debug device (core/device_emulation.hpp): the host's
// CellList and neighbour_list, reading the positions as a launch does, copied into its memory. The
// GPU's own build (device_neighbour_search.cu) is checked against the same host lists by the device
// tests.
#include <span>

#include "core/device_neighbour_search.hpp"

namespace isph {

template <int D>
void DeviceCellList<D>::build_on_debug_device(const Vec<D>* x, Index n, Real radius, const Periodicity<D>& period) {
  CellList<D> host;
  {
    const EmulatedLaunch launch;  // the positions are in the debug device's memory
    host.build(std::span<const Vec<D>>(x, static_cast<std::size_t>(n)), radius, period);
  }
  const CellListView<D> built = host.view();
  x_ = x;
  radius_ = radius;
  period_ = period;
  grid_ = built.grid;
  cell_start_.assign(std::span<const Index>(built.cell_start, static_cast<std::size_t>(grid_.cells) + 1));
  sorted_.assign(host.order());
}

template <int D>
DeviceNeighbourList debug_device_neighbour_list(const DeviceCellList<D>& cells, Index n, const int* group,
                                                const LevelReach& levels) {
  NeighbourList host;
  {
    const EmulatedLaunch launch;
    host = neighbour_list(cells.view(group, levels), n);
  }
  return {DeviceArray<Index>(host.offset), DeviceArray<Index>(host.index)};
}

template void DeviceCellList<2>::build_on_debug_device(const Vec<2>*, Index, Real, const Periodicity<2>&);
template void DeviceCellList<3>::build_on_debug_device(const Vec<3>*, Index, Real, const Periodicity<3>&);
template DeviceNeighbourList debug_device_neighbour_list<2>(const DeviceCellList<2>&, Index, const int*,
                                                            const LevelReach&);
template DeviceNeighbourList debug_device_neighbour_list<3>(const DeviceCellList<3>&, Index, const int*,
                                                            const LevelReach&);

}  // namespace isph
