#include "rigid_body_sim/ros/contact_parameters.hpp"

#include "parameter_values.hpp"

#include <cmath>
#include <optional>
#include <set>

#include "rigid_body_sim/mesh_io.hpp"
#include "rigid_body_sim/shape_registry.hpp"
#include "rigid_body_sim/ros/parameters.hpp"

namespace rigid_body_ros {

using namespace parameter_values;

const char* const kEnvironmentKeys[] = {"type", "name", "normal", "offset", "size", "pose", "mesh", "scale",
                                        "restitution", "friction", nullptr};
const char* const kCollisionKeys[] = {"shape", "size", "mesh", "scale", "restitution", "friction", nullptr};

namespace {


std::set<std::string> keySet(const char* const* keys) {
  std::set<std::string> set;
  for (; *keys != nullptr; ++keys) set.insert(*keys);
  return set;
}

// Keys a struct may not have: a typo in a collision shape changes the physics, so it stops the node.
void refuseUnknown(const XmlRpcValue& item, const std::string& prefix, const char* const* keys) {
  const std::set<std::string> known = keySet(keys);
  XmlRpcValue copy = item;
  for (const auto& member : copy) {
    if (!known.count(member.first)) {
      std::string allowed;
      for (const std::string& key : known) allowed += (allowed.empty() ? "" : ", ") + key;
      fail(prefix + member.first, member.second, "is not a key here (allowed: " + allowed + ")");
    }
  }
}

void readMaterial(const XmlRpcValue& params, const std::string& prefix, rigid_body::ContactMaterial& material) {
  material.restitution = readNumber(params, prefix + "restitution", material.restitution,
                                    [](double e) { return e >= 0.0 && e <= 1.0; },
                                    "must be a number in [0, 1] (Newton's coefficient of restitution)");
  material.friction = readNumber(params, prefix + "friction", material.friction, [](double mu) { return mu >= 0.0; },
                                 "must be a finite number >= 0 (Coulomb's friction coefficient)");
}

rigid_body::ShapeType shapeType(const XmlRpcValue& params, const std::string& name, const std::string& fallback,
                                bool plane_allowed) {
  const std::string allowed =
      "must be one of: " + (plane_allowed ? rigid_body::shapeNames([](const rigid_body::ShapeInfo&) { return true; })
                                          : rigid_body::shapeNames([](const rigid_body::ShapeInfo& s) {
                                              return !s.environment_only;
                                            }));
  const std::string type = readString(params, name, fallback, allowed);
  const std::optional<rigid_body::ShapeType> shape = rigid_body::shapeFromName(type);
  if (!shape || (!plane_allowed && rigid_body::shapeInfo(*shape).environment_only)) {
    failAt(params, name, XmlRpcValue(type), allowed);
  }
  return *shape;
}

// size for a shape type: as many entries as its row says (box [x, y, z], sphere [r], cylinder and capsule
// [r, length]).
Eigen::Vector3d readSize(const XmlRpcValue& params, const std::string& name, rigid_body::ShapeType type,
                         const std::vector<double>& fallback) {
  const std::size_t length = static_cast<std::size_t>(rigid_body::shapeInfo(type).size_count);
  const std::string allowed = rigid_body::sizeRule(type);
  if (!find(params, name) && fallback.size() != length) {
    fail(name, XmlRpcValue(std::string()), "must be set: " + allowed);
  }
  const std::vector<double> size = readNumbers(params, name, fallback, length, allowed);
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < length; ++i) {
    // Within the contact world (docs/contact.md): 1e-6 … 1e6 m.
    if (!(size[i] >= 1e-6 && size[i] <= 1e6)) {
      if (find(params, name)) failAt(params, name, XmlRpcValue(), allowed + ", each in [1e-6, 1e6] m");
      fail(name, XmlRpcValue(size[i]), allowed + ", each in [1e-6, 1e6] m (the body's own size is outside)");
    }
    out[static_cast<int>(i)] = size[i];
  }
  return out;
}

rigid_body::TriangleMesh readCollisionMesh(const XmlRpcValue& params, const std::string& prefix, std::size_t max_bytes) {
  const std::string uri = readString(params, prefix + "mesh", "", "must be a mesh file path or package:// URI (.stl, .obj)");
  if (uri.empty()) fail(prefix + "mesh", XmlRpcValue(std::string()), "must be set for a mesh shape");
  const double scale = readNumber(params, prefix + "scale", 1.0, [](double s) { return s > 0.0; },
                                  "must be a finite number > 0 (mesh units to metres)");
  try {
    std::vector<std::string> warnings;
    // A collision mesh must be closed and not degenerate: inside and outside have to mean something.
    return rigid_body::validatedClosedMesh(
        rigid_body::transformed(rigid_body::loadMesh(resolveMeshUri(uri), max_bytes), scale), warnings);
  } catch (const rigid_body::MeshError& error) {
    failAt(params, prefix + "mesh", XmlRpcValue(uri), error.what());
  }
}

Eigen::Isometry3d readPose(const XmlRpcValue& params, const std::string& prefix) {
  requireStruct(params, prefix + "pose", "position, orientation");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = readVector3(params, prefix + "pose/position", "[m]");
  if (!(pose.translation().norm() <= 1e6)) {
    failAt(params, prefix + "pose/position", XmlRpcValue(), "must be within 1e6 m of the origin [m]");
  }
  pose.linear() = readQuaternion(params, prefix + "pose/orientation").normalized().toRotationMatrix();
  return pose;
}

}  // namespace

