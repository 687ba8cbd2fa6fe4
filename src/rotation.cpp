#include "rigid_body_sim/rotation.hpp"

#include <cmath>

namespace rigid_body {

Eigen::Quaterniond quaternionExp(const Eigen::Vector3d& rotation_vector) {
  const double theta2 = rotation_vector.squaredNorm();
  double cos_half, sinc_half;  // cos(θ/2), sin(θ/2)/θ
  if (theta2 <= kHalfAngleSeriesLimit) {
    halfAngleSeries(theta2, cos_half, sinc_half);
  } else {
    const double theta = std::sqrt(theta2);
    cos_half = std::cos(0.5 * theta);
    sinc_half = std::sin(0.5 * theta) / theta;
  }
  const Eigen::Vector3d vec = sinc_half * rotation_vector;
  return Eigen::Quaterniond(cos_half, vec.x(), vec.y(), vec.z());
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
