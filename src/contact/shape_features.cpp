#include "shape_features.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace rigid_body {
namespace contact {

namespace {

constexpr double kCos45 = 0.70710678118654752440;

void boxFace(const Eigen::Vector3d& half, const Eigen::Isometry3d& X_WS, const Eigen::Vector3d& direction,
             SupportFace& face) {
  const Eigen::Vector3d d = X_WS.linear().transpose() * direction;
  int i = 0;
  d.cwiseAbs().maxCoeff(&i);
  const double side = d[i] < 0.0 ? -1.0 : 1.0;
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  // The corners in order around the face: (+,+), (−,+), (−,−), (+,−) along its two edges' axes.
  static constexpr std::array<std::array<double, 2>, 4> kCorners{{{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}};
  for (const auto& corner : kCorners) {
    Eigen::Vector3d local;
    local[i] = side * half[i], local[j] = corner[0] * half[j], local[k] = corner[1] * half[k];
    face.vertices.push_back(X_WS * local);
  }
  face.normal = side * X_WS.linear().col(i);
}

void hullFace(const HullFaces& hull, const Eigen::Isometry3d& X_WS, const Eigen::Vector3d& direction, SupportFace& face) {
  if (hull.normals.empty()) return;
  const Eigen::Vector3d d = X_WS.linear().transpose() * direction;
  std::size_t best = 0;
  for (std::size_t f = 1; f < hull.normals.size(); ++f) {
    if (hull.normals[f].dot(d) > hull.normals[best].dot(d)) best = f;
  }
  for (const Eigen::Vector3d& v : hull.loops[best]) face.vertices.push_back(X_WS * v);
  face.normal = X_WS.linear() * hull.normals[best];
}

// A cylinder's end facing `direction`: its rim's points as the half-space features have them, in order
// around the rim, so that a cylinder meets a box's face as it meets the ground.
void cylinderEnd(const Eigen::Isometry3d& X_WS, double radius, double half_length, const Eigen::Vector3d& direction,
                 SupportFace& face) {
  const Eigen::Vector3d axis = X_WS.linear().col(2);
  const double side = axis.dot(direction) < 0.0 ? -1.0 : 1.0;
  std::array<std::pair<double, Eigen::Vector3d>, 9> rim;
  std::size_t count = 0;
  cylinderRim(X_WS.translation() + side * half_length * axis, radius, X_WS.linear().col(0), X_WS.linear().col(1),
              acrossAxis(axis, direction),
              [&](int, double angle, const Eigen::Vector3d& x) { rim[count++] = {angle, x}; });
  std::sort(rim.begin(), rim.begin() + static_cast<std::ptrdiff_t>(count),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t k = 0; k < count; ++k) face.vertices.push_back(rim[k].second);
  face.normal = side * axis;
}

}  // namespace

void supportingFace(const CollisionShape& shape, const HullFaces* hull, const Eigen::Isometry3d& X_WS,
                    const Eigen::Vector3d& direction, SupportFace& face) {
  face.vertices.clear();
  face.normal.setZero();
  const Eigen::Vector3d& s = shape.size;
  switch (shape.type) {
    case ShapeType::kBox:
      return boxFace(0.5 * s, X_WS, direction, face);
    case ShapeType::kMesh:
      if (hull != nullptr) hullFace(*hull, X_WS, direction, face);
      return;
    case ShapeType::kCapsule: {
      // The segment's end spheres meet a plane at their centres pushed out by the radius.
      const Eigen::Vector3d half_axis = 0.5 * s.y() * X_WS.linear().col(2);
      const Eigen::Vector3d out = X_WS.translation() + s.x() * direction;
      face.vertices.push_back(out + half_axis);
      face.vertices.push_back(out - half_axis);
      return;
    }
    case ShapeType::kCylinder: {
      const Eigen::Vector3d axis = X_WS.linear().col(2);
      if (std::abs(axis.dot(direction)) >= kCos45) return cylinderEnd(X_WS, s.x(), 0.5 * s.y(), direction, face);
      const Eigen::Vector3d side = X_WS.translation() + s.x() * acrossAxis(axis, direction);
      face.vertices.push_back(side + 0.5 * s.y() * axis);
      face.vertices.push_back(side - 0.5 * s.y() * axis);
      return;
    }
    case ShapeType::kSphere:
    case ShapeType::kPlane:
      return;
  }
}

}  // namespace contact
}  // namespace rigid_body
