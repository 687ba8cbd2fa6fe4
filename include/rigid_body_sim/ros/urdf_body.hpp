// A body from a robot description: one link of a URDF (parsed by the ROS urdf package) gives the mass, the
// centre of mass and the inertia (<inertial>, its origin's rotation honoured), the collision shape
// (<collision>) and the visual for the markers (<visual>). docs/scenes.md, "A body from a URDF".
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

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

/// The largest robot description read (a file or a parameter's text), checked before it is parsed: a URDF is
/// text that names its meshes, and even large robots' are well under 1 MiB.
constexpr std::size_t kMaxUrdfBytes = std::size_t{16} << 20;

/// Where a robot description came from, to name it in messages and to resolve its relative mesh paths.
struct UrdfSource {
  std::string key;     ///< the parameter that gave it: "urdf" or "robot_description"
  std::string value;   ///< that parameter's value (a file or package:// URI, or a parameter name)
  std::string folder;  ///< the file's folder, against which relative mesh paths resolve; empty for a parameter
};

/// The link `link` of the URDF `xml`. Throws ParameterError naming ~link (or the source's parameter for XML
/// that does not parse or is too large): a missing link, a link without <inertial>, a non-physical inertia,
/// an unusable geometry. The <collision> (and its mesh file, at most `max_mesh_bytes`) is read only if
/// `with_collision`: a body that does not collide never opens it.
UrdfLink readUrdfLink(const std::string& xml, const std::string& link, const UrdfSource& source, bool with_collision,
                      std::size_t max_mesh_bytes);

/// The text of a URDF file (a path or package:// URI), at most kMaxUrdfBytes. Throws ParameterError naming
/// ~urdf. `folder` is set to the file's folder.
std::string readUrdfFile(const std::string& uri, std::string& folder);

/// A body given by ~urdf or ~robot_description and ~link (the keys of one body in `params`): fills the
/// link's frames, collision and visual into `config` and returns its mass properties. Keys of other body
/// kinds (shape, mass, …) are refused; `reader` fetches a robot_description parameter's text.
rigid_body::MassProperties readUrdfBody(const XmlRpc::XmlRpcValue& params, BodyConfig& config,
                                        const ParameterReader& reader, std::size_t max_mesh_bytes);

}  // namespace rigid_body_ros
