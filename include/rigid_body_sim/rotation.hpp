// Quaternion helpers shared by the integrators and the references.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rigid_body {

/// exp of a rotation vector: the unit quaternion (cos(|v|/2), sin(|v|/2) v/|v|), a rotation by |v| [rad]
/// about v/|v|. Exact for v = 0 and free of NaN for tiny |v| (Taylor series of sin(θ/2)/θ below a guard).
Eigen::Quaterniond quaternionExp(const Eigen::Vector3d& rotation_vector);

/// R(q) of a possibly unnormalised quaternion, R(q/|q|): Eigen's formula scaled by 2/|q|² (no square root),
/// for the stage states of Runge–Kutta methods, whose q drifts off the unit sphere within a step.
inline Eigen::Matrix3d rotationMatrix(const Eigen::Quaterniond& q) {
  const double s = 2.0 / q.squaredNorm();
  const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
  const double sx = s * x, sy = s * y, sz = s * z;
  const double wx = w * sx, wy = w * sy, wz = w * sz;
  const double xx = x * sx, xy = y * sx, xz = z * sx;
  const double yy = y * sy, yz = z * sy, zz = z * sz;
  Eigen::Matrix3d R;
  R << 1.0 - (yy + zz), xy - wz, xz + wy,  //
      xy + wz, 1.0 - (xx + zz), yz - wx,   //
      xz - wy, yz + wx, 1.0 - (xx + yy);
  return R;
}

/// The rotation vector of a unit quaternion (inverse of quaternionExp), angle in [0, π].
Eigen::Vector3d quaternionLog(const Eigen::Quaterniond& q);

/// Angle [rad] of the rotation between two orientations: θ = 2 atan2(|vec(a⁻¹b)|, |w(a⁻¹b)|),
/// the orientation error metric of docs/references.md §3.2. In [0, π].
double rotationAngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

}  // namespace rigid_body
