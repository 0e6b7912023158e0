// The same TLSPH stages on every available device, compared with the host on random inputs.
// CPU always runs; CUDA runs when the build has it and a GPU is present, and is skipped otherwise.
// ISPH_REQUIRE_GPU_TESTS=1 turns that skip into a failure.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

#include "core/device_memory.hpp"
#include "gpu_skip.hpp"
#include "structure/tlsph.hpp"

using namespace isph;

namespace {

// A block clamped at its left end, with random velocities; fresh inputs for every seed.
TlsphSetup<2> random_setup(unsigned seed, int columns = 40,
                           StructureQuadrature quadrature = StructureQuadrature::point) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-1.0, 1.0);
  TlsphSetup<2> s;
  const Real dx = 0.01;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < 12; ++j) {
      s.X.push_back({{(i + 0.5) * dx, (j + 0.5) * dx}});
      s.v.push_back({{u(rng), u(rng)}});
      s.volume.push_back(dx * dx);
      s.material.push_back(0);
      s.body.push_back(0);
      s.fixed.push_back(i < 3);
    }
  s.materials.push_back({1100.0, 2.0e7, 4.0e6, 1.2e7});
  s.kernels = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2 * dx);
  s.hourglass = 0.5;
  s.damping = 3.0;
  s.quadrature = quadrature;
  return s;
}

// The same block, randomly deformed.
TlsphSolver<2> random_block(unsigned seed, int columns = 40,
                            StructureQuadrature quadrature = StructureQuadrature::point) {
  std::mt19937 rng(seed + 1000);
  std::uniform_real_distribution<Real> u(-1.0, 1.0);
  const TlsphSetup<2> s = random_setup(seed, columns, quadrature);
  const Real dx = 0.01;
  TlsphSolver<2> solver(s);
  TlsphView<2> v = solver.view();
  auto* x = const_cast<Vec<2>*>(v.x);
  for (Index a = 0; a < v.n; ++a)
    if (!s.fixed[a]) x[a] = x[a] + Vec<2>{{0.1 * dx * u(rng), 0.1 * dx * u(rng)}};
  return solver;
}

// Largest |a_i - b_i| over the largest |b_i|.
template <class Array>
double largest_relative_difference(const Array& a, const Array& b) {
  double scale = 0, worst = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    scale = std::max(scale, std::sqrt(norm2(b[i])));
    worst = std::max(worst, std::sqrt(norm2(a[i] - b[i])));
  }
  return worst / scale;
}

template <class T>
void poison(std::vector<T>& v) {
  std::fill(reinterpret_cast<unsigned char*>(v.data()), reinterpret_cast<unsigned char*>(v.data() + v.size()), 0xFF);
}

}  // namespace

