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

// A mesh filename of a URDF as a file path: package:// through the package's path, file:// stripped, and a
// relative path against the URDF file's folder (as rviz and Gazebo read them), never the working directory.
std::string meshPath(const std::string& filename, const UrdfSource& source, const std::string& link) {
  const std::string file = "file://", package = "package://";
  if (filename.compare(0, package.size(), package) == 0) {
    try {
      return resolveMeshUri(filename);
    } catch (const ParameterError&) {
      const std::string rest = filename.substr(package.size());
      fail("link", XmlRpcValue(link), "its mesh '" + filename + "': package '" + rest.substr(0, rest.find('/')) +
                                         "' not found (is its workspace sourced?)");
    }
  }
  const std::string path = filename.compare(0, file.size(), file) == 0 ? filename.substr(file.size()) : filename;
  if (std::filesystem::path(path).is_absolute()) return path;
  if (source.folder.empty()) {
    fail("link", XmlRpcValue(link), "its mesh '" + filename + "' is a relative path, and a description from ~" +
                                        source.key + " has no folder to resolve it against: use package:// or an "
                                        "absolute path");
  }
  return (std::filesystem::path(source.folder) / path).lexically_normal().string();
}

// A visual mesh's filename as a URI rviz resolves (a marker's mesh_resource): package:// and file:// as
// written, a path made absolute against the URDF's folder and given file://.
std::string visualMeshUri(const std::string& filename, const UrdfSource& source) {
  if (filename.find("://") != std::string::npos) return filename;
  std::filesystem::path path(filename);
  if (path.is_relative() && !source.folder.empty()) path = std::filesystem::path(source.folder) / path;
  return path.is_absolute() ? "file://" + path.lexically_normal().string() : filename;
}

// A URDF geometry as a collision shape; `what` names it in messages ("collision", "visual").
rigid_body::CollisionShape shapeOf(const urdf::Geometry& geometry, const std::string& link, const std::string& what,
                                   const UrdfSource& source, bool load_mesh, std::size_t max_mesh_bytes) {
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
            rigid_body::transformed(rigid_body::loadMesh(meshPath(mesh.filename, source, link), max_mesh_bytes),
                                    mesh.scale.x),
            warnings);
      } catch (const rigid_body::MeshError& error) {
        fail("link", XmlRpcValue(link), "its " + what + " mesh '" + mesh.filename + "': " + error.what());
      }
      break;
    }
  }
  return shape;
}

}  // namespace

std::string readUrdfFile(const std::string& uri, std::string& folder) {
  std::string path;
  const std::string file = "file://";
  try {
    path = uri.compare(0, file.size(), file) == 0 ? uri.substr(file.size()) : resolveMeshUri(uri);
  } catch (const ParameterError&) {
    fail("urdf", XmlRpcValue(uri), "names a package that is not found (is its workspace sourced?)");
  }
  // A regular file of a bounded size, read to exactly that size: a FIFO or a device (/dev/zero) would never end.
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    fail("urdf", XmlRpcValue(uri), "cannot open the file '" + path + "' (not a regular file, or missing)");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error || size > kMaxUrdfBytes) {
    fail("urdf", XmlRpcValue(uri), "is not a readable file of at most " + std::to_string(kMaxUrdfBytes) +
                                       " bytes (16 MiB, the largest robot description read)");
  }
  folder = std::filesystem::absolute(std::filesystem::path(path), error).parent_path().string();
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in || !in.read(&text[0], static_cast<std::streamsize>(size))) {
    fail("urdf", XmlRpcValue(uri), "cannot open the file '" + path + "'");
  }
  return text;
}

UrdfLink readUrdfLink(const std::string& xml, const std::string& link_name, const UrdfSource& source,
                      bool with_collision, std::size_t max_mesh_bytes) {
  if (xml.size() > kMaxUrdfBytes) {
    fail(source.key, XmlRpcValue(source.value), "holds " + std::to_string(xml.size()) + " bytes, more than the " +
                                                    std::to_string(kMaxUrdfBytes) +
                                                    " (16 MiB) a robot description may have");
  }
  urdf::Model model;
  if (!model.initString(xml)) fail(source.key, XmlRpcValue(source.value), "does not parse as a URDF robot description");
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
  if (with_collision && link->collision && link->collision->geometry) {
    out.collision = shapeOf(*link->collision->geometry, link_name, "collision", source, true, max_mesh_bytes);
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
      out.visual_mesh = visualMeshUri(mesh.filename, source);
      out.visual_mesh_scale = mesh.scale.x;
      out.X_LV = toEigen(link->visual->origin);
    } else {
      out.visual = shapeOf(*link->visual->geometry, link_name, "visual", source, false, max_mesh_bytes);
      out.visual->pose = toEigen(link->visual->origin);
    }
  }
  return out;
}

// shape: urdf. The body frame is the link's inertial frame (centre of mass, its axes); the published frame is
// the link frame, at X_BP = X_LB⁻¹.
rigid_body::MassProperties readUrdfBody(const XmlRpcValue& params, BodyConfig& config, const ParameterReader& reader,
                                        std::size_t max_bytes) {
  for (const char* key : {"shape", "size", "mass", "inertia", "mesh", "scale", "density", "inertia_method", "samples",
                          "principal_axes", "mesh_frame"}) {
    if (find(params, key)) failAt(params, key, XmlRpcValue(), "is not a key of a body given by ~urdf or ~robot_description");
  }
  if (find(params, "urdf") && find(params, "robot_description")) {
    failAt(params, "robot_description", XmlRpcValue(), "give ~urdf or ~robot_description, not both");
  }
  config.link = readString(params, "link", "", "must be the name of a link of the robot description");
  if (config.link.empty()) fail("link", XmlRpcValue(std::string()), "must be set with ~urdf or ~robot_description");
  std::string xml;
  UrdfSource source;
  if (find(params, "urdf")) {
    source.key = "urdf";
    source.value = readString(params, "urdf", "", "must be a URDF file path or package:// URI");
    xml = readUrdfFile(source.value, source.folder);
  } else {
    source.key = "robot_description";
    source.value = readString(params, "robot_description", "", "must name the parameter that holds the URDF");
    if (source.value.empty() || !reader || !reader(source.value, xml)) {
      failAt(params, "robot_description", XmlRpcValue(), "must name a parameter that holds the URDF as text");
    }
  }
  // The link's <collision> is the body's collision shape only with collision: true (or a struct without
  // collision/shape): otherwise its mesh is never opened.
  const XmlRpcValue* collision = find(params, "collision");
  const bool with_collision =
      collision && ((collision->getType() == XmlRpcValue::TypeBoolean && static_cast<bool>(*collision)) ||
                    (collision->getType() == XmlRpcValue::TypeStruct && !find(params, "collision/shape")));
  UrdfLink link = readUrdfLink(xml, config.link, source, with_collision, max_bytes);
  config.mass_source = MassSource::kUrdf;
  config.size.clear();
  config.X_BP = link.X_LB.inverse();
  config.published_offset = !link.X_LB.isApprox(Eigen::Isometry3d::Identity(), 0.0);
  config.urdf_collision_problem = link.collision_problem;
  if (link.collision) {
    config.urdf_collision = link.collision;
    config.urdf_collision->pose = config.X_BP * link.collision->pose;  // X_BC = X_BL X_LC
  }
  config.visual = link.visual;
  config.visual_mesh = link.visual_mesh;
  config.visual_mesh_scale = link.visual_mesh_scale;
  config.X_PV = link.X_LV;
  return link.mass;
}

}  // namespace rigid_body_ros
