#pragma once
// Private: rigid-transform arithmetic on plain doubles, used on the lookup hot paths. Quaternions
// are (w, x, y, z), unit; a QP is X = (R(q), p). Every function is a fixed sequence of IEEE
// operations, so replicas running the same build compute bit-identical results.

#include <Eigen/Geometry>
#include <cmath>

#include "quiver/graph/ids.h"

namespace quiver::kinematics::internal {

struct QP {
  double q[4] = {1.0, 0.0, 0.0, 0.0};
  double p[3] = {0.0, 0.0, 0.0};
};

/// sin(x) and cos(x) for x in [0, π/2] (interpolation angles: slerp uses r·θ with r in [0, 1]
/// and θ = acos|<q0, q1>| in [0, π/2]). Taylor series around π/4 (|y| <= π/4, so the first
/// omitted terms are below 1e-16): a few ulp from the true values, about three times faster
/// than std::sin plus std::cos, and a fixed sequence of + and × — the same bits on every machine,
/// whatever its libm.
template <class T>
[[gnu::always_inline]] inline void sincos_quarter(T x, T* s, T* c) {
  constexpr double kPi4 = 0.78539816339744830962;
  constexpr double kSqrtHalf = 0.70710678118654752440;
  const T y = x - kPi4;
  const T z = y * y;
  const T z2 = z * z;
  const T z4 = z2 * z2;
  // sin y = y (1 − z/3! + z²/5! − ...), cos y = 1 − z/2! + z²/4! − ..., evaluated by Estrin's
  // scheme (a short dependency chain: the slerp weights sit on the lookup's critical path).
  const T s01 = 1.0 + z * (-1.0 / 6);
  const T s23 = 1.0 / 120 + z * (-1.0 / 5040);
  const T s45 = 1.0 / 362880 + z * (-1.0 / 39916800);
  const T s67 = 1.0 / 6227020800 + z * (-1.0 / 1307674368000);
  const T sy = y * ((s01 + z2 * s23) + z4 * (s45 + z2 * s67));
  const T c01 = 1.0 + z * (-1.0 / 2);
  const T c23 = 1.0 / 24 + z * (-1.0 / 720);
  const T c45 = 1.0 / 40320 + z * (-1.0 / 3628800);
  const T c67 = 1.0 / 479001600 + z * (-1.0 / 87178291200);
  const double c8 = 1.0 / 20922789888000;
  const T cy = (c01 + z2 * c23) + z4 * ((c45 + z2 * c67) + z4 * c8);
  *s = (cy + sy) * kSqrtHalf;  // sin(π/4 + y)
  *c = (cy - sy) * kSqrtHalf;  // cos(π/4 + y)
}

/// a ⊗ b (T: double, or a vector of doubles for lane-wise products; `out` may be `b`).
template <class T>
[[gnu::always_inline]] inline void quat_mul(const T* a, const T* b, T* out) {
  const T w = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
  const T x = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
  const T y = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
  const T z = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
  out[0] = w;
  out[1] = x;
  out[2] = y;
  out[3] = z;
}

/// R(q)·v (`out` may be `v`).
template <class T>
[[gnu::always_inline]] inline void quat_rotate(const T* q, const T* v, T* out) {
  // t = 2 (u × v); v' = v + w t + u × t
  const T tx = 2.0 * (q[2] * v[2] - q[3] * v[1]);
  const T ty = 2.0 * (q[3] * v[0] - q[1] * v[2]);
  const T tz = 2.0 * (q[1] * v[1] - q[2] * v[0]);
  out[0] = v[0] + q[0] * tx + (q[2] * tz - q[3] * ty);
  out[1] = v[1] + q[0] * ty + (q[3] * tx - q[1] * tz);
  out[2] = v[2] + q[0] * tz + (q[1] * ty - q[2] * tx);
}

/// X_AC = X_AB · X_BC.
[[gnu::always_inline]] inline QP compose(const QP& X_AB, const QP& X_BC) {
  QP X_AC;
  quat_mul(X_AB.q, X_BC.q, X_AC.q);
  double r[3];
  quat_rotate(X_AB.q, X_BC.p, r);
  X_AC.p[0] = X_AB.p[0] + r[0];
  X_AC.p[1] = X_AB.p[1] + r[1];
  X_AC.p[2] = X_AB.p[2] + r[2];
  return X_AC;
}

/// X_BA from X_AB.
[[gnu::always_inline]] inline QP inverse(const QP& X_AB) {
  QP X_BA;
  X_BA.q[0] = X_AB.q[0];
  X_BA.q[1] = -X_AB.q[1];
  X_BA.q[2] = -X_AB.q[2];
  X_BA.q[3] = -X_AB.q[3];
  double r[3];
  quat_rotate(X_BA.q, X_AB.p, r);
  X_BA.p[0] = -r[0];
  X_BA.p[1] = -r[1];
  X_BA.p[2] = -r[2];
  return X_BA;
}

/// Row-major rotation matrix of a quaternion (normalised first).
inline void quat_to_matrix(const double* q_in, double* R) {
  const double n =
      std::sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] + q_in[3] * q_in[3]);
  const double w = q_in[0] / n, x = q_in[1] / n, y = q_in[2] / n, z = q_in[3] / n;
  R[0] = 1.0 - 2.0 * (y * y + z * z);
  R[1] = 2.0 * (x * y - w * z);
  R[2] = 2.0 * (x * z + w * y);
  R[3] = 2.0 * (x * y + w * z);
  R[4] = 1.0 - 2.0 * (x * x + z * z);
  R[5] = 2.0 * (y * z - w * x);
  R[6] = 2.0 * (x * z - w * y);
  R[7] = 2.0 * (y * z + w * x);
  R[8] = 1.0 - 2.0 * (x * x + y * y);
}

inline Eigen::Isometry3d to_isometry(const double* R, const double* p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() << R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8];
  X.translation() << p[0], p[1], p[2];
  return X;
}

/// A graph pose as a QP with its quaternion normalised (a zero quaternion becomes identity).
inline QP from_pose(const graph::Pose& pose) {
  QP X;
  const auto& r = pose.rotation;
  const double n = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
  if (n > 0.0 && std::isfinite(n)) {
    for (int i = 0; i < 4; ++i) X.q[i] = r[i] / n;
  }
  for (int i = 0; i < 3; ++i) X.p[i] = pose.translation[i];
  return X;
}

}  // namespace quiver::kinematics::internal
