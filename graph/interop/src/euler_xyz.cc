// Poses in the source formats' convention (a translation in millimetres, Euler angles in radians with
// R = Rx·Ry·Rz) to and from Quiver's (metres, a unit quaternion).
#include "euler_xyz.h"

#include <cmath>

namespace quiver::interop::internal {

graph::Pose pose_from_xyz(const std::array<double, 3>& t, const std::array<double, 3>& r, double metres_per_unit) {
  graph::Pose X;
  // Dividing by 1000 (not multiplying by 0.001, which is inexact) gives the double nearest to the
  // metres the file means.
  const double units_per_metre = 1.0 / metres_per_unit;
  for (int i = 0; i < 3; ++i) X.translation[i] = t[i] / units_per_metre;
  // q = q_x(rx) ⊗ q_y(ry) ⊗ q_z(rz), the quaternion of Rx·Ry·Rz.
  const double ca = std::cos(r[0] / 2), sa = std::sin(r[0] / 2);
  const double cb = std::cos(r[1] / 2), sb = std::sin(r[1] / 2);
  const double cc = std::cos(r[2] / 2), sc = std::sin(r[2] / 2);
  X.rotation = {ca * cb * cc - sa * sb * sc, sa * cb * cc + ca * sb * sc, ca * sb * cc - sa * cb * sc,
                ca * cb * sc + sa * sb * cc};
  return X;
}

void xyz_from_pose(const graph::Pose& X, double metres_per_unit, std::array<double, 3>& t, std::array<double, 3>& r) {
  const double units_per_metre = 1.0 / metres_per_unit;
  for (int i = 0; i < 3; ++i) t[i] = X.translation[i] * units_per_metre;
  const double w = X.rotation[0], x = X.rotation[1], y = X.rotation[2], z = X.rotation[3];
  const double n2 = w * w + x * x + y * y + z * z;
  const double s = n2 > 0 ? 2.0 / n2 : 0.0;
  // The rotation matrix of q; Rx·Ry·Rz with a = rx, b = ry, c = rz is
  //   [[cb cc, -cb sc, sb], [ca sc + sa sb cc, ca cc - sa sb sc, -sa cb], [sa sc - ca sb cc, sa cc + ca sb sc, ca cb]].
  const double r02 = s * (x * z + w * y);
  const double r10 = s * (x * y + w * z), r11 = 1 - s * (x * x + z * z), r12 = s * (y * z - w * x);
  const double r20 = s * (x * z - w * y), r21 = s * (y * z + w * x), r22 = 1 - s * (x * x + y * y);
  // a from the last column; then b and c from Rx(a)ᵀ·R = Ry(b)·Rz(c), whose elements used here
  // are O(1): near ry = ±π/2 (where a and c are ill-determined one by one) c absorbs the error
  // in a, and the angles still give R to a few ulp. At ry = ±π/2 exactly, rx = 0.
  r[0] = std::hypot(r12, r22) > 1e-12 ? std::atan2(-r12, r22) : 0.0;
  const double ca = std::cos(r[0]), sa = std::sin(r[0]);
  r[1] = std::atan2(r02, ca * r22 - sa * r12);
  r[2] = std::atan2(ca * r10 + sa * r20, ca * r11 + sa * r21);
}

}  // namespace quiver::interop::internal
