// The device neighbour search in a build without CUDA: the debug device's, else building says so.
#include <stdexcept>

#include "core/device_neighbour_search.hpp"

#if !defined(ISPH_HAVE_CUDA)
namespace isph {

template <int D>
void DeviceCellList<D>::build(const Vec<D>* x, Index n, Real radius, const Periodicity<D>& period) {
  if (!device_emulated()) throw std::runtime_error("DeviceCellList: this build has no CUDA backend");
  build_on_debug_device(x, n, radius, period);
}

template <int D>
DeviceNeighbourList device_neighbour_list(const DeviceCellList<D>& cells, Index n, const int* group,
                                          const LevelReach& levels) {
  if (!device_emulated()) throw std::runtime_error("device_neighbour_list: this build has no CUDA backend");
  return debug_device_neighbour_list(cells, n, group, levels);
}

template class DeviceCellList<2>;
template class DeviceCellList<3>;
template DeviceNeighbourList device_neighbour_list<2>(const DeviceCellList<2>&, Index, const int*, const LevelReach&);
template DeviceNeighbourList device_neighbour_list<3>(const DeviceCellList<3>&, Index, const int*, const LevelReach&);

}  // namespace isph
#endif
