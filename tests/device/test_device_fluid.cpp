// The ISPH stages that build the PPE, on the GPU against the host, on fresh random fluid blocks over
// a wall: the gradient correction, the corrected divergence of u*, and the PPE rows (matrix, right-hand
// side, wall moments), each within a relative 1e-12, the column indices exactly; and the coupled
// step's own stages on random arrays. The device outputs
// are poisoned with NaN bytes first. This file is compiled by nvcc in builds with the CUDA backend, so
// that it can launch the functors on the device; it is skipped without a GPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "core/neighbour_search.hpp"
#include "core/ordered_sum.hpp"
#include "core/parallel.hpp"
#include "gpu_skip.hpp"
#include "poisson/ppe_assembly.hpp"
#include "sim/fluid_functors.hpp"
#include "structure/interaction.hpp"
#include "structure/tlsph_functors.hpp"

using namespace isph;

namespace {

template <class T>
DeviceArray<T> poisoned(std::size_t n) {
  std::vector<T> h(n);
  std::memset(static_cast<void*>(h.data()), 0xFF, n * sizeof(T));
  return DeviceArray<T>(h);
}

double scalar_difference(double a, double b) { return std::abs(a - b); }
template <class T>
double scalar_difference(const T& a, const T& b) {  // Vec or Mat: largest component difference
  double d = 0;
  const auto* pa = reinterpret_cast<const Real*>(&a);
  const auto* pb = reinterpret_cast<const Real*>(&b);
  for (std::size_t k = 0; k < sizeof(T) / sizeof(Real); ++k) d = std::max(d, std::abs(pa[k] - pb[k]));
  return d;
}
double magnitude(double a) { return std::abs(a); }
template <class T>
double magnitude(const T& a) {
  double m = 0;
  const auto* p = reinterpret_cast<const Real*>(&a);
  for (std::size_t k = 0; k < sizeof(T) / sizeof(Real); ++k) m = std::max(m, std::abs(p[k]));
  return m;
}

// Largest difference over the largest magnitude of the host values (NaN compares as a failure).
template <class T>
double relative_difference(const std::vector<T>& host, const DeviceArray<T>& device) {
  const std::vector<T> d = device.to_host();
  double worst = 0, scale = 0;
  for (std::size_t k = 0; k < host.size(); ++k) {
    const double diff = scalar_difference(d[k], host[k]);
    if (!(diff == diff)) return INFINITY;
    worst = std::max(worst, diff);
    scale = std::max(scale, magnitude(host[k]));
  }
  return scale > 0 ? worst / scale : worst;
}

}  // namespace

