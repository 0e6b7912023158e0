#include "poisson/manufactured_system.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace isph {

ManufacturedSystem manufactured_ppe_system(int n, int stencil) {
  if (stencil != 5 && stencil != 9 && stencil != 21)
    throw std::invalid_argument("manufactured_ppe_system: stencil must be 5, 9 or 21");
  const int r2max = stencil == 5 ? 1 : stencil == 9 ? 2 : 5;
  const int ring = stencil == 21 ? 2 : 1;
  std::vector<std::pair<int, int>> offsets;
  for (int dj = -2; dj <= 2; ++dj)
    for (int di = -2; di <= 2; ++di)
      if ((di || dj) && di * di + dj * dj <= r2max) offsets.emplace_back(di, dj);

  ManufacturedSystem p;
  const int N = n * n;
  p.A.rows = N;
  p.A.row_offset.resize(N + 1);
  p.A.row_offset[0] = 0;
  p.A.col.reserve(static_cast<std::size_t>(N) * (offsets.size() + 1));
  p.A.val.reserve(p.A.col.capacity());
  p.x_star.resize(N);
  const double h = 1.0 / (n - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i * h, y = j * h;
      p.x_star[j * n + i] = std::sin(std::numbers::pi * x) * std::cos(2 * std::numbers::pi * y) + x * y + 1.0;
    }
  const double ex = 1.0 / std::sqrt(1.25), ey = 0.5 / std::sqrt(1.25);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int row = j * n + i;
      if (j >= n - ring || row % 97 == 0) {
        p.A.col.push_back(row);
        p.A.val.push_back(1.0);
      } else {
        const std::size_t at = p.A.col.size();
        p.A.col.push_back(row);
        p.A.val.push_back(0.0);
        double diag = 0;
        for (const auto& [di, dj] : offsets) {
          if (i + di < 0 || i + di >= n || j + dj < 0 || j + dj >= n) continue;
          const double r2 = di * di + dj * dj;
          const double cos_theta = (di * ex + dj * ey) / std::sqrt(r2);
          const double jitter = 1.0 + 0.2 * std::sin(12.9898 * row + 78.233 * (5 * dj + di));
          const double a = -(1.0 / r2) * (1.0 + 0.6 * cos_theta) * jitter;
          p.A.col.push_back((j + dj) * n + (i + di));
          p.A.val.push_back(a);
          diag -= a;
        }
        p.A.val[at] = diag;
      }
      p.A.row_offset[row + 1] = static_cast<int>(p.A.col.size());
    }
  p.b.assign(N, 0.0);
#pragma omp parallel for schedule(static)
  for (int r = 0; r < N; ++r)
    for (int k = p.A.row_offset[r]; k < p.A.row_offset[r + 1]; ++k) p.b[r] += p.A.val[k] * p.x_star[p.A.col[k]];
  return p;
}

double relative_difference(const std::vector<double>& x, const std::vector<double>& ref) {
  double d = 0, s = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    d += (x[i] - ref[i]) * (x[i] - ref[i]);
    s += ref[i] * ref[i];
  }
  return std::sqrt(d / s);
}

}  // namespace isph
