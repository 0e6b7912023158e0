// TLSPH: deformation gradient, stress, momentum and the time integrators.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/device_memory.hpp"
#include "structure/tlsph.hpp"

using namespace isph;

namespace {

// A rectangular block nx x ny of spacing dx; the first `clamped_columns` columns are clamped.
TlsphSetup<2> block(int nx, int ny, Real dx, int clamped_columns, StructureIntegrator integrator) {
  TlsphSetup<2> s;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      s.X.push_back({{(i + 0.5) * dx, (j + 0.5) * dx}});
      s.v.push_back(Vec<2>::zero());
      s.volume.push_back(dx * dx);
      s.material.push_back(0);
      s.body.push_back(0);
      s.fixed.push_back(i < clamped_columns ? 1 : 0);
    }
  const Real E = 1e6, nu = 0.3;
  s.materials.push_back({1000.0, E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu)), E});
  s.kernels = SmoothingKernel<2>::make(KernelType::cubic_spline, 1.2 * dx);
  s.integrator = integrator;
  return s;
}

// Moves the solver's particles to x = A X + c through its host view.
void deform(TlsphSolver<2>& solver, const Mat<2>& A, const Vec<2>& c) {
  TlsphView<2> v = solver.view();
  auto* x = const_cast<Vec<2>*>(v.x);
  for (Index a = 0; a < v.n; ++a) x[a] = A * v.X[a] + c;
}

}  // namespace

// F is exact for any affine map, at every particle including edges and corners (Eq. 36 with
// the corrected gradient).
TEST(Tlsph, DeformationGradientExactForAffineMaps) {
  TlsphSolver<2> solver(block(12, 6, 0.01, 0, StructureIntegrator::rk4));
  Mat<2> A;
  A(0, 0) = 1.3;
  A(0, 1) = 0.2;
  A(1, 0) = -0.15;
  A(1, 1) = 0.8;
  deform(solver, A, {{0.05, -0.02}});
  solver.update_stress();
  for (Index a = 0; a < solver.size(); ++a)
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) ASSERT_NEAR(solver.deformation_gradient()[a](i, j), A(i, j), 1e-12);
}

// With quadratic-exact pair gradients F is exact for a quadratic displacement at every particle,
// corners included, where the linear-exact gradient is off by O(h) times the curvature; and the
// symmetric hourglass energy of such a field is zero (it does not stiffen smooth bending).
TEST(Tlsph, QuadraticGradientIsExactForQuadraticFields) {
  const Real k = 2.0;  // u = (-k x y, k x^2 / 2 + 0.3 k y^2): bending plus a transverse quadratic
  auto displacement = [&](const Vec<2>& X) {
    return Vec<2>{{-k * X[0] * X[1], 0.5 * k * X[0] * X[0] + 0.3 * k * X[1] * X[1]}};
  };
  auto gradient = [&](const Vec<2>& X) {
    Mat<2> F = Mat<2>::identity();
    F(0, 0) += -k * X[1], F(0, 1) += -k * X[0], F(1, 0) += k * X[0], F(1, 1) += 0.6 * k * X[1];
    return F;
  };
  Real worst[2] = {0, 0};
  for (StructureGradient g : {StructureGradient::linear, StructureGradient::quadratic}) {
    auto s = block(12, 6, 0.01, 0, StructureIntegrator::rk4);
    s.gradient = g;
    s.hourglass = 5;
    TlsphSolver<2> solver(s);
    TlsphView<2> v = solver.view();
    auto* x = const_cast<Vec<2>*>(v.x);
    for (Index a = 0; a < v.n; ++a) x[a] = v.X[a] + displacement(v.X[a]);
    tlsph_stress(Exec{}, v);
    Real& w = worst[g == StructureGradient::quadratic];
    for (Index a = 0; a < v.n; ++a) {
      const Mat<2> F = gradient(v.X[a]);
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) w = std::max(w, std::abs(v.F[a](i, j) - F(i, j)));
    }
    if (g == StructureGradient::quadratic) {
      // strain energy without the hourglass part
      Real elastic = 0, stored = 0;
      for (Index a = 0; a < v.n; ++a) {
        Real psi = 0;
        svk_stress(green_strain(v.F[a]), s.materials[0], &psi);
        elastic += v.volume[a] * psi;
        stored += v.volume[a] * v.psi[a];
      }
      EXPECT_NEAR(stored, elastic, 1e-10 * elastic);
    }
  }
  EXPECT_LT(worst[1], 1e-10);
  EXPECT_GT(worst[0], 1e-3);  // the linear-exact gradient at the edges: O(h k) = 0.012 k
}

