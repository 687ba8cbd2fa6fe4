#include "rigid_body_sim/ros/body_spawner.hpp"

#include <yaml-cpp/yaml.h>

#include <climits>
#include <string>
#include <vector>

namespace rigid_body_ros {

namespace {

XmlRpc::XmlRpcValue scalarValue(const YAML::Node& node) {
  const std::string& text = node.Scalar();
  // A quoted scalar ('1', "true") is text, as rosparam reads it.
  if (node.Tag() == "!") return XmlRpc::XmlRpcValue(text);
  bool flag = false;
  if (YAML::convert<bool>::decode(node, flag)) return XmlRpc::XmlRpcValue(flag);
  long long integer = 0;
  if (YAML::convert<long long>::decode(node, integer) && integer >= INT_MIN && integer <= INT_MAX) {
    return XmlRpc::XmlRpcValue(static_cast<int>(integer));
  }
  double number = 0.0;
  if (YAML::convert<double>::decode(node, number)) return XmlRpc::XmlRpcValue(number);
  return XmlRpc::XmlRpcValue(text);
}

XmlRpc::XmlRpcValue convertNode(const YAML::Node& node, int depth) {
  if (depth > kMaxSpawnYamlDepth) {
    throw ParameterError("spawn: body: nested deeper than " + std::to_string(kMaxSpawnYamlDepth) + " levels");
  }
  XmlRpc::XmlRpcValue value;
  switch (node.Type()) {
    case YAML::NodeType::Map:
      value.begin();  // an empty struct (XmlRpcValue makes one of an invalid value on first use as a struct)
      for (const auto& member : node) {
        if (!member.first.IsScalar()) throw ParameterError("spawn: body: a map key must be a plain name");
        value[member.first.Scalar()] = convertNode(member.second, depth + 1);
      }
      return value;
    case YAML::NodeType::Sequence:
      value.setSize(static_cast<int>(node.size()));
      for (std::size_t i = 0; i < node.size(); ++i) value[static_cast<int>(i)] = convertNode(node[i], depth + 1);
      return value;
    case YAML::NodeType::Scalar:
      return scalarValue(node);
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return value;  // invalid: "not set", as an unset parameter
  }
  return value;
}

// "parameter ~bodies[0]/mass = -1: ..." of the start-up parser as "spawn: key mass = -1: ...".
ParameterError asSpawnError(const ParameterError& error) {
  std::string message = error.what();
  for (const std::string prefix : {"parameter ~bodies[0]/", "parameter ~bodies[0]", "parameter ~"}) {
    if (message.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = message.substr(prefix.size());
    return ParameterError("spawn: " + (rest.empty() || rest[0] == ' ' ? "body" + rest : "key " + rest));
  }
  return ParameterError("spawn: " + message);
}

// The name or body_frame of `body` already named in the scene (a body's name or frames, an environment shape).
void refuseTakenNames(const BodyConfig& body, const NodeConfig& scene) {
  for (const BodyConfig& other : scene.bodies) {
    if (!other.name.empty() && (other.name == body.name || other.name == body.body_frame)) {
      throw ParameterError("spawn: key name = " + body.name + ": the scene has a body of that name already");
    }
    for (const std::string& frame : {other.body_frame, other.mesh_frame, other.imu ? other.imu->frame : std::string()}) {
      if (frame.empty()) continue;
      if (frame == body.body_frame || frame == body.mesh_frame || (body.imu && frame == body.imu->frame)) {
        throw ParameterError("spawn: key body_frame = " + body.body_frame + ": the tf frame " + frame +
                             " is a frame of body " + (other.name.empty() ? other.body_frame : other.name) +
                             " already (one frame, one parent in tf's tree)");
      }
    }
  }
  for (const rigid_body::CollisionShape& shape : scene.environment) {
    if (shape.name == body.name || shape.name == body.body_frame) {
      throw ParameterError("spawn: key name = " + body.name + ": an environment shape has that name (contacts name "
                           "both sides by it)");
    }
  }
}

}  // namespace

XmlRpc::XmlRpcValue yamlToXmlRpc(const std::string& yaml) {
  if (yaml.size() > kMaxSpawnYamlBytes) {
    throw ParameterError("spawn: body: " + std::to_string(yaml.size()) + " bytes of YAML, more than the " +
                         std::to_string(kMaxSpawnYamlBytes) + " a body's keys may take (name meshes and robot "
                         "descriptions by path or parameter)");
  }
  try {
    return convertNode(YAML::Load(yaml), 0);
  } catch (const YAML::Exception& error) {
    throw ParameterError(std::string("spawn: body: not YAML: ") + error.what());
  }
}

BodyConfig parseSpawnedBody(const std::string& yaml, const NodeConfig& scene, const ParameterReader& reader) {
  const XmlRpc::XmlRpcValue item = yamlToXmlRpc(yaml);
  if (item.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    throw ParameterError("spawn: body = '" + yaml.substr(0, 80) +
                         "': must be a YAML map with the keys of one item of ~bodies, at least name");
  }
  std::vector<std::string> unknown;
  BodyConfig body;
  try {
    body = parseBodyItem(item, scene, unknown, reader);
  } catch (const ParameterError& error) {
    throw asSpawnError(error);
  }
  if (!unknown.empty()) {
    const std::string item_prefix = "bodies[0]/";
    std::string key = unknown.front();
    if (key.compare(0, item_prefix.size(), item_prefix) == 0) key.erase(0, item_prefix.size());
    throw ParameterError("spawn: key " + key + ": not a key of a body (README, \"Parameters\")");
  }
  refuseTakenNames(body, scene);
  return body;
}

std::size_t findBody(const NodeConfig& scene, const std::string& name) {
  if (name.empty()) return scene.bodies.size();
  for (std::size_t body = 0; body < scene.bodies.size(); ++body) {
    const BodyConfig& config = scene.bodies[body];
    if (config.name == name || (config.name.empty() && config.body_frame == name)) return body;
  }
  return scene.bodies.size();
}

}  // namespace rigid_body_ros
