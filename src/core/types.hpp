#pragma once
// Small fixed-size vector and matrix types usable in host and device code.
// Functors use these rather than Eigen so that the same code compiles under nvcc.
#include <array>
#include <cmath>
#include <cstdint>

#if defined(__CUDACC__)
#define ISPH_HD __host__ __device__
#else
#define ISPH_HD
#endif

namespace isph {

using Real = double;
using Index = std::int32_t;

template <int D>
struct Vec {
  Real c[D];
  ISPH_HD Real& operator[](int i) { return c[i]; }
  ISPH_HD const Real& operator[](int i) const { return c[i]; }
  ISPH_HD static Vec zero() {
    Vec v;
    for (int i = 0; i < D; ++i) v.c[i] = 0;
    return v;
  }
};

template <int D>
ISPH_HD inline Vec<D> operator+(const Vec<D>& a, const Vec<D>& b) {
  Vec<D> r;
  for (int i = 0; i < D; ++i) r[i] = a[i] + b[i];
  return r;
}
template <int D>
ISPH_HD inline Vec<D> operator-(const Vec<D>& a, const Vec<D>& b) {
  Vec<D> r;
  for (int i = 0; i < D; ++i) r[i] = a[i] - b[i];
  return r;
}
template <int D>
ISPH_HD inline Vec<D> operator*(Real s, const Vec<D>& a) {
  Vec<D> r;
  for (int i = 0; i < D; ++i) r[i] = s * a[i];
  return r;
}
template <int D>
ISPH_HD inline Vec<D>& operator+=(Vec<D>& a, const Vec<D>& b) {
  for (int i = 0; i < D; ++i) a[i] += b[i];
  return a;
}
template <int D>
ISPH_HD inline Real dot(const Vec<D>& a, const Vec<D>& b) {
  Real s = 0;
  for (int i = 0; i < D; ++i) s += a[i] * b[i];
  return s;
}
template <int D>
ISPH_HD inline Real norm2(const Vec<D>& a) {
  return dot(a, a);
}

// The spacing of a particle of volume V (its cell's edge), V^(1/D).
template <int D>
ISPH_HD inline Real particle_spacing(Real volume) {
  return pow(volume, 1.0 / D);
}

// Row-major D x D matrix.
template <int D>
struct Mat {
  Real m[D][D];
  ISPH_HD Real& operator()(int i, int j) { return m[i][j]; }
  ISPH_HD const Real& operator()(int i, int j) const { return m[i][j]; }
  ISPH_HD static Mat zero() {
    Mat a;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) a.m[i][j] = 0;
    return a;
  }
  ISPH_HD static Mat identity() {
    Mat a = zero();
    for (int i = 0; i < D; ++i) a.m[i][i] = 1;
    return a;
  }
};

template <int D>
ISPH_HD inline Mat<D> operator+(const Mat<D>& a, const Mat<D>& b) {
  Mat<D> r;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r(i, j) = a(i, j) + b(i, j);
  return r;
}
template <int D>
ISPH_HD inline Mat<D> operator-(const Mat<D>& a, const Mat<D>& b) {
  Mat<D> r;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r(i, j) = a(i, j) - b(i, j);
  return r;
}
template <int D>
ISPH_HD inline Mat<D> operator*(Real s, const Mat<D>& a) {
  Mat<D> r;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r(i, j) = s * a(i, j);
  return r;
}
template <int D>
ISPH_HD inline Mat<D> operator*(const Mat<D>& a, const Mat<D>& b) {
  Mat<D> r = Mat<D>::zero();
  for (int i = 0; i < D; ++i)
    for (int k = 0; k < D; ++k)
      for (int j = 0; j < D; ++j) r(i, j) += a(i, k) * b(k, j);
  return r;
}
template <int D>
ISPH_HD inline Vec<D> operator*(const Mat<D>& a, const Vec<D>& v) {
  Vec<D> r = Vec<D>::zero();
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r[i] += a(i, j) * v[j];
  return r;
}
template <int D>
ISPH_HD inline Mat<D> transpose(const Mat<D>& a) {
  Mat<D> r;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r(i, j) = a(j, i);
  return r;
}
// a ⊗ b : (a ⊗ b)_ij = a_i b_j
template <int D>
ISPH_HD inline Mat<D> outer(const Vec<D>& a, const Vec<D>& b) {
  Mat<D> r;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r(i, j) = a[i] * b[j];
  return r;
}
template <int D>
ISPH_HD inline Real trace(const Mat<D>& a) {
  Real s = 0;
  for (int i = 0; i < D; ++i) s += a(i, i);
  return s;
}
// A : B
template <int D>
ISPH_HD inline Real ddot(const Mat<D>& a, const Mat<D>& b) {
  Real s = 0;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) s += a(i, j) * b(i, j);
  return s;
}

ISPH_HD inline Real determinant(const Mat<2>& a) { return a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0); }
ISPH_HD inline Real determinant(const Mat<3>& a) {
  return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
         a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
}

// Inverse by the adjugate; the caller checks the determinant when the matrix may be singular.
ISPH_HD inline Mat<2> inverse(const Mat<2>& a) {
  const Real inv = 1.0 / determinant(a);
  Mat<2> r;
  r(0, 0) = a(1, 1) * inv;
  r(0, 1) = -a(0, 1) * inv;
  r(1, 0) = -a(1, 0) * inv;
  r(1, 1) = a(0, 0) * inv;
  return r;
}
ISPH_HD inline Mat<3> inverse(const Mat<3>& a) {
  const Real inv = 1.0 / determinant(a);
  Mat<3> r;
  r(0, 0) = (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) * inv;
  r(0, 1) = (a(0, 2) * a(2, 1) - a(0, 1) * a(2, 2)) * inv;
  r(0, 2) = (a(0, 1) * a(1, 2) - a(0, 2) * a(1, 1)) * inv;
  r(1, 0) = (a(1, 2) * a(2, 0) - a(1, 0) * a(2, 2)) * inv;
  r(1, 1) = (a(0, 0) * a(2, 2) - a(0, 2) * a(2, 0)) * inv;
  r(1, 2) = (a(0, 2) * a(1, 0) - a(0, 0) * a(1, 2)) * inv;
  r(2, 0) = (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0)) * inv;
  r(2, 1) = (a(0, 1) * a(2, 0) - a(0, 0) * a(2, 1)) * inv;
  r(2, 2) = (a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0)) * inv;
  return r;
}

// Whether a symmetric matrix is positive definite (Sylvester: every leading principal minor > 0).
// |v| <= the largest double: false for NaN and +-Inf (std::isfinite is not a device function).
ISPH_HD inline bool finite_value(double v) { return fabs(v) <= 1.7976931348623157e308; }

ISPH_HD inline bool positive_definite(const Mat<2>& a) { return a(0, 0) > 0 && determinant(a) > 0; }
ISPH_HD inline bool positive_definite(const Mat<3>& a) {
  return a(0, 0) > 0 && a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0) > 0 && determinant(a) > 0;
}

// The first D components of a case-file vector (host code).
template <int D>
inline Vec<D> to_vec(const std::array<double, 3>& a) {
  Vec<D> v;
  for (int d = 0; d < D; ++d) v[d] = a[d];
  return v;
}

// A vector as three components, z = 0 in 2D (case-file points, snapshot fields; host code).
template <int D>
inline std::array<double, 3> to_array(const Vec<D>& v) {
  std::array<double, 3> a{0, 0, 0};
  for (int d = 0; d < D; ++d) a[d] = v[d];
  return a;
}

}  // namespace isph