// Pure bending of a block of N particle rows: the one-point (particle) quadrature stores the bending
// energy of the second moment sum V y^2 = I (1 - 1/N^2); the cell quadrature stores all of it (the
// strain is linear across each cell). Quadratic gradients make F exact, so only the quadrature differs.
TEST(Tlsph, CellQuadratureStoresTheWholeBendingEnergy) {
  const int N = 6;
  const Real dx = 0.01, kappa = 1e-4, y0 = 0.5 * N * dx;
  for (StructureQuadrature q : {StructureQuadrature::point, StructureQuadrature::cell}) {
    auto s = block(16, N, dx, 0, StructureIntegrator::rk4);
    s.gradient = StructureGradient::quadratic;
    s.quadrature = q;
    TlsphSolver<2> solver(s);
    TlsphView<2> v = solver.view();
    auto* x = const_cast<Vec<2>*>(v.x);
    for (Index a = 0; a < v.n; ++a) {  // u = (-kappa x (y - y0), kappa x^2 / 2): curvature kappa, E_yy = 0
      const Vec<2> X = v.X[a];
      x[a] = X + Vec<2>{{-kappa * X[0] * (X[1] - y0), 0.5 * kappa * X[0] * X[0]}};
    }
    solver.update_stress();
    const ElasticMaterial& m = s.materials[0];
    const Real T = N * dx, length = 16 * dx;
    const Real continuum = 0.5 * (m.lambda + 2 * m.mu) * kappa * kappa * length * T * T * T / 12;
    const Real expected = q == StructureQuadrature::point ? 1 - 1.0 / (N * N) : 1.0;
    EXPECT_NEAR(solver.strain_energy() / continuum, expected, 1e-4) << "quadrature " << int(q);
  }
}

TEST(Tlsph, WithoutCorrectionFIsNotExactAtEdges) {
  auto s = block(12, 6, 0.01, 0, StructureIntegrator::rk4);
  s.gradient = StructureGradient::uncorrected;
  TlsphSolver<2> solver(s);
  Mat<2> A = Mat<2>::identity();
  A(0, 0) = 1.1;
  deform(solver, A, Vec<2>::zero());
  solver.update_stress();
  Real worst = 0;
  for (Index a = 0; a < solver.size(); ++a)
    worst = std::max(worst, std::abs(solver.deformation_gradient()[a](0, 0) - 1.1));
  EXPECT_GT(worst, 1e-2);
}

// A rigid rotation produces no strain, no stress and no acceleration (objectivity of SVK).
TEST(Tlsph, RigidRotationIsStressFree) {
  TlsphSolver<2> solver(block(10, 5, 0.01, 0, StructureIntegrator::rk4));
  const Real th = 0.7;
  Mat<2> R;
  R(0, 0) = std::cos(th);
  R(0, 1) = -std::sin(th);
  R(1, 0) = std::sin(th);
  R(1, 1) = std::cos(th);
  deform(solver, R, {{0.3, 0.1}});
  solver.update_stress();
  EXPECT_LT(solver.strain_energy(), 1e-20);
  for (Index a = 0; a < solver.size(); ++a) {
    const Mat<2> sigma = solver.cauchy_stress(a);
    EXPECT_NEAR(sigma(0, 0), 0.0, 1e-6);
    EXPECT_NEAR(sigma(0, 1), 0.0, 1e-6);
  }
}

