// Where convex shapes can touch, in closed form: the points of a shape that meet a half-space first (its
// features), and the face a shape turns towards a direction (the face that face clipping cuts, in
// face_manifold.hpp). Bullet-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "rigid_body_sim/collision_shape.hpp"

namespace rigid_body {
namespace contact {

/// A convex hull's faces in its shape frame: each an outward unit normal and its vertices in order around
/// the face (a convex polygon).
struct HullFaces {
  std::vector<Eigen::Vector3d> normals;
  std::vector<std::vector<Eigen::Vector3d>> loops;
};

/// What a shape offers a contact normal: a convex polygon (three or more vertices, in order, with its
/// outward unit normal), a segment (two), or nothing (a sphere). World coordinates [m].
struct SupportFace {
  std::vector<Eigen::Vector3d> vertices;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< a polygon's outward unit normal (else unused)
};

/// The points of a cylinder's end rim (centre `centre`, `radius`, the cylinder's frame axes u, v across its
/// axis) that can touch first along the unit `out` (across the axis, or zero where the end faces `out`
/// squarely): the rim's point farthest along `out` (feature 0, where `out` is not zero), and the eight
/// material points at k·45° (features 1 + k) but those within 45° of it. The rim's farthest point is where
/// a tilted end touches; a material point beside it would brake a rolling cylinder with friction of its own.
/// `visit(feature, angle about the axis from u [rad], point)`.
template <typename Visit>
void cylinderRim(const Eigen::Vector3d& centre, double radius, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                 const Eigen::Vector3d& out, Visit visit) {
  constexpr double kCos45 = 0.70710678118654752440;
  constexpr double kQuarterPi = 0.78539816339744830962;
  const bool tilted = out.squaredNorm() > 0.0;
  if (tilted) visit(0, std::atan2(out.dot(v), out.dot(u)), Eigen::Vector3d(centre + radius * out));
  for (int k = 0; k < 8; ++k) {
    const double phi = k * kQuarterPi;
    const Eigen::Vector3d radial = std::cos(phi) * u + std::sin(phi) * v;
    if (tilted && radial.dot(out) > kCos45) continue;
    visit(1 + k, k < 5 ? phi : phi - 8.0 * kQuarterPi, Eigen::Vector3d(centre + radius * radial));
  }
}

/// The unit direction across a cylinder's `axis` nearest to `direction`, or zero where `direction` lies
/// along the axis (within 1e-9).
inline Eigen::Vector3d acrossAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d across = direction - direction.dot(axis) * axis;
  return across.norm() > 1e-9 ? Eigen::Vector3d(across.normalized()) : Eigen::Vector3d::Zero();
}

/// The points of a convex shape (at pose X_WS) that can touch the half-space n·x ≤ offset first, each with a
/// feature number that stays the same from step to step: a box's corners, a hull's vertices (`shape.mesh`
/// holding the hull's), a sphere's lowest point, a capsule's two lowest points, a cylinder's rims (each end's
/// as cylinderRim gives it, a cylinder standing on its end resting on its rim). Half-space contact is exact
/// this way and gives a face its whole manifold in one pass. `visit(feature, point)`.
template <typename Visit>
void planeFeatures(const CollisionShape& shape, const Eigen::Isometry3d& X_WS, const Eigen::Vector3d& n, Visit visit) {
  const Eigen::Vector3d& s = shape.size;
  const Eigen::Vector3d c = X_WS.translation();
  const Eigen::Vector3d axis = X_WS.linear().col(2);
  switch (shape.type) {
    case ShapeType::kBox:
      for (int i = 0; i < 8; ++i) {
        visit(i, X_WS * Eigen::Vector3d((i & 1 ? 0.5 : -0.5) * s.x(), (i & 2 ? 0.5 : -0.5) * s.y(),
                                        (i & 4 ? 0.5 : -0.5) * s.z()));
      }
      return;
    case ShapeType::kSphere:
      return visit(0, c - s.x() * n);
    case ShapeType::kCapsule:
      visit(0, c + 0.5 * s.y() * axis - s.x() * n);
      return visit(1, c - 0.5 * s.y() * axis - s.x() * n);
    case ShapeType::kCylinder: {
      const Eigen::Vector3d down = acrossAxis(axis, -n);
      for (int end = 0; end < 2; ++end) {
        const Eigen::Vector3d centre = c + (end == 0 ? -0.5 : 0.5) * s.y() * axis;
        cylinderRim(centre, s.x(), X_WS.linear().col(0), X_WS.linear().col(1), down,
                    [&](int feature, double, const Eigen::Vector3d& x) { visit(9 * end + feature, x); });
      }
      return;
    }
    case ShapeType::kMesh:
      for (std::size_t i = 0; i < shape.mesh.vertices.size(); ++i) visit(static_cast<int>(i), X_WS * shape.mesh.vertices[i]);
      return;
    case ShapeType::kPlane:
      return;
  }
}

/// The face of `shape` (at X_WS) whose outward side points most along the unit `direction`: a box's face,
/// a hull's face (`hull`, required for kMesh), a capsule's segment pushed out by its radius along
/// `direction`, a cylinder's end (its rim as cylinderRim gives it, in order around it) where the axis is
/// within 45° of `direction`, else the line of its side. A sphere has none. Every vertex lies on the shape's
/// surface, and every point between them on it or inside it.
void supportingFace(const CollisionShape& shape, const HullFaces* hull, const Eigen::Isometry3d& X_WS,
                    const Eigen::Vector3d& direction, SupportFace& face);

}  // namespace contact
}  // namespace rigid_body
