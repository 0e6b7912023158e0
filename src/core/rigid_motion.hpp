#pragma once
// Prescribed rigid motion of walls and of structure clamps: the moving tank of a sloshing case, the
// lifted gate of a dam break, the sliding plate of Couette flow. The case file's motion (MotionSpec)
// is declared here rather than in io/case.hpp, so that the structure solver takes motions without
// depending on the case description.
#include <array>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "core/types.hpp"

namespace isph {

enum class MotionType { none, constant_velocity, translation, rotation };
constexpr EnumName<MotionType> kMotionTypeNames[] = {{MotionType::none, "none"},
                                                     {MotionType::constant_velocity, "constant_velocity"},
                                                     {MotionType::translation, "translation"},
                                                     {MotionType::rotation, "rotation"}};
constexpr std::span<const EnumName<MotionType>> enum_names(MotionType) { return kMotionTypeNames; }

// The law s(t) of a translation or a rotation.
enum class MotionLaw { polynomial, sine, csv };
constexpr EnumName<MotionLaw> kMotionLawNames[] = {
    {MotionLaw::polynomial, "polynomial"}, {MotionLaw::sine, "sine"}, {MotionLaw::csv, "csv"}};
constexpr std::span<const EnumName<MotionLaw>> enum_names(MotionLaw) { return kMotionLawNames; }

// Prescribed rigid motion of a wall body, or of the clamped particles of a structure body (their
// clamp moves with it: the baffle of a rolling tank). X is a particle's position as the case file draws
// it, which is its position at t = 0: the body moves by s(t) - s(0).
//  "none":              fixed.
//  "constant_velocity": x = X + velocity t.
//  "translation":       x = X + (s(t) - s(0)) direction, s in metres.
//  "rotation" (2D):     x = pivot + R(theta) (X - pivot), theta = s(t) - s(0) in degrees, counter-clockwise.
// s(t) follows `profile`:
//  "polynomial": s = sum_k coefficients[k] t^k, held at s(until) after t = until (until = 0: never held);
//  "sine":       s = amplitude sin(2 pi t / period + phase);
//  "csv":        rows "time, s" of a file, strictly increasing in time and reaching end_time,
//                interpolated by a natural cubic spline (so that the velocity and acceleration are
//                continuous); before the first row the first value holds.
struct MotionSpec {
  MotionType type = MotionType::none;
  std::array<double, 3> velocity{};           // constant_velocity [m/s]
  std::array<double, 3> direction{0, 1, 0};   // translation (unit)
  std::array<double, 3> pivot{};              // rotation
  MotionLaw profile = MotionLaw::polynomial;  // translation, rotation
  std::vector<double> coefficients;           // polynomial [m or deg, per s^k]
  double until = 0.0;                         // polynomial [s]
  double amplitude = 0.0;                     // sine [m or deg]
  double period = 0.0;                        // sine [s]
  double phase = 0.0;                         // sine [rad]
  std::string file;                           // csv: as given, resolved against the case file's folder
  std::vector<double> times, values;          // csv: the rows, read by the loader
  bool operator==(const MotionSpec&) const = default;
};

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