TEST(DeviceStages, TlsphStressAndAccelerationCudaMatchesCpu) {
  ISPH_SKIP_WITHOUT_GPU();
  for (auto [seed, quadrature] : {std::pair{1u, StructureQuadrature::point}, std::pair{2u, StructureQuadrature::point},
                                  std::pair{3u, StructureQuadrature::cell}, std::pair{4u, StructureQuadrature::cell}}) {
    TlsphSolver<2> solver = random_block(seed, 40, quadrature);
    TlsphView<2> h = solver.view();
    const Index n = h.n, pairs = solver.pairs();
    auto vec = [](const auto* p, std::size_t k) {
      return std::vector<std::remove_cv_t<std::remove_pointer_t<decltype(p)>>>(p, p + k);
    };
    DeviceArray<Vec<2>> X(vec(h.X, n)), x(vec(h.x, n)), v(vec(h.v, n)), cgrad(vec(h.cgrad, pairs)),
        rcgrad(vec(h.rcgrad, pairs)), cgrad_sum(vec(h.cgrad_sum, n)), load(std::vector<Vec<2>>(1, Vec<2>::zero()));
    DeviceArray<Index> off(vec(h.nbr_offset, n + 1)), nbr(vec(h.nbr, pairs));
    DeviceArray<Real> hg_weight(vec(h.hg_weight, pairs)), volume(vec(h.volume, n)), cell_moment(vec(h.cell_moment, n));
    DeviceArray<Mat<2>> hg_moment(vec(h.hg_moment, n));
    DeviceArray<Index> strained(vec(h.strained, h.strained ? h.strained_count : 0)),
        moving(vec(h.moving, h.moving ? h.moving_count : 0));
    DeviceArray<int> mat(vec(h.material, n));
    DeviceArray<ElasticMaterial> mats(vec(h.materials, 1));
    DeviceArray<unsigned char> fixed(vec(h.fixed, n));
    DeviceArray<Index> contact_offset(vec(h.obstacles.offset, n + 1));  // no obstacles: every count zero
    std::vector<Mat<2>> poisoned_m(n);
    std::vector<Real> poisoned_r(n);
    std::vector<Vec<2>> poisoned_v(n);
    poison(poisoned_m), poison(poisoned_r), poison(poisoned_v);
    DeviceArray<Mat<2>> F(poisoned_m), stress(poisoned_m), strain(poisoned_m);
    std::vector<Mat<2>> poisoned_gradient_stress(2 * n);
    poison(poisoned_gradient_stress);
    DeviceArray<Mat<2>> gradient_stress(poisoned_gradient_stress);
    DeviceArray<Real> psi(poisoned_r);
    DeviceArray<Vec<2>> acc(poisoned_v);

    TlsphView<2> d = h;
    d.X = X.data(), d.x = x.data(), d.v = v.data(), d.cgrad = cgrad.data();
    d.rcgrad = rcgrad.data(), d.cgrad_sum = cgrad_sum.data(), d.hg_weight = hg_weight.data(), d.volume = volume.data();
    d.cell_moment = cell_moment.data(), d.hg_moment = hg_moment.data();
    d.strained = h.strained ? strained.data() : nullptr, d.moving = h.moving ? moving.data() : nullptr;
    d.nbr_offset = off.data(), d.nbr = nbr.data(), d.material = mat.data(), d.materials = mats.data();
    d.fixed = fixed.data(), d.load_acc = load.data(), d.loads = 0;
    d.obstacles = {contact_offset.data(), nullptr, nullptr};
    d.F = F.data(), d.stress = stress.data(), d.psi = psi.data(), d.acc = acc.data();
    d.strain = strain.data(), d.gradient_stress = gradient_stress.data();

    tlsph_stress(Exec{Device::cpu}, h);
    tlsph_acceleration(Exec{Device::cpu}, h);
    tlsph_stress(Exec{Device::cuda}, d);
    tlsph_acceleration(Exec{Device::cuda}, d);
    const auto acc_d = acc.to_host();
    const auto F_d = F.to_host();
    const auto psi_d = psi.to_host();
    // The passes visit the free particles (acceleration) and those within their reach (stress): the
    // clamped column furthest in keeps its poison, except with the cell quadrature's longer reach.
    ASSERT_TRUE(h.moving != nullptr);
    std::vector<bool> strained_mask(n, h.strained == nullptr);
    for (Index k = 0; h.strained && k < h.strained_count; ++k) strained_mask[h.strained[k]] = true;
    for (Index a = 0; a < n; ++a) {
      for (int i = 0; i < 2; ++i) {
        if (!h.fixed[a]) {
          EXPECT_NEAR(acc_d[a][i], h.acc[a][i], 1e-12 * (1 + std::abs(h.acc[a][i])))
              << "seed " << seed << " particle " << a;
        }
        for (int j = 0; j < 2 && strained_mask[a]; ++j) EXPECT_NEAR(F_d[a](i, j), h.F[a](i, j), 1e-12);
      }
      if (strained_mask[a]) {
        EXPECT_NEAR(psi_d[a], h.psi[a], 1e-12 * (1 + std::abs(h.psi[a])));
      }
    }
  }
}

// The host path of the same stage must be independent of the thread count (gather, no atomics).
// The block is larger than kMinParallelLoop, so that the loops really run on several threads.
TEST(DeviceStages, CpuResultIndependentOfThreadCount) {
  TlsphSolver<2> solver = random_block(9, 200);
  ASSERT_GE(solver.size(), kMinParallelLoop);
  TlsphView<2> h = solver.view();
  tlsph_stress(Exec{}, h);
  tlsph_acceleration(Exec{}, h);
  const std::vector<Vec<2>> many(h.acc, h.acc + h.n);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  tlsph_stress(Exec{}, h);
  tlsph_acceleration(Exec{}, h);
  omp_set_num_threads(threads);
  for (Index a = 0; a < h.n; ++a) {
    EXPECT_EQ(many[a][0], h.acc[a][0]);
    EXPECT_EQ(many[a][1], h.acc[a][1]);
  }
}

