#pragma once
// Cell-linked list neighbour search. Particles are bucketed into cells of size >= the search
// radius by a stable sort by cell; a particle's neighbours are found in the 3^D surrounding
// cells. On a periodic axis the grid spans exactly one period and the cell block wraps around, with
// pair vectors taken as minimum images (core/periodic.hpp). The neighbour list is CSR (offset,
// index), built by two gather loops (count, fill) through the common launcher, so it runs wherever
// the other particle loops run.
#include <algorithm>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/device_memory.hpp"
#include "core/parallel.hpp"
#include "core/periodic.hpp"
#include "core/types.hpp"

namespace isph {

template <int D>
struct CellGrid {
  Vec<D> origin;
  Vec<D> cell_size;
  int dims[D];
  Index cells = 0;

  ISPH_HD int coord(const Vec<D>& x, int d) const {
    int c = static_cast<int>(floor((x[d] - origin[d]) / cell_size[d]));
    return c < 0 ? 0 : (c >= dims[d] ? dims[d] - 1 : c);
  }
  ISPH_HD Index flat(const int* c) const {
    Index k = c[D - 1];
    for (int d = D - 2; d >= 0; --d) k = k * dims[d] + c[d];
    return k;
  }
  ISPH_HD Index cell_of(const Vec<D>& x) const {
    int c[D];
    for (int d = 0; d < D; ++d) c[d] = coord(x, d);
    return flat(c);
  }
};

// The reach of each pair in a particle set with more than one resolution (kernels/operators.hpp
// KernelTable): particles carry a level, reach2[l] is the squared kernel support of level l (ascending),
// and a pair is within reach when |r_ij|^2 < reach2[max(level_i, level_j)]. Without levels every pair
// within the cell list's radius is.
inline constexpr int kMaxLevels = 4;
struct LevelReach {
  const unsigned char* level = nullptr;
  Real reach2[kMaxLevels] = {};
  ISPH_HD bool within(Index i, Index j, Real r2) const {
    if (!level) return true;
    const int l = level[i] > level[j] ? level[i] : level[j];
    return r2 < reach2[l];
  }
};

// A read-only view of a built cell list, usable inside functors.
template <int D>
struct CellListView {
  CellGrid<D> grid;
  const Index* cell_start;  // cells + 1 offsets into `sorted`
  const Index* sorted;      // particle indices ordered by cell
  const Vec<D>* x;
  const int* group;  // optional: only pairs with equal group are neighbours
  Real radius2;
  Periodicity<D> period;
  LevelReach levels = {};  // optional: each pair's own reach, at most the radius

  // Calls f(j, r_ij) for every j != i with |r_ij| < radius (and within the pair's reach),
  // r_ij = x_i - x_j (minimum image).
  template <class F>
  ISPH_HD void for_each_neighbour(Index i, F&& f) const {
    for_each_near(x[i], [&](Index j, const Vec<D>& r) {
      if (j != i && !(group && group[j] != group[i]) && levels.within(i, j, norm2(r))) f(j, r);
    });
  }