TEST(DeviceFluid, PpeAssemblyStagesMatchTheHost) {
  ISPH_SKIP_WITHOUT_GPU();
#if defined(__CUDACC__)
  for (unsigned seed : {41u, 42u, 43u}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Real> jitter(-0.2, 0.2), uniform(-1.0, 1.0);
    const Real dx = 0.1, density = 1000, dt = 1e-3;
    const Vec<2> gravity{{0.0, -9.81}};
    std::vector<Vec<2>> x, u;
    std::vector<FluidKind> kind;
    for (int i = 0; i < 40; ++i)
      for (int j = -3; j < 25; ++j) {
        const bool wall = j < 0;
        x.push_back(Vec<2>{{(i + 0.5 + (wall ? 0 : jitter(rng))) * dx, (j + 0.5 + (wall ? 0 : jitter(rng))) * dx}});
        u.push_back(Vec<2>{{uniform(rng), uniform(rng)}});
        kind.push_back(wall ? FluidKind::wall : FluidKind::fluid);
      }
    const auto n = static_cast<Index>(x.size());
    std::vector<Real> volume(n, dx * dx), alpha(n), depth(n, 0);
    std::vector<Vec<2>> wall_velocity(n), wall_acceleration(n), wall_normal(n, Vec<2>::zero()),
        normal(n, Vec<2>::zero());
    std::vector<SurfaceClass> cls(n, SurfaceClass::interior);
    for (Index a = 0; a < n; ++a) {
      wall_velocity[a] = Vec<2>{{0.1 * uniform(rng), 0.0}};
      wall_acceleration[a] = Vec<2>{{uniform(rng), uniform(rng)}};
      const Real y = x[a][1];
      alpha[a] = kind[a] == FluidKind::wall ? 1.0 : (y > 2.3 ? 0.0 : (y > 2.1 ? 0.5 : 1.0));
      if (alpha[a] == 0) cls[a] = SurfaceClass::surface;
      if (alpha[a] < 1) normal[a] = Vec<2>{{0.6, 0.8}};
      if (kind[a] == FluidKind::wall) {
        wall_normal[a] = Vec<2>{{0.0, 1.0}};
        depth[a] = -y;
      }
    }
    const auto kernel = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2 * dx);
    const NeighbourList nl = build_neighbour_list<2>(x, kernel.support());
    std::vector<int> row_offset(n + 1);
    for (Index a = 0; a <= n; ++a) row_offset[a] = a + nl.offset[a];
    const std::size_t entries = static_cast<std::size_t>(row_offset[n]);

    // Host.
    const Exec host{};
    const OperatorView<2> op{n, x.data(), volume.data(), nl.offset.data(), nl.index.data(), kernel};
    const FluidView<2> view{
        op, kind.data(), wall_velocity.data(), wall_acceleration.data(), wall_normal.data(), depth.data(), dx};
    std::vector<Mat<2>> L(n);
    std::vector<Real> div(n);
    std::vector<int> col(entries);
    std::vector<double> val(entries), rhs(n);
    std::vector<Vec<2>> moment(n);
    parallel_for(host, n, GradientCorrection<2>{op, L.data()});
    parallel_for(host, n, CorrectedDivergence<2>{op, L.data(), u.data(), div.data()});
    parallel_for(host, n,
                 PpeRowFill<2>{view, L.data(), alpha.data(), div.data(), density, dt, gravity, cls.data(),
                               normal.data(), true, -1, col.data(), val.data(), rhs.data(), moment.data()});

    // Device: the same functors on device copies of the same inputs.
    const Exec gpu{Device::cuda};
    DeviceArray<Vec<2>> dx_(x), du(u), dwall_velocity(wall_velocity), dwall_acceleration(wall_acceleration),
        dwall_normal(wall_normal), dnormal(normal);
    DeviceArray<Real> dvolume(volume), dalpha(alpha), ddepth(depth);
    DeviceArray<Index> doffset({nl.offset.begin(), nl.offset.end()}), dindex({nl.index.begin(), nl.index.end()});
    DeviceArray<FluidKind> dkind(kind);
    DeviceArray<SurfaceClass> dcls(cls);
    auto dL = poisoned<Mat<2>>(n);
    auto ddiv = poisoned<Real>(n);
    auto dcol = poisoned<int>(entries);
    auto dval = poisoned<double>(entries);
    auto drhs = poisoned<double>(n);
    auto dmoment = poisoned<Vec<2>>(n);
    const OperatorView<2> dop{n, dx_.data(), dvolume.data(), doffset.data(), dindex.data(), kernel};
    const FluidView<2> dview{
        dop, dkind.data(), dwall_velocity.data(), dwall_acceleration.data(), dwall_normal.data(), ddepth.data(), dx};
    parallel_for(gpu, n, GradientCorrection<2>{dop, dL.data()});
    parallel_for(gpu, n, CorrectedDivergence<2>{dop, dL.data(), du.data(), ddiv.data()});
    parallel_for(gpu, n,
                 PpeRowFill<2>{dview, dL.data(), dalpha.data(), ddiv.data(), density, dt, gravity, dcls.data(),
                               dnormal.data(), true, -1, dcol.data(), dval.data(), drhs.data(), dmoment.data()});

    EXPECT_LT(relative_difference(L, dL), 1e-12) << "gradient correction, seed " << seed;
    EXPECT_LT(relative_difference(div, ddiv), 1e-12) << "divergence, seed " << seed;
    EXPECT_EQ(dcol.to_host(), col) << "PPE columns, seed " << seed;
    EXPECT_LT(relative_difference(val, dval), 1e-12) << "PPE values, seed " << seed;
    EXPECT_LT(relative_difference(rhs, drhs), 1e-12) << "PPE right-hand side, seed " << seed;
    EXPECT_LT(relative_difference(moment, dmoment), 1e-12) << "wall moments, seed " << seed;
  }