// Whole RK4 steps on the device (recorded as a graph and replayed) against the host: a clamped block
// under gravity, a load that ramps up over the first 40 steps (no graph while it ramps), an interaction
// field set at step 100 (the graph is recorded again), and a step repeated from a saved state, as the
// coupled step does. Displacements and velocities after 300 steps agree to 1e-12 of their largest value.
TEST(DeviceStages, TlsphRk4StepsOnTheDeviceMatchTheHost) {
  ISPH_SKIP_WITHOUT_GPU();
  for (unsigned seed : {4u, 5u}) {
    std::mt19937 rng(seed + 2000);
    std::uniform_real_distribution<Real> u(-1.0, 1.0);
    TlsphSetup<2> s = random_setup(seed);
    s.gravity = {{0.0, -9.81}};
    LoadField<2> load;
    for (std::size_t a = 0; a < s.X.size(); ++a) load.acc.push_back({{50 * u(rng), 50 * u(rng)}});
    TlsphSolver<2> host(s), device(s, Exec{Device::cuda});
    const Real dt = host.stable_dt(0.5);
    load.ramp_time = 40 * dt;
    s.loads.push_back(load);
    TlsphSolver<2> host_loaded(s), device_loaded(s, Exec{Device::cuda});
    std::vector<Vec<2>> interaction(s.X.size());
    for (auto& a : interaction) a = {{20 * u(rng), 20 * u(rng)}};

    for (auto [h, d] : {std::pair{&host, &device}, std::pair{&host_loaded, &device_loaded}}) {
      for (int k = 0; k < 300; ++k) {
        if (k == 100) h->set_interaction(interaction), d->set_interaction(interaction);
        if (k == 200) {  // a step tried, undone and repeated
          h->save_state(), d->save_state();
          h->step(k * dt, dt), d->step(k * dt, dt);
          h->restore_state(), d->restore_state();
        }
        h->step(k * dt, dt);
        d->step(k * dt, dt);
        if (k == 10) {
          EXPECT_EQ(d->replayed_graph(), h == &host) << "seed " << seed << ": a graph replayed while a load ramps";
        }
      }
      EXPECT_TRUE(d->replayed_graph()) << "seed " << seed;
      std::vector<Vec<2>> uh(h->size()), ud(h->size());
      for (Index a = 0; a < h->size(); ++a) {
        uh[a] = h->position()[a] - h->reference()[a];
        ud[a] = d->position()[a] - d->reference()[a];
      }
      EXPECT_LT(largest_relative_difference(ud, uh), 1e-12) << "seed " << seed << (h == &host ? "" : ", ramped load");
      EXPECT_LT(largest_relative_difference(d->velocity(), h->velocity()), 1e-12) << "seed " << seed;
      double largest_displacement = 0;
      for (const auto& e : uh) largest_displacement = std::max(largest_displacement, std::sqrt(norm2(e)));
      EXPECT_GT(largest_displacement, 1e-4) << "seed " << seed << ": the block hardly moved";
    }
  }
}

// A coupled fluid step's substeps (advance) queued on the device, with the interaction's power after
// each and one wait at the end, against the host: under a held field, under a ramped one (set on the
// device between the substeps), then held again at a smaller substep (the graph recorded again). The
// states agree to 1e-12 of their largest value, the interaction's works to 1e-12.
TEST(DeviceStages, TlsphSubstepsQueuedOnTheDeviceMatchTheHost) {
  ISPH_SKIP_WITHOUT_GPU();
  for (unsigned seed : {6u, 7u}) {
    std::mt19937 rng(seed + 3000);
    std::uniform_real_distribution<Real> u(-1.0, 1.0);
    const TlsphSetup<2> s = random_setup(seed);
    TlsphSolver<2> host(s), device(s, Exec{Device::cuda});
    const Index n = host.size();
    StateVector<Vec<2>> from(n, Vec<2>::zero(), StateAllocator<Vec<2>>(true)), to(from);
    for (Index a = 0; a < n; ++a) from[a] = {{20 * u(rng), 20 * u(rng)}}, to[a] = {{20 * u(rng), 20 * u(rng)}};
    host.set_interaction(to), device.set_interaction(to);
    const Real dt = 16 * host.stable_dt(0.5);
    Real t = 0;
    for (auto [count, ramped] : {std::pair{16, false}, std::pair{16, true}, std::pair{20, false}}) {
      const InteractionSchedule<2> ramp =
          ramped ? InteractionSchedule<2>{.from = from.data(), .to = to.data()} : InteractionSchedule<2>{};
      const Real host_work = host.advance(t, dt, count, ramp);
      const Real device_work = device.advance(t, dt, count, ramp);
      t += dt;
      EXPECT_TRUE(device.replayed_graph()) << "seed " << seed;
      EXPECT_GT(std::abs(host_work), 0) << "seed " << seed;
      EXPECT_NEAR(device_work, host_work, 1e-12 * std::abs(host_work))
          << "seed " << seed << ", " << count << (ramped ? " ramped" : " held") << " substeps";
    }
    std::vector<Vec<2>> uh(n), ud(n);
    for (Index a = 0; a < n; ++a) {
      uh[a] = host.position()[a] - host.reference()[a];
      ud[a] = device.position()[a] - device.reference()[a];
    }
    EXPECT_LT(largest_relative_difference(ud, uh), 1e-12) << "seed " << seed;
    EXPECT_LT(largest_relative_difference(device.velocity(), host.velocity()), 1e-12) << "seed " << seed;
  }
}