// A uniform stretch of the free block: interior forces cancel and the block pulls itself back:
// the left half is pulled to +x, the right half to -x, by equal and opposite resultants
// (the pair forces are antisymmetric, so momentum is conserved).
TEST(Tlsph, StretchedBlockPullsBackAndConservesMomentum) {
  auto s = block(16, 8, 0.01, 0, StructureIntegrator::rk4);
  TlsphSolver<2> solver(s);
  Mat<2> A = Mat<2>::identity();
  A(0, 0) = 1.01;
  deform(solver, A, Vec<2>::zero());
  TlsphView<2> v = solver.view();
  tlsph_stress(Exec{}, v);
  tlsph_acceleration(Exec{}, v);
  const Real middle = 0.08 * 1.01;
  Vec<2> left = Vec<2>::zero(), right = Vec<2>::zero();
  for (Index a = 0; a < v.n; ++a) (v.x[a][0] < middle ? left : right) += v.acc[a];
  EXPECT_GT(left[0], 0.0);
  EXPECT_LT(right[0], 0.0);
  EXPECT_NEAR(left[0] + right[0], 0.0, 1e-10 * left[0]);
  EXPECT_NEAR(left[1] + right[1], 0.0, 1e-10 * left[0]);
}

// The hourglass force is the exact negative gradient of the hourglass energy (so that energy is
// conserved): compare the acceleration with a central finite difference of the total energy.
TEST(Tlsph, InternalForceIsTheGradientOfTheStoredEnergy) {
  using Q = StructureQuadrature;
  using G = StructureGradient;
  for (auto [alpha, gradient, quadrature] :
       {std::tuple{0.0, G::linear, Q::point}, std::tuple{10.0, G::linear, Q::point},
        std::tuple{0.0, G::quadratic, Q::point}, std::tuple{10.0, G::quadratic, Q::point},
        std::tuple{0.0, G::linear, Q::cell}, std::tuple{5.0, G::linear, Q::cell},
        std::tuple{5.0, G::quadratic, Q::cell}}) {
    auto s = block(8, 5, 0.01, 0, StructureIntegrator::rk4);
    s.hourglass = alpha;
    s.gradient = gradient;
    s.quadrature = quadrature;
    TlsphSolver<2> solver(s);
    TlsphView<2> v = solver.view();
    auto* x = const_cast<Vec<2>*>(v.x);
    std::mt19937 rng(5);
    std::uniform_real_distribution<Real> u(-1e-3, 1e-3);
    for (Index a = 0; a < v.n; ++a) x[a] = x[a] + Vec<2>{{u(rng), u(rng)}};
    auto energy = [&] {
      solver.update_stress();
      return solver.strain_energy();
    };
    tlsph_stress(Exec{}, v);
    tlsph_acceleration(Exec{}, v);
    const std::vector<Vec<2>> acc(v.acc, v.acc + v.n);
    const Real mass = 1000.0 * 0.01 * 0.01;
    for (Index a : {0, 7, 21, 39})
      for (int d = 0; d < 2; ++d) {
        const Real e = 1e-7, keep = x[a][d];
        x[a][d] = keep + e;
        const Real up = energy();
        x[a][d] = keep - e;
        const Real down = energy();
        x[a][d] = keep;
        const Real force = -(up - down) / (2 * e);
        EXPECT_NEAR(acc[a][d] * mass, force, 1e-5 * std::abs(force) + 1e-3)
            << "alpha " << alpha << " gradient " << int(gradient) << " quadrature " << int(quadrature) << " particle "
            << a;
      }
  }
}

// Convergence order of the integrators on a vibrating clamped block: the error against a
// fine-step solution falls by 2^p when the step is halved (p = 4 for RK4, 2 for Verlet).
double observed_order(StructureIntegrator integrator) {
  auto run = [&](int steps) {
    auto s = block(10, 3, 0.01, 3, integrator);
    for (Index a = 0; a < static_cast<Index>(s.X.size()); ++a)
      if (!s.fixed[a]) s.v[a] = {{0.0, 0.5 * (s.X[a][0] - 0.03)}};
    TlsphSolver<2> solver(s);
    const Real T = 40 * solver.stable_dt(0.5);
    const Real dt = T / steps;
    for (int k = 0; k < steps; ++k) solver.step(k * dt, dt);
    return solver.position();
  };
  const auto ref = run(1280);
  auto err = [&](int steps) {
    const auto x = run(steps);
    Real e = 0;
    for (std::size_t a = 0; a < x.size(); ++a) e = std::max(e, std::sqrt(norm2(x[a] - ref[a])));
    return e;
  };
  const double e1 = err(80), e2 = err(160);
  return std::log2(e1 / e2);
}

