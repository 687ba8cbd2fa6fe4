#include "rigid_body_sim/rotation.hpp"

#include <cmath>

namespace rigid_body {

namespace {
// Below this angle sin(θ/2)/θ is replaced by its Taylor series 1/2 − θ²/48 + θ⁴/3840; the next term,
// θ⁶/645120, is below 1e-16 relative there, so the series is exact to rounding.
constexpr double kSmallAngle = 1e-3;
}  // namespace

Eigen::Quaterniond quaternionExp(const Eigen::Vector3d& rotation_vector) {
  const double theta = rotation_vector.norm();
  const double half = 0.5 * theta;
  double sinc_half;  // sin(θ/2)/θ
  if (theta < kSmallAngle) {
    const double theta2 = theta * theta;
    sinc_half = 0.5 - theta2 / 48.0 + theta2 * theta2 / 3840.0;
  } else {
    sinc_half = std::sin(half) / theta;
  }
  const Eigen::Vector3d vec = sinc_half * rotation_vector;
  return Eigen::Quaterniond(std::cos(half), vec.x(), vec.y(), vec.z());
}

Eigen::Vector3d quaternionLog(const Eigen::Quaterniond& q) {
  // Take the representative with w ≥ 0 so the angle lies in [0, π].
  const double sign = q.w() < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d vec = sign * q.vec();
  const double vec_norm = vec.norm();
  const double w = sign * q.w();
  const double theta = 2.0 * std::atan2(vec_norm, w);
  if (vec_norm < 1e-300) return 2.0 * vec;  // θ ≈ 2|vec| to first order; exact zero stays zero.
  return (theta / vec_norm) * vec;
}

double rotationAngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().stableNorm(), std::abs(d.w()));  // stableNorm: angles down to 1e-300
}

}  // namespace rigid_body
