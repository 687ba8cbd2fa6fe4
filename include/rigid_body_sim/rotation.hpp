// Quaternion helpers shared by the integrators and the references.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rigid_body {

/// exp of a rotation vector: the unit quaternion (cos(|v|/2), sin(|v|/2) v/|v|), a rotation by |v| [rad]
/// about v/|v|. Exact for v = 0 and free of NaN for tiny |v| (halfAngleSeries below kHalfAngleSeriesLimit).
Eigen::Quaterniond quaternionExp(const Eigen::Vector3d& rotation_vector);

/// Up to θ² = 1/16, cos(θ/2) and sin(θ/2)/θ come from their Taylor series in y = (θ/2)², through y⁵: the
/// first terms left out, y⁶/12! and y⁶/13!, are below 4e-20 there, under the rounding of either value. No
/// square root, sine or cosine: a step's rotation (h|ω| ≤ 0.25 rad, |ω| up to 250 rad/s at 1 ms) costs two
/// short polynomials.
constexpr double kHalfAngleSeriesLimit = 1.0 / 16.0;

/// cos(θ/2) and sin(θ/2)/θ from θ² ≤ kHalfAngleSeriesLimit, by the series above. A template so that the
/// integrators' lanes (several bodies' θ² at once) take the same operations in the same order.
template <class T>
inline void halfAngleSeries(const T& theta2, T& cos_half, T& sinc_half) {
  const T y = 0.25 * theta2;
  cos_half = 1.0 - y * (1.0 / 2 - y * (1.0 / 24 - y * (1.0 / 720 - y * (1.0 / 40320 - y * (1.0 / 3628800)))));
  sinc_half = 0.5 * (1.0 - y * (1.0 / 6 - y * (1.0 / 120 - y * (1.0 / 5040 - y * (1.0 / 362880 - y * (1.0 / 39916800))))));
}

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
