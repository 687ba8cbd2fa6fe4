#include "rigid_body_sim/ros/urdf_body.hpp"

#include <urdf/model.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "parameter_values.hpp"
#include "rigid_body_sim/mesh.hpp"
#include "rigid_body_sim/mesh_io.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

namespace rigid_body_ros {

using namespace parameter_values;

namespace {

Eigen::Isometry3d toEigen(const urdf::Pose& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  X.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return X;
}

std::string meshPath(const std::string& filename) {
  const std::string file = "file://";
  return filename.compare(0, file.size(), file) == 0 ? filename.substr(file.size()) : resolveMeshUri(filename);
}

// A URDF geometry as a collision shape; `what` names it in messages ("collision", "visual").
rigid_body::CollisionShape shapeOf(const urdf::Geometry& geometry, const std::string& link, const std::string& what,
                                   bool load_mesh, std::size_t max_mesh_bytes) {
  rigid_body::CollisionShape shape;
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      shape.type = rigid_body::ShapeType::kBox;
      shape.size = Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z);
      break;
    }
    case urdf::Geometry::SPHERE:
      shape.type = rigid_body::ShapeType::kSphere;
      shape.size.x() = static_cast<const urdf::Sphere&>(geometry).radius;
      break;
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      shape.type = rigid_body::ShapeType::kCylinder;
      shape.size = Eigen::Vector3d(cylinder.radius, cylinder.length, 0.0);
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      shape.type = rigid_body::ShapeType::kMesh;
      if (!load_mesh) break;
      if (mesh.scale.x != mesh.scale.y || mesh.scale.x != mesh.scale.z || !(mesh.scale.x > 0.0)) {
        fail("link", XmlRpcValue(link), "its " + what + " mesh has a non-uniform or non-positive scale");
      }
      try {
        std::vector<std::string> warnings;
        shape.mesh = rigid_body::validatedClosedMesh(
            rigid_body::transformed(rigid_body::loadMesh(meshPath(mesh.filename), max_mesh_bytes), mesh.scale.x), warnings);
      } catch (const rigid_body::MeshError& error) {
        fail("link", XmlRpcValue(link), "its " + what + " mesh '" + mesh.filename + "': " + error.what());
      }
      break;
    }
  }
  return shape;
}

}  // namespace

std::string readUrdfFile(const std::string& uri, std::size_t max_bytes) {
  const std::string path = meshPath(uri);
  // A regular file of a bounded size, read to exactly that size: a FIFO or a device (/dev/zero) would never end.
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    fail("urdf", XmlRpcValue(uri), "cannot open the file '" + path + "' (not a regular file, or missing)");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error || size > max_bytes) {
    fail("urdf", XmlRpcValue(uri), "is not a readable file of at most " + std::to_string(max_bytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in || !in.read(&text[0], static_cast<std::streamsize>(size))) {
    fail("urdf", XmlRpcValue(uri), "cannot open the file '" + path + "'");
  }
  return text;
}

UrdfLink readUrdfLink(const std::string& xml, const std::string& link_name, std::size_t max_mesh_bytes) {
  urdf::Model model;
  if (!model.initString(xml)) fail("urdf", XmlRpcValue(std::string("...")), "does not parse as a URDF robot description");
  const urdf::LinkConstSharedPtr link = model.getLink(link_name);
  if (!link) fail("link", XmlRpcValue(link_name), "names no link of the robot description");
  if (!link->inertial) fail("link", XmlRpcValue(link_name), "has no <inertial>: mass and inertia are needed");
  const urdf::Inertial& inertial = *link->inertial;
  UrdfLink out;
  // The inertia is given about the centre of mass in the inertial frame (origin xyz rpy in the link frame);
  // that frame becomes the body frame, so I_Bcm_B is the tensor as written.
  Eigen::Matrix3d I;
  I << inertial.ixx, inertial.ixy, inertial.ixz,  //
      inertial.ixy, inertial.iyy, inertial.iyz,   //
      inertial.ixz, inertial.iyz, inertial.izz;
  try {
    out.mass = rigid_body::MassProperties::fromInertia(inertial.mass, I);
  } catch (const rigid_body::InvalidMassProperties& error) {
    fail("link", XmlRpcValue(link_name), std::string("has a non-physical <inertial>: ") + error.what());
  }
  out.X_LB = toEigen(inertial.origin);
  // Offsets within the contact world's 1e6 m (docs/contact.md), like every other pose of a scene.
  if (!(out.X_LB.translation().norm() <= 1e6)) {
    fail("link", XmlRpcValue(link_name), "has an <inertial> origin beyond 1e6 m (or not finite)");
  }
  if (link->collision && link->collision->geometry) {
    out.collision = shapeOf(*link->collision->geometry, link_name, "collision", true, max_mesh_bytes);
    out.collision->pose = toEigen(link->collision->origin);
    try {
      rigid_body::validateShape(*out.collision, false);
    } catch (const std::invalid_argument& error) {
      // Only a problem if the body collides with it (collision: true): kept to say so then.
      out.collision_problem = std::string("has an unusable <collision>: ") + error.what();
      out.collision.reset();
    }
  }
  if (link->visual && link->visual->geometry) {
    if (link->visual->geometry->type == urdf::Geometry::MESH) {
      const auto& mesh = static_cast<const urdf::Mesh&>(*link->visual->geometry);
      out.visual_mesh = mesh.filename;
      out.visual_mesh_scale = mesh.scale.x;
      out.X_LV = toEigen(link->visual->origin);
    } else {
      out.visual = shapeOf(*link->visual->geometry, link_name, "visual", false, max_mesh_bytes);
      out.visual->pose = toEigen(link->visual->origin);
    }
  }
  return out;
}

}  // namespace rigid_body_ros