  // Calls f(j, r) for every particle j with |r| < radius, r = point - x_j (minimum image), the point
  // being anywhere (not necessarily a particle).
  template <class F>
  ISPH_HD void for_each_near(const Vec<D>& point, F&& f) const {
    int lo[D], hi[D], c[D];
    for (int d = 0; d < D; ++d) {
      const int ci = grid.coord(point, d);
      if (period.axis[d]) {  // wraps: dims >= 3 on a periodic axis, so the three cells differ
        lo[d] = ci - 1;
        hi[d] = ci + 1;
      } else {
        lo[d] = ci > 0 ? ci - 1 : 0;
        hi[d] = ci + 1 < grid.dims[d] ? ci + 1 : grid.dims[d] - 1;
      }
      c[d] = lo[d];
    }
    while (true) {
      int wrapped[D];
      for (int d = 0; d < D; ++d) wrapped[d] = (c[d] + grid.dims[d]) % grid.dims[d];
      const Index cell = grid.flat(wrapped);
      for (Index k = cell_start[cell]; k < cell_start[cell + 1]; ++k) {
        const Index j = sorted[k];
        const Vec<D> r = period.delta(point, x[j]);
        if (norm2(r) < radius2) f(j, r);
      }
      int d = 0;  // odometer over the 3^D block
      while (d < D && ++c[d] > hi[d]) {
        c[d] = lo[d];
        ++d;
      }
      if (d == D) break;
    }
  }
};

template <int D>
struct CountNeighbours {
  CellListView<D> cells;
  Index* count;
  ISPH_HD void operator()(Index i) const {
    Index n = 0;
    cells.for_each_neighbour(i, [&](Index, const Vec<D>&) { ++n; });
    count[i] = n;
  }
};

template <int D>
struct FillNeighbours {
  CellListView<D> cells;
  const Index* offset;
  Index* index;
  ISPH_HD void operator()(Index i) const {
    Index k = offset[i];
    cells.for_each_neighbour(i, [&](Index j, const Vec<D>&) { index[k++] = j; });
  }
};

// The grid of cells of edge `radius` (at least) over the box [lo, hi] of the particles; on a periodic
// axis, over the period (which must hold at least three cells).
template <int D>
CellGrid<D> make_cell_grid(const Vec<D>& lo, const Vec<D>& hi, Real radius, const Periodicity<D>& period) {
  if (!(radius > 0)) throw std::invalid_argument("CellList: search radius must be positive");
  CellGrid<D> grid;
  grid.origin = lo;
  grid.cells = 1;
  for (int d = 0; d < D; ++d) {
    if (period.axis[d]) {
      grid.origin[d] = period.lo[d];
      grid.dims[d] = static_cast<int>(period.length[d] / radius);
      if (grid.dims[d] < 3) throw std::invalid_argument("CellList: a periodic length must be at least 3 search radii");
      grid.cell_size[d] = period.length[d] / grid.dims[d];
    } else {
      grid.cell_size[d] = radius;
      grid.dims[d] = std::max(1, static_cast<int>((hi[d] - lo[d]) / radius) + 1);
    }
    grid.cells *= grid.dims[d];
  }
  return grid;
}

// The coordinate d of each position, as a functor Index -> Real (the bounding box's reductions).
template <int D>
struct PositionComponent {
  const Vec<D>* x;
  int d;
  ISPH_HD Real operator()(Index i) const { return x[i][d]; }
};

// Each particle's cell and its own index: the keys and values of the sort by cell.
template <int D>
struct CellKeys {
  CellGrid<D> grid;
  const Vec<D>* x;
  Index* key;
  Index* particle;
  ISPH_HD void operator()(Index i) const {
    key[i] = grid.cell_of(x[i]);
    particle[i] = i;
  }
};

// exec's device, with launches on the default stream that each wait: the primitives' sorts and scans
// run there, so the launches between them must too.
inline Exec waiting(const Exec& exec) { return Exec{exec.device, nullptr, true, exec.parallel_from}; }

// The cell list, built by the launcher's primitives (reductions, a launch, a stable sort by key, a
// launch of binary searches) on the device given at construction, in its memory: managed memory on the
// cuda device. Host, debug device and GPU thus run one algorithm; the order is the stable order by
// cell on each (Cabana's LinkedCellList::build has the same shape).
template <int D>
class CellList {
 public:
  explicit CellList(const Exec& exec = {})
      : exec_(waiting(exec)), key_(memory()), sorted_(memory()), cell_start_(memory()) {}

