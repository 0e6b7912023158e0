#include "core/rigid_motion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace isph {

MotionProfile::MotionProfile(const MotionSpec& m) {
  if (m.type == MotionType::constant_velocity) {  // s = t along the velocity
    coefficients_ = {0.0, 1.0};
    return;
  }
  if (m.profile == MotionLaw::polynomial) {
    coefficients_ = m.coefficients;
    until_ = m.until;
  } else if (m.profile == MotionLaw::sine) {
    kind_ = Kind::sine;
    amplitude_ = m.amplitude;
    omega_ = 2 * M_PI / m.period;
    phase_ = m.phase;
  } else {
    kind_ = Kind::spline;
    t_ = m.times;
    s_ = m.values;
    const std::size_t n = t_.size();
    if (n < 2) throw std::invalid_argument("a motion table needs at least two rows");
    // Thomas algorithm for h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (d_i - d_{i-1}),
    // d_i = (s_{i+1} - s_i) / h_i, i = 1 .. n-2.
    m_.assign(n, 0.0);
    std::vector<Real> diag(n, 1.0), rhs(n, 0.0), upper(n, 0.0);
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const Real h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      const Real lower = h0;
      diag[i] = 2 * (h0 + h1);
      upper[i] = h1;
      rhs[i] = 6 * ((s_[i + 1] - s_[i]) / h1 - (s_[i] - s_[i - 1]) / h0);
      if (i > 1) {
        const Real factor = lower / diag[i - 1];
        diag[i] -= factor * upper[i - 1];
        rhs[i] -= factor * rhs[i - 1];
      }
    }
    for (std::size_t i = n - 2; i >= 1; --i) m_[i] = (rhs[i] - upper[i] * m_[i + 1]) / diag[i];
  }
}

Index MotionProfile::interval(Real t) const {
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  const Index i = static_cast<Index>(it - t_.begin()) - 1;
  return std::clamp<Index>(i, 0, static_cast<Index>(t_.size()) - 2);
}

Real MotionProfile::value(Real t) const {
  switch (kind_) {
    case Kind::polynomial: {
      if (until_ > 0) t = std::min(t, until_);
      Real s = 0;
      for (std::size_t k = coefficients_.size(); k-- > 0;) s = s * t + coefficients_[k];
      return s;
    }
    case Kind::sine:
      return amplitude_ * std::sin(omega_ * t + phase_);
    case Kind::spline:
      break;
  }
  t = std::clamp(t, t_.front(), t_.back());
  const Index i = interval(t);
  const Real h = t_[i + 1] - t_[i], A = (t_[i + 1] - t) / h, B = 1 - A;
  return A * s_[i] + B * s_[i + 1] + ((A * A * A - A) * m_[i] + (B * B * B - B) * m_[i + 1]) * h * h / 6;
}

Real MotionProfile::rate(Real t) const {
  switch (kind_) {
    case Kind::polynomial: {
      if (until_ > 0 && t > until_) return 0;
      Real r = 0;
      for (std::size_t k = coefficients_.size(); k-- > 1;) r = r * t + k * coefficients_[k];
      return r;
    }
    case Kind::sine:
      return amplitude_ * omega_ * std::cos(omega_ * t + phase_);
    case Kind::spline:
      break;
  }
  if (t < t_.front() || t > t_.back()) return 0;
  const Index i = interval(t);
  const Real h = t_[i + 1] - t_[i], A = (t_[i + 1] - t) / h, B = 1 - A;
  return (s_[i + 1] - s_[i]) / h + ((1 - 3 * A * A) * m_[i] + (3 * B * B - 1) * m_[i + 1]) * h / 6;
}

template <int D>
RigidMotion<D>::RigidMotion(const MotionSpec& m) : profile_(m), s0_(profile_.value(0)) {
  if (m.type == MotionType::rotation) {
    if (D != 2) throw std::invalid_argument("a rotation is a 2D motion");
    rotates_ = true;
    pivot_ = to_vec<D>(m.pivot);
  } else if (m.type == MotionType::constant_velocity) {
    direction_ = to_vec<D>(m.velocity);
  } else if (m.type == MotionType::translation) {
    direction_ = to_vec<D>(m.direction);
  }
}

template <int D>
RigidPose<D> RigidMotion<D>::pose(Real t) const {
  RigidPose<D> p;
  p.rotates = rotates_;
  if (!rotates_) {
    p.shift = (profile_.value(t) - s0_) * direction_;
    p.shift_rate = profile_.rate(t) * direction_;
    return p;
  }
  if constexpr (D == 2) {
    const Real theta = (profile_.value(t) - s0_) * M_PI / 180;
    p.R(0, 0) = p.R(1, 1) = std::cos(theta);
    p.R(1, 0) = std::sin(theta);
    p.R(0, 1) = -p.R(1, 0);
    p.pivot = pivot_;
    p.omega = profile_.rate(t) * M_PI / 180;
  }
  return p;
}

template class RigidMotion<2>;
template class RigidMotion<3>;

}  // namespace isph
