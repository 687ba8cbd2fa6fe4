// What collides: the shapes of the static environment and of the bodies, with their contact materials.
// A plain description; the collision library's objects are made from it inside the core (collision_world.cpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rigid_body_sim/mesh.hpp"

namespace rigid_body {

enum class ShapeType {
  kPlane,     ///< the solid half-space n·x ≤ offset (environment only)
  kBox,       ///< size = full edge lengths (x, y, z) [m]
  kSphere,    ///< size.x() = radius [m]
  kCylinder,  ///< size = (radius, length) [m], axis z of its frame
  kCapsule,   ///< size = (radius, length of the straight part) [m], axis z of its frame
  kMesh,      ///< a triangle mesh: its convex hull on a body, the triangles themselves in the environment
};

/// Its spelling in parameter files (shape_registry.hpp has the rest of its row).
const char* shapeTypeName(ShapeType type);

/// Newton's coefficient of restitution e ∈ [0, 1] and Coulomb's friction coefficient μ ≥ 0. A contact
/// combines two materials as e = max(e_a, e_b) and μ = √(μ_a μ_b).
struct ContactMaterial {
  double restitution = 0.0;
  double friction = 0.5;
};

/// One collision shape. For a body, `pose` is the shape's frame in the body frame B (whose origin is the
/// centre of mass); for the environment, in the world frame W.
struct CollisionShape {
  ShapeType type = ShapeType::kBox;
  std::string name;                                  ///< reported as the other side of a contact
  Eigen::Vector3d size = Eigen::Vector3d::Zero();     ///< see ShapeType
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< kPlane: outward unit normal
  double offset = 0.0;                               ///< kPlane: n·x ≤ offset is solid [m]
  TriangleMesh mesh;                                 ///< kMesh, in the shape's frame [m]
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  ContactMaterial material;
};

/// The radius of the largest ball about the shape's frame origin inside the shape [m]: how far a body may
/// move in one step before it could pass through a thin obstacle unseen (the swept test starts beyond it).
double innerRadius(const CollisionShape& shape);

/// The radius of the smallest ball about the body frame's origin (the centre of mass) that holds the shape
/// at its pose [m]: no point of the body moves faster than |v| + |ω| times it (the continuous test's bound).
double outerRadius(const CollisionShape& shape);

/// Throws std::invalid_argument for a shape that cannot collide: non-finite or non-positive sizes, a zero
/// plane normal, a mesh with fewer than 4 vertices or no volume, a material out of range.
void validateShape(const CollisionShape& shape, bool in_environment);

}  // namespace rigid_body