TEST(TimeIntegration, Rk4IsFourthOrder) { EXPECT_NEAR(observed_order(StructureIntegrator::rk4), 4.0, 0.3); }
TEST(TimeIntegration, VerletIsSecondOrder) { EXPECT_NEAR(observed_order(StructureIntegrator::verlet), 2.0, 0.2); }

// A coupled step changes the interaction acceleration between structure steps (and repeats a step
// from a saved state with another field). Both integrators must apply, over each step, the field set
// for it: on a free, unstrained block under a uniform interaction a, v grows by exactly dt a per step.
// Velocity-Verlet's opening kick reuses the acceleration of the last step's end, so it must follow
// the new field.
TEST(TimeIntegration, EachStepFeelsTheInteractionSetForIt) {
  for (auto integrator : {StructureIntegrator::rk4, StructureIntegrator::verlet}) {
    TlsphSolver<2> solver(block(6, 3, 0.01, 0, integrator));
    const Index n = solver.size();
    const Real dt = solver.stable_dt(0.5);
    const Vec<2> a1{{2.0, -1.0}}, a2{{-3.0, 5.0}}, a3{{7.0, 1.0}};
    solver.set_interaction(std::vector<Vec<2>>(n, a1));
    solver.step(0, dt);
    solver.set_interaction(std::vector<Vec<2>>(n, a2));
    solver.step(dt, dt);
    const Vec<2> after_two = dt * (a1 + a2);
    // the repeated step: back to the state after the first step, then stepped under a3
    solver.save_state();
    solver.set_interaction(std::vector<Vec<2>>(n, a3));
    solver.step(2 * dt, dt);
    solver.restore_state();
    for (Index a = 0; a < n; ++a)
      for (int d = 0; d < 2; ++d)
        EXPECT_NEAR(solver.velocity()[a][d], after_two[d], 1e-9) << "integrator " << int(integrator);
    solver.step(2 * dt, dt);
    const Vec<2> after_three = dt * (a1 + a2 + a3);
    for (Index a = 0; a < n; ++a)
      for (int d = 0; d < 2; ++d)
        EXPECT_NEAR(solver.velocity()[a][d], after_three[d], 1e-9) << "integrator " << int(integrator);
  }
}

// advance() runs a fluid step's substeps and returns the interaction's work over them. A free,
// unstrained block under a uniform field moves rigidly, so that work is the change of its kinetic
// energy, and the trapezoidal rule on each substep's power is exact (under a field held over a substep
// the power is linear in time). With the field ramped from substep to substep (the coupling's
// "interpolated" alpha) each substep's two ends must take that substep's field: the one of the substep
// before, at the start, misses the work here by 0.3 %.
TEST(TimeIntegration, AdvanceReturnsTheInteractionsWork) {
  for (auto integrator : {StructureIntegrator::rk4, StructureIntegrator::verlet})
    for (bool ramped : {false, true}) {
      TlsphSolver<2> solver(block(6, 3, 0.01, 0, integrator));
      const Index n = solver.size();
      const Vec<2> v0{{0.3, -0.2}}, a1{{2.0, -1.0}}, a2{{-3.0, 5.0}};
      solver.set_motion(std::vector<Vec<2>>(solver.position().begin(), solver.position().end()),
                        std::vector<Vec<2>>(n, v0));
      const std::vector<Vec<2>> from(n, a1), to(n, a2);
      solver.set_interaction(to);
      const int count = 20;
      const Real dt = count * solver.stable_dt(0.5);
      const Real before = solver.kinetic_energy();
      const Real work = solver.advance(
          0, dt, count,
          ramped ? InteractionSchedule<2>{.from = from.data(), .to = to.data()} : InteractionSchedule<2>{});
      const Real gain = solver.kinetic_energy() - before;
      EXPECT_NEAR(work, gain, 1e-9 * std::abs(gain)) << "integrator " << int(integrator) << (ramped ? ", ramped" : "");
      // each substep applied its own field: v = v0 + h sum_k a_k, a_k = a1 + (k + 1/2)/count (a2 - a1)
      const Vec<2> expected = ramped ? v0 + (0.5 * dt) * (a1 + a2) : v0 + dt * a2;
      for (int d = 0; d < 2; ++d) EXPECT_NEAR(solver.velocity()[0][d], expected[d], 1e-9);
    }
}

