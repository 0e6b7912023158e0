#pragma once
// Prescribed rigid motion of walls and of structure clamps (io/case.hpp MotionSpec): the moving tank
// of a sloshing case, the lifted gate of a dam break, the sliding plate of Couette flow.
#include <stdexcept>
#include <string>
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

// A rigid motion at one time, as plain data that device loops read: a translation x = X + shift with
// velocity shift_rate, or a turn by R about `pivot`, x = pivot + R (X - pivot), with the angular rate
// omega [rad/s] and velocity v = omega e_z x (x - pivot) (2D).
template <int D>
struct RigidPose {
  bool rotates = false;
  Mat<D> R = Mat<D>::identity();
  Vec<D> pivot = Vec<D>::zero();
  Vec<D> shift = Vec<D>::zero(), shift_rate = Vec<D>::zero();
  Real omega = 0;
  ISPH_HD Vec<D> position(const Vec<D>& X) const { return rotates ? pivot + R * (X - pivot) : X + shift; }
  ISPH_HD Vec<D> velocity(const Vec<D>& X) const {
    if (!rotates) return shift_rate;
    const Vec<D> r = R * (X - pivot);
    Vec<D> v = Vec<D>::zero();
    v[0] = -omega * r[1];
    v[1] = omega * r[0];
    return v;
  }
};

// The poses of a scene's motions at one time, handed to a launch by value (in the kernel's arguments),
// so that the host writes no array of poses in device memory before every launch. A scene has at most
// kMaxMotions moving bodies among its walls, and as many among its clamped structures.
inline constexpr int kMaxMotions = 16;
template <int D>
struct PoseTable {
  RigidPose<D> pose[kMaxMotions];
  ISPH_HD const RigidPose<D>& operator[](Index m) const { return pose[m]; }
};

// x(X, t) of a motion and its velocity: X moves by s(t) - s(0) (a rotation in 2D: turns about `pivot`
// by that many degrees), so that X is the position at t = 0.
template <int D>
class RigidMotion {
 public:
  explicit RigidMotion(const MotionSpec& m);
  RigidPose<D> pose(Real t) const;
  Vec<D> position(const Vec<D>& X, Real t) const { return pose(t).position(X); }
  Vec<D> velocity(const Vec<D>& X, Real t) const { return pose(t).velocity(X); }
  Mat<D> rotation(Real t) const { return pose(t).R; }  // identity for translations

 private:
  bool rotates_ = false;
  Vec<D> direction_ = Vec<D>::zero();  // translation: x = X + s(t) direction
  Vec<D> pivot_ = Vec<D>::zero();
  MotionProfile profile_;
  Real s0_ = 0;  // s(0)
};

// Each motion's pose at time t.
template <int D>
PoseTable<D> poses_at(const std::vector<RigidMotion<D>>& motions, Real t) {
  if (motions.size() > static_cast<std::size_t>(kMaxMotions))
    throw std::invalid_argument("at most " + std::to_string(kMaxMotions) + " moving bodies are supported");
  PoseTable<D> table;
  for (std::size_t m = 0; m < motions.size(); ++m) table.pose[m] = motions[m].pose(t);
  return table;
}

}  // namespace isph