// The structure's obstacle candidates (a cell list over the obstacles, count, scan and fill) and its
// overlaps with them found on the device against the host: random obstacle points below a block whose
// lowest particles reach into them, then 100 steps with the candidates found again every 10. The
// candidate lists agree exactly (same points, same order), the contact's energy and depth to 1e-12 (the
// device's pow may differ from the host's in the last bit), its pair count exactly, and the states to
// 1e-12 of their largest value.
TEST(DeviceStages, TlsphObstaclesOnTheDeviceMatchTheHost) {
  ISPH_SKIP_WITHOUT_GPU();
  for (unsigned seed : {8u, 9u}) {
    std::mt19937 rng(seed + 4000);
    std::uniform_real_distribution<Real> u(0.0, 1.0);
    TlsphSetup<2> s = random_setup(seed);
    s.gravity = {{0.0, -9.81}};
    const Real dx = 0.01;
    std::vector<Vec<2>> point;
    std::vector<Real> radius;
    for (int k = 0; k < 400; ++k) {
      point.push_back({{0.45 * u(rng) - 0.02, -0.5 * dx + 0.3 * dx * u(rng)}});
      radius.push_back((0.4 + 0.2 * u(rng)) * dx);
    }
    TlsphSolver<2> host(s), device(s, Exec{Device::cuda});
    host.set_obstacles(point, radius, host.support());
    device.set_obstacles(point, radius, device.support());
    const Real dt = host.stable_dt(0.25);
    for (int k = 0; k <= 100; ++k) {
      if (k % 10 == 0) {
        host.find_obstacle_candidates(), device.find_obstacle_candidates();
        const ObstacleView<2> h = host.obstacles(), d = device.obstacles();
        for (Index a = 0; a <= host.size(); ++a)
          ASSERT_EQ(d.offset[a], h.offset[a]) << "seed " << seed << ", particle " << a;
        ASSERT_GT(h.offset[host.size()], 0) << "seed " << seed << ": no candidates";
        for (Index c = 0; c < h.offset[host.size()]; ++c) {
          ASSERT_EQ(d.point[c][0], h.point[c][0]) << "seed " << seed << ", candidate " << c;
          ASSERT_EQ(d.point[c][1], h.point[c][1]) << "seed " << seed << ", candidate " << c;
          ASSERT_EQ(d.radius[c], h.radius[c]) << "seed " << seed << ", candidate " << c;
        }
        const auto hc = host.obstacle_contact(), dc = device.obstacle_contact();
        EXPECT_NEAR(dc.energy, hc.energy, 1e-12 * hc.energy) << "seed " << seed << ", step " << k;
        EXPECT_NEAR(dc.deepest, hc.deepest, 1e-12 * hc.deepest) << "seed " << seed << ", step " << k;
        EXPECT_EQ(dc.pairs, hc.pairs) << "seed " << seed << ", step " << k;
        if (k == 0) {
          EXPECT_GT(hc.pairs, 0) << "seed " << seed << ": nothing overlaps";
        }
      }
      if (k < 100) host.step(k * dt, dt), device.step(k * dt, dt);
    }
    std::vector<Vec<2>> uh(host.size()), ud(host.size());
    for (Index a = 0; a < host.size(); ++a) {
      uh[a] = host.position()[a] - host.reference()[a];
      ud[a] = device.position()[a] - device.reference()[a];
    }
    EXPECT_LT(largest_relative_difference(ud, uh), 1e-12) << "seed " << seed;
    EXPECT_LT(largest_relative_difference(device.velocity(), host.velocity()), 1e-12) << "seed " << seed;
  }
}
