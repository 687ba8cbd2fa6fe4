#include "rigid_body_sim/collision_shape.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rigid_body_sim/shape_registry.hpp"

namespace rigid_body {

namespace {

// Shapes live within the contact world: sizes and positions up to 1e6 m (where doubles still resolve 1e-10 m
// and no bounding box can overflow), sizes down to 1e-6 m (below, Bullet's margins and tolerances dominate).
constexpr double kLargest = 1e6;
constexpr double kSmallest = 1e-6;

}  // namespace

const char* shapeTypeName(ShapeType type) { return shapeInfo(type).name; }

double innerRadius(const CollisionShape& shape) {
  const Eigen::Vector3d& s = shape.size;
  switch (shape.type) {
    case ShapeType::kBox:
      return 0.5 * s.minCoeff();
    case ShapeType::kSphere:
    case ShapeType::kCapsule:
      return s.x();
    case ShapeType::kCylinder:
      return std::min(s.x(), 0.5 * s.y());
    case ShapeType::kMesh: {
      // The box of the vertices bounds the hull from outside; a tenth of its smallest side is a safe guess
      // from inside for any hull that is not a sliver (a sliver sweeps more often, which costs, not fails).
      Eigen::Vector3d low = shape.mesh.vertices.front(), high = low;
      for (const auto& v : shape.mesh.vertices) low = low.cwiseMin(v), high = high.cwiseMax(v);
      return 0.1 * (high - low).minCoeff();
    }
    case ShapeType::kPlane:
      return 0.0;
  }
  return 0.0;
}

double outerRadius(const CollisionShape& shape) {
  const Eigen::Vector3d& s = shape.size;
  double about_origin = 0.0;  // about the shape frame's origin
  switch (shape.type) {
    case ShapeType::kBox:
      about_origin = 0.5 * s.norm();
      break;
    case ShapeType::kSphere:
      about_origin = s.x();
      break;
    case ShapeType::kCylinder:
      about_origin = std::hypot(s.x(), 0.5 * s.y());
      break;
    case ShapeType::kCapsule:
      about_origin = s.x() + 0.5 * s.y();
      break;
    case ShapeType::kMesh:
      for (const auto& v : shape.mesh.vertices) about_origin = std::max(about_origin, v.norm());
      break;
    case ShapeType::kPlane:
      return 0.0;
  }
  return shape.pose.translation().norm() + about_origin;
}

void validateShape(const CollisionShape& shape, bool in_environment) {
  const std::string what = std::string(shapeTypeName(shape.type)) + (shape.name.empty() ? "" : " '" + shape.name + "'");
  if (!(shape.material.restitution >= 0.0 && shape.material.restitution <= 1.0)) {
    throw std::invalid_argument(what + ": restitution must be in [0, 1]");
  }
  if (!(shape.material.friction >= 0.0) || !std::isfinite(shape.material.friction)) {
    throw std::invalid_argument(what + ": friction must be a finite number >= 0");
  }
  if (!shape.pose.matrix().allFinite() || !(shape.pose.translation().norm() <= kLargest)) {
    throw std::invalid_argument(what + ": pose must be finite, within 1e6 m of the origin");
  }
  const Eigen::Vector3d& s = shape.size;
  auto positive = [&](int count) {
    for (int i = 0; i < count; ++i) {
      if (!(s[i] >= kSmallest && s[i] <= kLargest)) {
        throw std::invalid_argument(what + ": sizes must be in [1e-6, 1e6] m");
      }
    }
  };
  switch (shape.type) {
    case ShapeType::kPlane:
      if (!in_environment) throw std::invalid_argument("a plane can only be part of the environment");
      if (!shape.normal.allFinite() || !(shape.normal.norm() > 0.0) || !(std::abs(shape.offset) <= kLargest)) {
        throw std::invalid_argument(what + ": needs a finite non-zero normal and an offset within 1e6 m");
      }
      return;
    case ShapeType::kBox:
    case ShapeType::kSphere:
    case ShapeType::kCylinder:
    case ShapeType::kCapsule:
      return positive(shapeInfo(shape.type).size_count);
    case ShapeType::kMesh: {
      if (shape.mesh.vertices.size() < 4 || shape.mesh.triangles.size() < 4) {
        throw std::invalid_argument(what + ": a collision mesh needs at least 4 vertices and 4 triangles");
      }
      Eigen::Vector3d low = shape.mesh.vertices.front(), high = low;
      for (const auto& v : shape.mesh.vertices) {
        if (!(v.norm() <= kLargest)) throw std::invalid_argument(what + ": mesh vertices must be within 1e6 m");
        low = low.cwiseMin(v), high = high.cwiseMax(v);
      }
      if (!((high - low).minCoeff() >= kSmallest)) throw std::invalid_argument(what + ": the mesh is flat (no volume)");
      for (const auto& t : shape.mesh.triangles) {
        for (int i : t) {
          if (i < 0 || static_cast<std::size_t>(i) >= shape.mesh.vertices.size()) {
            throw std::invalid_argument(what + ": a triangle refers to a vertex that does not exist");
          }
        }
      }
      return;
    }
  }
}

}  // namespace rigid_body
