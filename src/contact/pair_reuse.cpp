#include "pair_reuse.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigid_body {
namespace contact {

bool PairReuse::standsStill(std::size_t a, std::size_t b, const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB,
                            double reach_a, double reach_b, double max_distance) {
  reused_ = false;
  if (!holds(a, b) || max_distance != max_distance_) return false;
  const double bound = kReuseShare * max_distance;
  // Each way round the bound is at least how far the other shape's origin moved (b's in a's frame, a's in
  // b's): a pair whose origins both moved farther, as every moving pair's do, is refused before the turn is
  // formed. An infinite reach leaves that way out.
  const Eigen::Vector3d d = X_WB.translation() - X_WA.translation();
  const Eigen::Vector3d p_AB = X_WA.linear().transpose() * d, p_BA = -(X_WB.linear().transpose() * d);
  const double infinity = std::numeric_limits<double>::infinity();
  const double shift_b = std::isfinite(reach_b) ? (p_AB - p_AB_).norm() : infinity;
  const double shift_a = std::isfinite(reach_a) ? (p_BA - p_BA_).norm() : infinity;
  if (!(std::min(shift_a, shift_b) <= bound)) return false;
  const double turned = (X_WA.linear().transpose() * X_WB.linear() - R_AB_).norm();
  reused_ = std::min(turned * reach_b + shift_b, turned * reach_a + shift_a) <= bound;
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
  const Eigen::Vector3d d = X_WB.translation() - X_WA.translation();
  R_AB_ = R_AW * X_WB.linear();
  p_AB_ = R_AW * d;
  p_BA_ = -(X_WB.linear().transpose() * d);
  if (!R_AB_.allFinite() || !p_AB_.allFinite() || !p_BA_.allFinite()) return;
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