namespace {

// Structure-wall contact (for_each_wall_overlap): obstacle points of radius dx/2 in a row along y = -dx/2,
// the top of a floor whose surface is y = 0, as the fluid's wall particles stand.
struct Floor {
  std::vector<Vec<2>> point;
  std::vector<Real> radius;
};
Floor floor_row(Real dx, Real x_lo, Real x_hi) {
  Floor f;
  for (Real x = x_lo; x <= x_hi; x += dx) {
    f.point.push_back({{x, -0.5 * dx}});
    f.radius.push_back(0.5 * dx);
  }
  return f;
}

}  // namespace

// The penalty's law on a block at rest, unstrained, its bottom row lowered into the floor by delta: only
// the bottom row feels it, each particle pushed up by M delta / (rho dx^2) (the one floor point below it
// overlaps; the diagonal ones lie sqrt(2) dx away), and the pairs store (M delta^2 / 2) each.
TEST(WallContact, OverlapPushesOutWithTheMaterialsStiffness) {
  const Real dx = 0.01, delta = 0.01 * dx;
  TlsphSolver<2> solver(block(6, 3, dx, 0, StructureIntegrator::rk4));
  deform(solver, Mat<2>::identity(), {{0.0, -delta}});
  const Floor f = floor_row(dx, -0.5 * dx, 7 * dx);
  solver.set_obstacles(f.point, f.radius, solver.support());
  const TlsphView<2> v = solver.view();
  tlsph_stress(Exec{}, v);
  tlsph_acceleration(Exec{}, v);
  const ElasticMaterial m = v.materials[0];
  const Real modulus = m.lambda + 2 * m.mu;
  for (Index a = 0; a < v.n; ++a) {
    const bool bottom = v.X[a][1] < dx;
    EXPECT_NEAR(v.acc[a][0], 0.0, 1e-9);
    EXPECT_NEAR(v.acc[a][1], bottom ? modulus * delta / (m.density * dx * dx) : 0.0, 1e-6) << "particle " << a;
  }
  const auto contact = solver.obstacle_contact();
  EXPECT_NEAR(contact.deepest, delta, 1e-15);
  EXPECT_EQ(contact.pairs, 6);
  EXPECT_NEAR(contact.energy, 6 * 0.5 * modulus * delta * delta, 1e-12 * modulus * delta * delta);
}

