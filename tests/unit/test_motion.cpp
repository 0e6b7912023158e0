// Prescribed motions (core/rigid_motion.hpp): the profile laws, the spline through a motion file,
// and the rigid-body kinematics of translations and rotations.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rigid_motion.hpp"

using namespace isph;

namespace {

MotionSpec table_of(double (*f)(double), const std::vector<double>& times) {
  MotionSpec m;
  m.type = MotionType::translation;
  m.profile = MotionLaw::csv;
  m.times = times;
  for (double t : times) m.values.push_back(f(t));
  return m;
}

}  // namespace

// The natural cubic spline through samples of sin t (whose second derivative vanishes at both ends,
// like the spline's) is fourth-order accurate in the value and third-order in the rate.
TEST(MotionProfile, SplineThroughSamplesConverges) {
  double last_value = 0, last_rate = 0;
  for (int n : {50, 100, 200}) {
    std::vector<double> times;
    for (int i = 0; i <= n; ++i) times.push_back(2 * M_PI * i / n + (i % 2 ? 0.3 * M_PI / n : 0.0));  // uneven
    times.back() = 2 * M_PI;
    const MotionProfile s(table_of([](double t) { return std::sin(t); }, times));
    double value = 0, rate = 0;
    for (int k = 0; k <= 1000; ++k) {
      const double t = 2 * M_PI * k / 1000;
      value = std::max(value, std::fabs(s.value(t) - std::sin(t)));
      rate = std::max(rate, std::fabs(s.rate(t) - std::cos(t)));
    }
    if (n > 50) {
      EXPECT_GT(last_value / value, 10.0) << n;  // 16 for fourth order
      EXPECT_GT(last_rate / rate, 5.0) << n;     // 8 for third order
    }
    last_value = value, last_rate = rate;
  }
  EXPECT_LT(last_value, 1e-7);
  EXPECT_LT(last_rate, 1e-5);
}

TEST(MotionProfile, SplinePassesThroughTheRowsAndHoldsOutside) {
  const MotionProfile s(table_of([](double t) { return t * t * t - t; }, {0.0, 0.1, 0.35, 0.4, 1.0}));
  for (double t : {0.0, 0.1, 0.35, 0.4, 1.0}) EXPECT_NEAR(s.value(t), t * t * t - t, 1e-14) << t;
  EXPECT_DOUBLE_EQ(s.value(2.0), s.value(1.0));
  EXPECT_EQ(s.rate(2.0), 0.0);
}

TEST(MotionProfile, PolynomialHeldAfterUntil) {
  MotionSpec m;
  m.type = MotionType::translation;
  m.coefficients = {0.0, 0.1463, 72.305, -285.115};  // the gate lift of Liao et al. (2015)
  m.until = 0.1;
  const MotionProfile s(m);
  EXPECT_NEAR(s.value(0.05), 0.1463 * 0.05 + 72.305 * 0.0025 - 285.115 * 1.25e-4, 1e-15);
  EXPECT_NEAR(s.rate(0.05), 0.1463 + 2 * 72.305 * 0.05 - 3 * 285.115 * 0.0025, 1e-13);
  EXPECT_DOUBLE_EQ(s.value(0.3), s.value(0.1));
  EXPECT_EQ(s.rate(0.3), 0.0);
}

// Velocities are the time derivatives of the positions, and a rotation keeps distances to the pivot.
TEST(RigidMotion, VelocityIsTheDerivativeOfPosition) {
  MotionSpec roll;
  roll.type = MotionType::rotation;
  roll.pivot = {0.3, 0.0, 0.0};
  roll.profile = MotionLaw::sine;
  roll.amplitude = 4.0;  // degrees
  roll.period = 1.211;
  MotionSpec lift;
  lift.type = MotionType::translation;
  lift.direction = {0.6, 0.8, 0.0};
  lift.profile = MotionLaw::sine;
  lift.amplitude = 0.02;
  lift.period = 0.5;
  lift.phase = 0.3;
  const Vec<2> X{{0.1, 0.25}};
  for (const MotionSpec& spec : {roll, lift}) {
    const RigidMotion<2> m(spec);
    const Vec<2> x0 = m.position(X, 0);  // X is where the body is at t = 0, whatever s(0)
    EXPECT_DOUBLE_EQ(x0[0], X[0]);
    EXPECT_DOUBLE_EQ(x0[1], X[1]);
    for (double t : {0.0, 0.17, 0.4, 0.9}) {
      const double h = 1e-6;
      const Vec<2> fd = (1.0 / (2 * h)) * (m.position(X, t + h) - m.position(X, t - h));
      const Vec<2> v = m.velocity(X, t);
      EXPECT_NEAR(v[0], fd[0], 1e-8) << name_of(spec.type) << " t = " << t;
      EXPECT_NEAR(v[1], fd[1], 1e-8) << name_of(spec.type) << " t = " << t;
    }
  }
  const RigidMotion<2> m(roll);
  const Vec<2> pivot{{0.3, 0.0}};
  const double t = 0.3;  // theta = 4 sin(2 pi 0.3 / 1.211) degrees (s(0) = 0)
  EXPECT_NEAR(norm2(m.position(X, t) - pivot), norm2(X - pivot), 1e-15);
  const double theta = 4.0 * std::sin(2 * M_PI * t / 1.211) * M_PI / 180;
  const Vec<2> n = m.rotation(t) * Vec<2>{{1.0, 0.0}};
  EXPECT_NEAR(n[0], std::cos(theta), 1e-15);
  EXPECT_NEAR(n[1], std::sin(theta), 1e-15);
}