std::vector<rigid_body::CollisionShape> readEnvironment(const XmlRpcValue& params, std::size_t max_mesh_bytes) {
  std::vector<rigid_body::CollisionShape> environment;
  const XmlRpcValue* list = find(params, "environment");
  if (!list) return environment;
  if (list->getType() != XmlRpcValue::TypeArray) {
    fail("environment", *list, "must be a list of shapes, each a struct with 'type' (plane, box, sphere, cylinder, capsule, mesh)");
  }
  std::set<std::string> names;
  for (int i = 0; i < list->size(); ++i) {
    const XmlRpcValue& item = (*list)[i];
    const std::string prefix = "environment[" + std::to_string(i) + "]/";
    if (item.getType() != XmlRpcValue::TypeStruct) fail(prefix.substr(0, prefix.size() - 1), item, "must be a struct with 'type'");
    refuseUnknown(item, prefix, kEnvironmentKeys);
    // The item's keys are read with the item as the namespace; errors name them with the prefix.
    try {
      rigid_body::CollisionShape shape;
      if (!find(item, "type")) fail("type", XmlRpcValue(std::string()), "must be set: plane, box, sphere, cylinder, capsule or mesh");
      shape.type = shapeType(item, "type", "", true);
      shape.name = readString(item, "name", std::string(rigid_body::shapeTypeName(shape.type)) + std::to_string(i),
                              "must be a name for the shape");
      if (shape.name.empty()) failAt(item, "name", XmlRpcValue(shape.name), "must be a non-empty name");
      if (!names.insert(shape.name).second) failAt(item, "name", XmlRpcValue(shape.name), "must be unique in ~environment");
      readMaterial(item, "", shape.material);
      if (shape.type == rigid_body::ShapeType::kPlane) {
        for (const char* key : {"size", "pose", "mesh", "scale"}) {
          if (find(item, key)) failAt(item, key, XmlRpcValue(), "is not a key of a plane (give normal and offset)");
        }
        const std::vector<double> n = readNumbers(item, "normal", {0.0, 0.0, 1.0}, 3, "must be 3 finite numbers, not all 0");
        shape.normal = Eigen::Vector3d(n[0], n[1], n[2]);
        if (!(shape.normal.norm() > 1e-9)) failAt(item, "normal", XmlRpcValue(), "must be 3 finite numbers, not all 0");
        shape.normal.normalize();
        shape.offset = readNumber(item, "offset", 0.0, [](double d) { return std::abs(d) <= 1e6; },
                                  "must be a finite number in [-1e6, 1e6] [m]");
      } else {
        for (const char* key : {"normal", "offset"}) {
          if (find(item, key)) failAt(item, key, XmlRpcValue(), "is a key of a plane only");
        }
        if (shape.type == rigid_body::ShapeType::kMesh) {
          shape.mesh = readCollisionMesh(item, "", max_mesh_bytes);
        } else {
          shape.size = readSize(item, "size", shape.type, {});
        }
        shape.pose = readPose(item, "");
      }
      environment.push_back(shape);
    } catch (const ParameterError& error) {
      std::string message = error.what();
      const std::string head = "parameter ~";
      if (message.compare(0, head.size(), head) == 0) message.insert(head.size(), prefix);
      throw ParameterError(message);
    }
  }
  return environment;
}

