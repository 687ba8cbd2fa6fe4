#include "pair_reuse.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigid_body {
namespace contact {

bool PairReuse::standsStill(std::size_t a, std::size_t b, const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB,
                            double reach_a, double reach_b, double max_distance) {
  reused_ = false;
  if (!stored_ || a != a_ || b != b_ || max_distance != max_distance_) return false;
  const Eigen::Matrix3d R_AW = X_WA.linear().transpose();
  const Eigen::Matrix3d R_AB = R_AW * X_WB.linear();
  const Eigen::Vector3d p_AB = R_AW * (X_WB.translation() - X_WA.translation());
  // b's origin moved by p − p₀ in a's frame; a's origin in b's frame is −Rᵀp, and moved by R₀ᵀp₀ − Rᵀp.
  const double turned = (R_AB - R_AB_).norm();
  const auto moved = [turned](double reach, double shift) {
    return std::isfinite(reach) ? turned * reach + shift : std::numeric_limits<double>::infinity();
  };
  const double b_seen_from_a = moved(reach_b, (p_AB - p_AB_).norm());
  const double a_seen_from_b = moved(reach_a, (R_AB_.transpose() * p_AB_ - R_AB.transpose() * p_AB).norm());
  reused_ = std::min(b_seen_from_a, a_seen_from_b) <= kReuseShare * max_distance;
  return reused_;
}

void PairReuse::appendPoints(const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB, double max_distance,
                             std::vector<ContactPoint>& points) const {
  const Eigen::Vector3d normal = X_WA.linear() * normal_A_;
  for (std::size_t i = 0; i < count_; ++i) {
    ContactPoint point;
    point.a = a_, point.b = b_;
    point.on_a = X_WA * on_a_A_[i];
    point.on_b = X_WB * on_b_B_[i];
    point.normal = normal;
    point.distance = normal.dot(point.on_a - point.on_b);
    if (point.distance <= max_distance) points.push_back(point);
  }
}

void PairReuse::store(std::size_t a, std::size_t b, const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB,
                      double max_distance, const std::vector<ContactPoint>& points, std::size_t first) {
  stored_ = false;
  const std::size_t count = points.size() - first;
  if (count > on_a_A_.size()) return;
  for (std::size_t i = first; i < points.size(); ++i) {
    if (points[i].normal != points[first].normal || points[i].speculative || points[i].a != a || points[i].b != b) return;
  }
  const Eigen::Matrix3d R_AW = X_WA.linear().transpose();
  R_AB_ = R_AW * X_WB.linear();
  p_AB_ = R_AW * (X_WB.translation() - X_WA.translation());
  if (!R_AB_.allFinite() || !p_AB_.allFinite()) return;
  const Eigen::Isometry3d X_AW = X_WA.inverse(), X_BW = X_WB.inverse();
  normal_A_ = count > 0 ? Eigen::Vector3d(R_AW * points[first].normal) : Eigen::Vector3d::UnitZ();
  for (std::size_t i = 0; i < count; ++i) {
    on_a_A_[i] = X_AW * points[first + i].on_a;
    on_b_B_[i] = X_BW * points[first + i].on_b;
  }
  a_ = a, b_ = b, max_distance_ = max_distance, count_ = count;
  stored_ = true;
}

}  // namespace contact
}  // namespace rigid_body