#else
  FAIL() << "a CUDA device is visible but this test was not compiled by nvcc";
#endif
}

// The coupled step's own stages on the GPU against the host, on fresh random arrays, the device outputs
// poisoned first: alpha = f/rho (InteractionAcceleration), the chord velocity and a_s (ChordMotion), the
// ramped interaction field with the fluid's impedance and Velocity-Verlet's stored acceleration
// (SetInteraction, the impedance rate from InteractionAcceleration on matrices), the force on
// the structure (ForceComponent, summed by ordered_sum), and the walls gathered as obstacles (MarkWalls,
// inclusive_scan, GatherWalls). Each within a relative 1e-12; the walls' places and points exactly.
TEST(DeviceFluid, CouplingStagesMatchTheHost) {
  ISPH_SKIP_WITHOUT_GPU();
  const Exec gpu{Device::cuda}, host{};
  for (unsigned seed : {11u, 12u}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Real> u(-1.0, 1.0);
    const Index n = 3000 + 500 * static_cast<Index>(seed);
    const auto vectors = [&] {
      std::vector<Vec<2>> v(n);
      for (auto& e : v) e = {{u(rng), u(rng)}};
      return v;
    };
    const auto positive = [&] {
      std::vector<Real> v(n);
      for (auto& e : v) e = 1.5 + u(rng);
      return v;
    };
    const std::vector<Vec<2>> force = vectors(), x = vectors(), x_old = vectors(), v_mean = vectors(), from = vectors(),
                              to = vectors(), interaction0 = vectors(), acc0 = vectors(), v = vectors();
    std::vector<Mat<2>> impedance(n);
    for (auto& z : impedance) z = outer(Vec<2>{{u(rng), u(rng)}}, Vec<2>{{u(rng), u(rng)}}) + Mat<2>::identity();
    const std::vector<Real> density = positive(), volume = positive();
    std::vector<FluidKind> kind(n);
    for (auto& k : kind) k = static_cast<FluidKind>(std::uniform_int_distribution<int>(0, 2)(rng));
    const Real inverse_dt = 1.0 / (1e-4 * (1.5 + u(rng))), s = 0.5 * (1 + u(rng));

    // the host
    std::vector<Vec<2>> alpha(n), v_new(n), a_new(n), interaction = interaction0, acc = acc0;
    std::vector<Mat<2>> rate(n);
    parallel_for(host, n, InteractionAcceleration<2>{force.data(), density.data(), alpha.data()});
    parallel_for(host, n, InteractionAcceleration<2, Mat<2>>{impedance.data(), density.data(), rate.data()});
    parallel_for(host, n,
                 ChordMotion<2>{x.data(), x_old.data(), v_mean.data(), inverse_dt, v_new.data(), a_new.data()});
    parallel_for(host, n,
                 SetInteraction<2>{.from = from.data(),
                                   .to = to.data(),
                                   .s = s,
                                   .impedance = rate.data(),
                                   .reference_velocity = v_mean.data(),
                                   .v = v.data(),
                                   .interaction = interaction.data(),
                                   .acc = acc.data()});
    StateVector<double> host_partial;
    Vec<2> host_total;
    for (int d = 0; d < 2; ++d)
      host_total[d] = ordered_sum(host, n, ForceComponent<2>{volume.data(), force.data(), d}, host_partial);
    std::vector<Index> slot(n + 1, 0);
    parallel_for(host, n, MarkWalls{kind.data(), slot.data()});
    inclusive_scan(host, slot.data() + 1, n);
    std::vector<Vec<2>> wall_point(slot[n]);
    std::vector<Real> wall_radius(slot[n]);
    parallel_for(
        host, n,
        GatherWalls<2>{kind.data(), x.data(), volume.data(), slot.data(), wall_point.data(), wall_radius.data()});
    ASSERT_GT(slot[n], 0) << "seed " << seed;

    // the device
    const DeviceArray<Vec<2>> d_force(force), d_x(x), d_x_old(x_old), d_v_mean(v_mean), d_from(from), d_to(to), d_v(v);
    const DeviceArray<Mat<2>> d_impedance(impedance);
    DeviceArray<Mat<2>> d_rate = poisoned<Mat<2>>(n);
    const DeviceArray<Real> d_density(density), d_volume(volume);
    const DeviceArray<FluidKind> d_kind(kind);
    DeviceArray<Vec<2>> d_alpha = poisoned<Vec<2>>(n), d_v_new = poisoned<Vec<2>>(n), d_a_new = poisoned<Vec<2>>(n);
    DeviceArray<Vec<2>> d_interaction(interaction0), d_acc(acc0);
    parallel_for(gpu, n, InteractionAcceleration<2>{d_force.data(), d_density.data(), d_alpha.data()});
    parallel_for(gpu, n, InteractionAcceleration<2, Mat<2>>{d_impedance.data(), d_density.data(), d_rate.data()});
    parallel_for(
        gpu, n,
        ChordMotion<2>{d_x.data(), d_x_old.data(), d_v_mean.data(), inverse_dt, d_v_new.data(), d_a_new.data()});
    parallel_for(gpu, n,
                 SetInteraction<2>{.from = d_from.data(),
                                   .to = d_to.data(),
                                   .s = s,
                                   .impedance = d_rate.data(),
                                   .reference_velocity = d_v_mean.data(),
                                   .v = d_v.data(),
                                   .interaction = d_interaction.data(),
                                   .acc = d_acc.data()});
    StateVector<double> device_partial{StateAllocator<double>(true)};
    for (int d = 0; d < 2; ++d) {
      const double total = ordered_sum(gpu, n, ForceComponent<2>{d_volume.data(), d_force.data(), d}, device_partial);
      EXPECT_NEAR(total, host_total[d], 1e-12 * std::abs(host_total[d])) << "seed " << seed << ", component " << d;
    }
    DeviceArray<Index> d_slot(std::vector<Index>(n + 1, 0));
    parallel_for(gpu, n, MarkWalls{d_kind.data(), d_slot.data()});
    inclusive_scan(gpu, d_slot.data() + 1, n);
    DeviceArray<Vec<2>> d_wall_point = poisoned<Vec<2>>(slot[n]);
    DeviceArray<Real> d_wall_radius = poisoned<Real>(slot[n]);
    parallel_for(gpu, n,
                 GatherWalls<2>{d_kind.data(), d_x.data(), d_volume.data(), d_slot.data(), d_wall_point.data(),
                                d_wall_radius.data()});

    EXPECT_LT(relative_difference(alpha, d_alpha), 1e-12) << "seed " << seed;
    EXPECT_LT(relative_difference(rate, d_rate), 1e-12) << "seed " << seed;
    EXPECT_LT(relative_difference(v_new, d_v_new), 1e-12) << "seed " << seed;
    EXPECT_LT(relative_difference(a_new, d_a_new), 1e-12) << "seed " << seed;
    EXPECT_LT(relative_difference(interaction, d_interaction), 1e-12) << "seed " << seed;
    EXPECT_LT(relative_difference(acc, d_acc), 1e-12) << "seed " << seed;
    EXPECT_EQ(d_slot.to_host(), slot) << "seed " << seed;
    EXPECT_EQ(relative_difference(wall_point, d_wall_point), 0.0) << "seed " << seed;
    EXPECT_LT(relative_difference(wall_radius, d_wall_radius), 1e-12) << "seed " << seed;
  }
}
