// How far apart two boxes are along the axis that separates them best: the separating-axis test of two
// oriented boxes (Gottschalk, Lin and Manocha, "OBBTree", SIGGRAPH 1996; Ericson, "Real-Time Collision
// Detection", §4.4.1). It gives a box pair's contact normal and a witness, apart or overlapping, from which
// face clipping finds the pair's points within the near distance as it does for every other faced pair
// (docs/contact.md, step 2). (Bullet's box–box detector, used before, reports penetrating points only: two
// boxes 1e-15 m apart had no contact.) Bullet-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rigid_body {
namespace contact {

/// Two boxes along their best separating axis.
struct BoxSeparation {
  /// The largest gap between the boxes' shadows over the fifteen candidate axes [m]: > 0 exactly when the
  /// boxes are apart. It is their distance where the nearest features are a face and what lies on it, or two
  /// edges across each other; otherwise (an edge or corner nearest an edge or corner) a lower bound of it.
  /// Overlapping, minus the depth along the axis of least overlap.
  double distance = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< the axis, unit, from b towards a
  /// A pair of points, on a's and on b's surface, with on_a − on_b = distance · normal: a's face point over
  /// b's nearest corner (b's over a's) on a face axis; the nearest points of the two edges on an edge axis.
  Eigen::Vector3d on_a = Eigen::Vector3d::Zero(), on_b = Eigen::Vector3d::Zero();
  bool edges = false;  ///< the axis is the cross product of an edge of each box
  /// On an edge axis: whether the nearest points lie inside both edges (else a corner is nearer and the
  /// witness is not a contact).
  bool edges_cross = false;
};

/// Boxes with half extents `half_a`, `half_b` placed at X_WA, X_WB; the distance is NaN where no gap can be
/// compared (a pose or size not finite), so that no point is made from it. A face axis wins ties with an edge axis
/// (two boxes face to face give their face's normal, not a cross product that equals it), and where the
/// boxes overlap it wins unless the edge axis's depth is 5 % smaller.
BoxSeparation separateBoxes(const Eigen::Isometry3d& X_WA, const Eigen::Vector3d& half_a, const Eigen::Isometry3d& X_WB,
                            const Eigen::Vector3d& half_b);

}  // namespace contact
}  // namespace rigid_body
