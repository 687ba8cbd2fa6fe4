// The shapes, one row each: what a parameter file, the contact step and the mass properties need to know of
// a shape. Adding a shape is its ShapeType value, its row here, and its Bullet builder and half-space
// features in collision_world.cpp and its rviz marker in src/ros/markers.cpp (switches without a default:
// the compiler names each place a new value lacks). CONTRIBUTING.md has the recipe.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/mass_properties.hpp"

namespace rigid_body {

struct ShapeInfo {
  ShapeType type;
  const char* name;          ///< its spelling in parameter files and logs
  int size_count;            ///< how many entries of CollisionShape::size it reads (0: none)
  const char* size_meaning;  ///< what they are, as a parameter error names them, e.g. "[radius, length]"
  /// A body's size when its parameters give none (the first size_count entries) [m].
  Eigen::Vector3d default_size;
  /// Its contact point rolls over its surface (a sphere, cylinder, capsule): the contact step treats its
  /// contact with a face as rolling (docs/contact.md, "Shapes").
  bool curved;
  bool environment_only;  ///< only in the static environment (the plane: a half-space has no mass)
  /// The mass properties of a uniform solid of this shape and size, about its centre in its own frame
  /// (docs/references.md §1); null where the shape has no formula of its own (a plane has no volume, a
  /// mesh's come from its triangles: mesh_mass_properties.hpp). A shape with one can be a body's `shape`.
  MassProperties (*solid)(double mass, const Eigen::Vector3d& size);
};

/// Every shape, in the enumeration's order.
const std::vector<ShapeInfo>& shapeRegistry();
const ShapeInfo& shapeInfo(ShapeType type);
/// The shape spelt `name`, or none.
std::optional<ShapeType> shapeFromName(const std::string& name);
/// What a size of this shape must be, for parameter errors: "for a box, must be [x, y, z] with 3 finite
/// numbers > 0 [m]".
std::string sizeRule(ShapeType type);
/// "a, b, c": the names of the shapes for which keep(row) holds, in the registry's order.
std::string shapeNames(bool (*keep)(const ShapeInfo&));

}  // namespace rigid_body
