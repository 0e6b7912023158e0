#pragma once
// Prescribed rigid motion of walls and of structure clamps (io/case.hpp MotionSpec): the moving tank
// of a sloshing case, the lifted gate of a dam break, the sliding plate of Couette flow.
#include <vector>

#include "core/types.hpp"
#include "io/case.hpp"

namespace isph {

// The scalar law s(t) of a motion and its rate ds/dt (MotionSpec::profile).
class MotionProfile {
 public:
  MotionProfile() = default;
  explicit MotionProfile(const MotionSpec& m);
  Real value(Real t) const;
  Real rate(Real t) const;

 private:
  enum class Kind { polynomial, sine, spline } kind_ = Kind::polynomial;
  std::vector<Real> coefficients_;
  Real until_ = 0;
  Real amplitude_ = 0, omega_ = 0, phase_ = 0;
  // Natural cubic spline through (t_i, s_i): on [t_i, t_i+1], with h = t_i+1 - t_i, A = (t_i+1 - t)/h and
  // B = 1 - A, s = A s_i + B s_i+1 + ((A^3 - A) M_i + (B^3 - B) M_i+1) h^2 / 6, where the second
  // derivatives M solve the tridiagonal continuity equations with M_0 = M_n = 0.
  std::vector<Real> t_, s_, m_;
  Index interval(Real t) const;
};

// x(X, t) of a motion and its velocity: X moves by s(t) - s(0) (a rotation in 2D: turns about `pivot`
// by that many degrees), so that X is the position at t = 0.
template <int D>
class RigidMotion {
 public:
  explicit RigidMotion(const MotionSpec& m);
  Vec<D> position(const Vec<D>& X, Real t) const;
  Vec<D> velocity(const Vec<D>& X, Real t) const;
  Mat<D> rotation(Real t) const;  // identity for translations

 private:
  bool rotates_ = false;
  Vec<D> direction_ = Vec<D>::zero();  // translation: x = X + s(t) direction
  Vec<D> pivot_ = Vec<D>::zero();
  MotionProfile profile_;
  Real s0_ = 0;  // s(0)
};

}  // namespace isph
