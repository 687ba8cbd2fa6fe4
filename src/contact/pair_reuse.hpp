// A pair's contact points kept from one detection to the next while the pair's relative pose stays put
// (docs/contact.md, step 2, "Points reused at rest"): two faces resting on each other have the same points,
// to far below the near distance, step after step, and recomputing them (a GJK query or a separating-axis
// test of fifteen axes, two supporting faces, clipping) is most of a resting scene's detection. Jolt's
// contact manager reuses a body pair's manifold the same way (ContactConstraintManager, "body pair cache"),
// within a millimetre and two degrees; here the bound is a thousandth of the near distance. Bullet-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <vector>

#include "collision_world.hpp"

namespace rigid_body {
namespace contact {

/// How far any point of one shape may have moved relative to the other, as a share of the near distance,
/// for the pair's points to be reused: a tenth of a micrometre at the default slop of 0.1 mm.
constexpr double kReuseShare = 1e-3;

/// One pair's points as last made, in each shape's own frame, with the relative pose they were made at.
class PairReuse {
 public:
  /// Whether the points stored are the pair's (objects a and b, shapes at X_WA and X_WB), made with the same
  /// near distance, and no point of either shape has moved relative to the other by more than kReuseShare ×
  /// max_distance since: for a point x of b, |x| ≤ reach_b about b's origin, the motion seen from a is
  /// (R − R₀) x + (p − p₀), at most ‖R − R₀‖_F reach_b + |p − p₀| (the Frobenius norm bounds the spectral
  /// one), with R, p b's pose in a's frame (R₀, p₀ when the points were made); and the same with the roles
  /// swapped. The smaller bound decides (either covers the contact, which lies in both shapes); an infinite
  /// reach (the environment's, here) leaves the other. Not finite: never. Remembered for reused().
  bool standsStill(std::size_t a, std::size_t b, const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB,
                   double reach_a, double reach_b, double max_distance);

  /// Appends the stored points as they stand now: each witness carried by its own shape, the normal by a, the
  /// distance measured anew along it (a point now farther apart than max_distance is left out).
  void appendPoints(const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB, double max_distance,
                    std::vector<ContactPoint>& points) const;

  /// Keeps points[first…] (the pair's fresh points, at most four, one normal) for the pair at these poses;
  /// more than four, or mixed normals, are not kept (the next detection makes them afresh).
  void store(std::size_t a, std::size_t b, const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB,
             double max_distance, const std::vector<ContactPoint>& points, std::size_t first);

  /// Whether points are stored for the pair (a, b), in that order.
  bool holds(std::size_t a, std::size_t b) const { return stored_ && a == a_ && b == b_; }

  /// Whether the last standsStill() since forget() said yes.
  bool reused() const { return reused_; }
  void forget() { reused_ = false; }

 private:
  bool stored_ = false, reused_ = false;
  std::size_t a_ = 0, b_ = 0;
  double max_distance_ = 0.0;
  Eigen::Matrix3d R_AB_ = Eigen::Matrix3d::Identity();  // b's shape in a's, when the points were made
  Eigen::Vector3d p_AB_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_BA_ = Eigen::Vector3d::Zero();       // a's origin in b's frame, then
  Eigen::Vector3d normal_A_ = Eigen::Vector3d::UnitZ();  // from b towards a, in a's frame
  std::size_t count_ = 0;
  std::array<Eigen::Vector3d, 4> on_a_A_, on_b_B_;  // each point's witnesses, in their own shape's frame
};

}  // namespace contact
}  // namespace rigid_body
