#include "pair_reuse.hpp"

#include <cmath>

namespace rigid_body {
namespace contact {

bool PairReuse::reuse(std::size_t a, std::size_t b, const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB,
                      double reach_b, double max_distance, std::vector<ContactPoint>& points) {
  reused_ = false;
  if (!stored_ || a != a_ || b != b_ || max_distance != max_distance_) return false;
  // A point x of b (|x| ≤ reach_b in b's frame) is at R x + p in a's frame: since the points were made it has
  // moved by (R − R₀) x + (p − p₀), at most ‖R − R₀‖_F reach_b + |p − p₀| (the Frobenius norm bounds the
  // spectral one). Not finite: never reused.
  const Eigen::Matrix3d R_AW = X_WA.linear().transpose();
  const Eigen::Matrix3d R_AB = R_AW * X_WB.linear();
  const Eigen::Vector3d p_AB = R_AW * (X_WB.translation() - X_WA.translation());
  const double moved = (R_AB - R_AB_).norm() * reach_b + (p_AB - p_AB_).norm();
  if (!(moved <= kReuseShare * max_distance)) return false;
  const Eigen::Vector3d normal = X_WA.linear() * normal_A_;
  for (std::size_t i = 0; i < count_; ++i) {
    ContactPoint point;
    point.a = a, point.b = b;
    point.on_a = X_WA * on_a_A_[i];
    point.on_b = X_WB * on_b_B_[i];
    point.normal = normal;
    point.distance = normal.dot(point.on_a - point.on_b);
    if (point.distance <= max_distance) points.push_back(point);
  }
  reused_ = true;
  return true;
}

void PairReuse::store(std::size_t a, std::size_t b, const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB,
                      double max_distance, const std::vector<ContactPoint>& points, std::size_t first) {
  stored_ = false;
  const std::size_t count = points.size() - first;
  if (count > on_a_A_.size()) return;
  for (std::size_t i = first; i < points.size(); ++i) {
    if (points[i].normal != points[first].normal || points[i].speculative) return;
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