  // Buckets the n positions x (readable where exec runs) into cells of edge `radius` (at least) over
  // their bounding box; on a periodic axis, over the period (which must hold at least three cells,
  // and every x must lie inside it). x is kept by pointer until the next build.
  void build(const Vec<D>* x, Index n, Real radius, const Periodicity<D>& period = {}) {
    x_ = x;
    radius_ = radius;
    period_ = period;
    Vec<D> lo = Vec<D>::zero(), hi = Vec<D>::zero();
    for (int d = 0; d < D && n > 0; ++d) {
      const PositionComponent<D> component{x, d};
      lo[d] = parallel_reduce(exec_, n, std::numeric_limits<Real>::infinity(), component, MinOf{});
      hi[d] = parallel_reduce(exec_, n, -std::numeric_limits<Real>::infinity(), component, MaxOf{});
    }
    grid_ = make_cell_grid(lo, hi, radius, period);
    resize_for_overwrite(key_, static_cast<std::size_t>(n));
    resize_for_overwrite(sorted_, static_cast<std::size_t>(n));
    parallel_for(exec_, n, CellKeys<D>{grid_, x, key_.data(), sorted_.data()});
    stable_sort_by_key(exec_, key_.data(), sorted_.data(), n, grid_.cells);
    resize_for_overwrite(cell_start_, static_cast<std::size_t>(grid_.cells) + 1);
    parallel_for(exec_, grid_.cells + 1, KeyStarts{key_.data(), n, cell_start_.data()});
  }
  void build(std::span<const Vec<D>> x, Real radius, const Periodicity<D>& period = {}) {
    build(x.data(), static_cast<Index>(x.size()), radius, period);
  }

  // Particle indices ordered by cell (stable): the permutation that sorts particles by cell.
  const StateVector<Index>& order() const { return sorted_; }
  const Exec& exec() const { return exec_; }

  CellListView<D> view(const int* group = nullptr, const LevelReach& levels = {}) const {
    return {grid_, cell_start_.data(), sorted_.data(), x_, group, radius_ * radius_, period_, levels};
  }

 private:
  StateAllocator<Index> memory() const { return StateAllocator<Index>(exec_.device == Device::cuda); }

  Exec exec_;
  CellGrid<D> grid_;
  Periodicity<D> period_;
  StateVector<Index> key_;  // each particle's cell, sorted by the build
  StateVector<Index> sorted_;
  StateVector<Index> cell_start_;
  const Vec<D>* x_ = nullptr;
  Real radius_ = 0;
};

// CSR neighbour list: the neighbours of i are index[offset[i] .. offset[i+1]), in the memory of the
// device that built it.
struct NeighbourList {
  StateVector<Index> offset;
  StateVector<Index> index;
  Index pairs() const { return static_cast<Index>(index.size()); }
};

// offset[0] = 0, written by a launch (the offsets may be device memory).
struct FirstOffset {
  Index* offset;
  ISPH_HD void operator()(Index) const { offset[0] = 0; }
};

// Rebuilds `list` as the CSR list of all pairs of a built cell list (and in the same group, if given): a
// count, a scan and a fill, launched on exec, into the list's own memory (reused while it is large
// enough: no allocation per step).
template <int D>
void fill_neighbour_list(const Exec& on, const CellListView<D>& cells, Index n, NeighbourList& list) {
  const Exec exec = waiting(on);
  resize_for_overwrite(list.offset, static_cast<std::size_t>(n) + 1);
  parallel_for(exec, 1, FirstOffset{list.offset.data()});
  parallel_for(exec, n, CountNeighbours<D>{cells, list.offset.data() + 1});
  inclusive_scan(exec, list.offset.data() + 1, n);
  resize_for_overwrite(list.index, static_cast<std::size_t>(read_back(exec, list.offset.data() + n)));
  parallel_for(exec, n, FillNeighbours<D>{cells, list.offset.data(), list.index.data()});
}
// The same into a new list in the memory of exec's device.
template <int D>
NeighbourList neighbour_list(const Exec& exec, const CellListView<D>& cells, Index n) {
  const StateAllocator<Index> memory(exec.device == Device::cuda);
  NeighbourList list{StateVector<Index>(memory), StateVector<Index>(memory)};
  fill_neighbour_list(exec, cells, n, list);
  return list;
}
template <int D>
NeighbourList neighbour_list(const CellList<D>& cells, Index n, const int* group = nullptr,
                             const LevelReach& levels = {}) {
  return neighbour_list(cells.exec(), cells.view(group, levels), n);
}

// Builds the CSR list of all pairs closer than `radius` (and in the same group, if given; minimum
// image on periodic axes).
template <int D>
NeighbourList build_neighbour_list(const std::vector<Vec<D>>& x, Real radius, const int* group = nullptr,
                                   const Periodicity<D>& period = {}) {
  CellList<D> cells;
  cells.build(x, radius, period);
  return neighbour_list(cells, static_cast<Index>(x.size()), group);
}

}  // namespace isph