std::optional<rigid_body::CollisionShape> readCollision(const XmlRpcValue& params, const BodyConfig& body) {
  const XmlRpcValue* value = find(params, "collision");
  if (!value) return std::nullopt;
  if (value->getType() == XmlRpcValue::TypeBoolean && !static_cast<bool>(*value)) return std::nullopt;
  const bool own = value->getType() == XmlRpcValue::TypeBoolean;
  if (!own && value->getType() != XmlRpcValue::TypeStruct) {
    fail("collision", *value, "must be true, false or a struct {shape, size, mesh, scale, restitution, friction}");
  }
  if (!own) refuseUnknown(*value, "collision/", kCollisionKeys);
  rigid_body::CollisionShape shape;
  shape.name = body.name.empty() ? body.body_frame : body.name;
  if (body.mass_source == MassSource::kUrdf && (own || !find(params, "collision/shape"))) {
    // The link's own <collision>, posed in the body frame; a struct may still set the material.
    if (!body.urdf_collision && !body.urdf_collision_problem.empty()) {
      fail("link", XmlRpcValue(body.link), body.urdf_collision_problem);
    }
    if (!body.urdf_collision) fail("collision", *value, "needs a shape: the link has no <collision>; give collision/shape");
    if (!own && find(params, "collision/size")) failAt(params, "collision/size", XmlRpcValue(), "needs collision/shape too");
    shape = *body.urdf_collision;
    shape.name = body.name.empty() ? body.body_frame : body.name;
    if (!own) readMaterial(params, "collision/", shape.material);
    return shape;
  }
  const std::string own_shape = body.mass_source == MassSource::kShape ? rigid_body::shapeTypeName(body.shape) : "";
  if (own && own_shape.empty()) {
    fail("collision", *value, "needs a shape: a body given by ~inertia has none; give collision/shape and collision/size");
  }
  shape.type = own ? shapeType(XmlRpcValue(), "shape", own_shape, false)
                   : shapeType(params, "collision/shape", own_shape, false);
  if (!own && own_shape.empty() && !find(params, "collision/shape")) {
    fail("collision/shape", XmlRpcValue(std::string()), "must be set: a body given by ~inertia has no shape of its own");
  }
  const bool same_shape = body.hasShape(shape.type);
  if (shape.type == rigid_body::ShapeType::kMesh) {
    if (!own && find(params, "collision/mesh")) {
      shape.mesh = readCollisionMesh(params, "collision/", rigid_body::kDefaultMaxMeshBytes);
    } else if (same_shape) {
      shape.mesh = rigid_body::transformed(body.mesh, 1.0, body.X_MB.inverse());  // into the body frame
    } else {
      fail("collision/mesh", XmlRpcValue(std::string()), "must be set for a mesh collision shape");
    }
  } else {
    const std::vector<double> fallback = same_shape ? body.size : std::vector<double>();
    shape.size = own ? readSize(XmlRpcValue(), "collision/size", shape.type, fallback)
                     : readSize(params, "collision/size", shape.type, fallback);
  }
  if (!own) readMaterial(params, "collision/", shape.material);
  return shape;
}

}  // namespace rigid_body_ros
