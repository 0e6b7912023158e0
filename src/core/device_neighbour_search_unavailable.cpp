// The device neighbour search in a build without CUDA: building says so.
#include <stdexcept>

#include "core/device_neighbour_search.hpp"

#if !defined(ISPH_HAVE_CUDA)
namespace isph {

template <int D>
void DeviceCellList<D>::build(const Vec<D>*, Index, Real, const Periodicity<D>&) {
  throw std::runtime_error("DeviceCellList: this build has no CUDA backend");
}

template <int D>
DeviceNeighbourList device_neighbour_list(const DeviceCellList<D>&, Index, const int*) {
  throw std::runtime_error("device_neighbour_list: this build has no CUDA backend");
}

template class DeviceCellList<2>;
template class DeviceCellList<3>;
template DeviceNeighbourList device_neighbour_list<2>(const DeviceCellList<2>&, Index, const int*);
template DeviceNeighbourList device_neighbour_list<3>(const DeviceCellList<3>&, Index, const int*);

}  // namespace isph
#endif
