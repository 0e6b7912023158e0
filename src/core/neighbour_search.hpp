#pragma once
// Cell-linked list neighbour search. Particles are bucketed into cells of size >= the search
// radius by a stable counting sort; a particle's neighbours are found in the 3^D surrounding
// cells. On a periodic axis the grid spans exactly one period and the cell block wraps around, with
// pair vectors taken as minimum images (core/periodic.hpp). The neighbour list is CSR (offset,
// index), built by two gather loops (count, fill) through the common launcher, so it runs wherever
// the other particle loops run.
#include <algorithm>
#include <span>
#include <stdexcept>
#include <vector>

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

template <int D>
class CellList {
 public:
  // Buckets x into cells of edge `radius` (at least) over the particles' bounding box; on a periodic
  // axis, over the period (which must hold at least three cells, and every x must lie inside it).
  void build(std::span<const Vec<D>> x, Real radius, const Periodicity<D>& period = {}) {
    x_ = x.data();
    radius_ = radius;
    period_ = period;
    Vec<D> lo, hi;
    for (int d = 0; d < D; ++d) {
      lo[d] = x.empty() ? 0 : x[0][d];
      hi[d] = lo[d];
    }
    for (const auto& p : x)
      for (int d = 0; d < D; ++d) {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
    grid_ = make_cell_grid(lo, hi, radius, period);
    cell_start_.assign(static_cast<std::size_t>(grid_.cells) + 1, 0);
    std::vector<Index> cell(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      cell[i] = grid_.cell_of(x[i]);
      ++cell_start_[cell[i] + 1];
    }
    inclusive_scan(Exec{}, cell_start_.data() + 1, grid_.cells);
    sorted_.resize(x.size());
    std::vector<Index> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < x.size(); ++i) sorted_[fill[cell[i]]++] = static_cast<Index>(i);
  }

  // Particle indices ordered by cell (stable): the permutation that sorts particles by cell.
  const std::vector<Index>& order() const { return sorted_; }

  CellListView<D> view(const int* group = nullptr, const LevelReach& levels = {}) const {
    return {grid_, cell_start_.data(), sorted_.data(), x_, group, radius_ * radius_, period_, levels};
  }

 private:
  CellGrid<D> grid_;
  Periodicity<D> period_;
  std::vector<Index> cell_start_;
  std::vector<Index> sorted_;
  const Vec<D>* x_ = nullptr;
  Real radius_ = 0;
};

// CSR neighbour list: the neighbours of i are index[offset[i] .. offset[i+1]).
struct NeighbourList {
  std::vector<Index> offset;
  std::vector<Index> index;
  Index pairs() const { return static_cast<Index>(index.size()); }
};

// The CSR list of all pairs of a built cell list (and in the same group, if given), on the host.
template <int D>
NeighbourList neighbour_list(const CellListView<D>& cells, Index n) {
  NeighbourList list;
  list.offset.assign(static_cast<std::size_t>(n) + 1, 0);
  const Exec host{};
  parallel_for(host, n, CountNeighbours<D>{cells, list.offset.data() + 1});
  inclusive_scan(host, list.offset.data() + 1, n);
  list.index.resize(static_cast<std::size_t>(list.offset[n]));
  parallel_for(host, n, FillNeighbours<D>{cells, list.offset.data(), list.index.data()});
  return list;
}
template <int D>
NeighbourList neighbour_list(const CellList<D>& cells, Index n, const int* group = nullptr,
                             const LevelReach& levels = {}) {
  return neighbour_list(cells.view(group, levels), n);
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