// A block thrown at the floor at 1 m/s under gravity: it bounces off without passing into the floor, and
// the energy, the penalty's included, is kept (the penalty is conservative; measured -0.27 % at Courant
// number 0.25, -0.02 % at 0.1, and -3.3 % at 0.5, where RK4 damps the high modes the impact excites).
// Its particles stand midway between the floor's points, where a disc of radius dx/2 touches them at a
// height of 0.366 dx (the floor is that rough, on the scale of its spacing): they come down to
// 0.338 dx, an overlap of 0.027 dx. Without the obstacles the same block falls through.
TEST(WallContact, ThrownBlockBouncesOffTheFloor) {
  const Real dx = 0.01, speed = 1.0;
  for (bool obstacles : {true, false}) {
    auto s = block(8, 3, dx, 0, StructureIntegrator::rk4);
    s.gravity = {{0.0, -9.81}};
    for (auto& X : s.X) X[1] += 0.5 * dx;  // half a spacing above the floor
    for (auto& v : s.v) v = {{0.0, -speed}};
    TlsphSolver<2> solver(s);
    const Floor f = floor_row(dx, -3 * dx, 11 * dx);
    const Real dt = solver.stable_dt(0.25);
    auto energy = [&] {
      solver.update_stress();
      return solver.kinetic_energy() + solver.potential_energy() + solver.strain_energy() +
             solver.obstacle_contact().energy;
    };
    const Real e0 = energy();
    Real lowest = 1e300, deepest = 0;
    const int steps = static_cast<int>(0.02 / dt);
    solver.set_obstacles(obstacles ? f.point : std::vector<Vec<2>>{}, obstacles ? f.radius : std::vector<Real>{},
                         solver.support());
    for (int k = 0; k < steps; ++k) {
      // candidates held over 10 steps, as over the substeps of a fluid step
      if (k % 10 == 0) solver.find_obstacle_candidates();
      solver.step(k * dt, dt);
      for (const auto& x : solver.position()) lowest = std::min(lowest, x[1]);
      deepest = std::max(deepest, solver.obstacle_contact().deepest);
    }
    Real mean_vy = 0;
    for (const auto& v : solver.velocity()) mean_vy += v[1] / solver.size();
    if (obstacles) {
      EXPECT_GT(lowest, 0.3 * dx);
      EXPECT_LT(deepest, 0.05 * dx);
      EXPECT_GT(mean_vy, 0.5 * speed);  // on its way back up
      EXPECT_NEAR(energy(), e0, 0.01 * e0);
    } else {
      EXPECT_LT(lowest, -0.5 * dx);
      EXPECT_LT(mean_vy, -speed);
    }
  }
}

// The same solver in 3D: F is exact for an affine map and a rigid rotation is stress-free.
TEST(Tlsph3D, AffineMapsAndRigidRotation) {
  TlsphSetup<3> s;
  const Real dx = 0.01;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k) {
        s.X.push_back({{(i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx}});
        s.v.push_back(Vec<3>::zero());
        s.volume.push_back(dx * dx * dx);
        s.material.push_back(0);
        s.body.push_back(0);
        s.fixed.push_back(0);
      }
  s.materials.push_back({1000.0, 5.0e5, 4.0e5, 1.0e6});
  s.kernels = SmoothingKernel<3>::make(KernelType::wendland_c2, 1.3 * dx);
  TlsphSolver<3> solver(s);
  auto move = [&](const Mat<3>& A) {
    TlsphView<3> v = solver.view();
    auto* x = const_cast<Vec<3>*>(v.x);
    for (Index a = 0; a < v.n; ++a) x[a] = A * v.X[a];
    solver.update_stress();
  };
  Mat<3> A = Mat<3>::identity();
  A(0, 1) = 0.3, A(2, 0) = -0.2, A(1, 1) = 1.1;
  move(A);
  for (Index a = 0; a < solver.size(); ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ASSERT_NEAR(solver.deformation_gradient()[a](i, j), A(i, j), 1e-12);
  EXPECT_GT(solver.strain_energy(), 0.0);
  const Real c = std::cos(0.4), sn = std::sin(0.4);
  Mat<3> R = Mat<3>::identity();
  R(0, 0) = c, R(0, 2) = sn, R(2, 0) = -sn, R(2, 2) = c;
  move(R);
  EXPECT_LT(solver.strain_energy(), 1e-20);
}

// Asking for the device where none is visible (or in a build without CUDA) is an error that says so;
// on a machine with a GPU the device tests cover the structure solver there.
TEST(Tlsph, CudaWithoutADeviceIsAClearError) {
  if (cuda_devices() > 0) GTEST_SKIP() << "a CUDA device is visible";
  try {
    TlsphSolver<2> solver(block(6, 3, 0.01, 1, StructureIntegrator::rk4), Exec{Device::cuda});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("none is visible"), std::string::npos) << e.what();
  }
}
