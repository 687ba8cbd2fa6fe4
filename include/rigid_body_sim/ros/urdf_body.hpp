// A body from a robot description: one link of a URDF (parsed by the ROS urdf package) gives the mass, the
// centre of mass and the inertia (<inertial>, its origin's rotation honoured), the collision shape
// (<collision>) and the visual for the markers (<visual>). docs/scenes.md, "A body from a URDF".
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/mass_properties.hpp"

namespace rigid_body_ros {

struct UrdfLink {
  rigid_body::MassProperties mass;
  /// The inertial frame, which becomes the body frame B (origin at the centre of mass), in the link frame L.
  Eigen::Isometry3d X_LB = Eigen::Isometry3d::Identity();
  std::optional<rigid_body::CollisionShape> collision;  ///< the first <collision>, its pose in L
  std::string collision_problem;                        ///< why a <collision> cannot be used, if it cannot
  std::optional<rigid_body::CollisionShape> visual;     ///< the first <visual> (a primitive), its pose in L
  std::string visual_mesh;                               ///< a mesh visual's filename as written (package://…)
  double visual_mesh_scale = 1.0;
  Eigen::Isometry3d X_LV = Eigen::Isometry3d::Identity();  ///< a mesh visual's pose in L
};

/// The link `link` of the URDF `xml`. Throws ParameterError naming ~link (or ~urdf for XML that does not
/// parse): a missing link, a link without <inertial>, a non-physical inertia, an unusable geometry.
/// `max_mesh_bytes` bounds a collision mesh file.
UrdfLink readUrdfLink(const std::string& xml, const std::string& link, std::size_t max_mesh_bytes);

/// The text of a URDF file (a path or package:// URI), at most `max_bytes`. Throws ParameterError naming ~urdf.
std::string readUrdfFile(const std::string& uri, std::size_t max_bytes);

}  // namespace rigid_body_ros
