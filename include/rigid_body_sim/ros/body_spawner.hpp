// A body spawned at run time, from text to a checked BodyConfig: the YAML of one ~bodies item read into the
// value the parameter parser reads, parsed as that item would be at start-up, then checked against the
// scene as it stands (names and frames taken). Pure functions: the node's spawn service calls them, tests too.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <cstddef>
#include <string>

#include "rigid_body_sim/ros/parameters.hpp"

namespace rigid_body_ros {

/// The longest YAML text a spawn request may carry [bytes]: a body's keys are a few hundred bytes; a mesh
/// or a robot description is named by path or parameter, never inlined.
constexpr std::size_t kMaxSpawnYamlBytes = 1 << 20;
/// The deepest nesting of maps and lists a spawn request may carry (a body's keys nest two levels).
constexpr int kMaxSpawnYamlDepth = 16;

/// YAML text as the XmlRpc value rosparam would make of it: maps as structs, sequences as arrays, and a plain
/// scalar as a bool, an int, a double or, failing those, a string (a quoted scalar stays a string). Throws
/// ParameterError for text that is not YAML, longer than kMaxSpawnYamlBytes or nested deeper than
/// kMaxSpawnYamlDepth, or a map key that is not a scalar.
XmlRpc::XmlRpcValue yamlToXmlRpc(const std::string& yaml);

/// The body `yaml` describes (the keys of one ~bodies item), for the scene `scene` as it stands: its gravity
/// and frames; unknown keys are refused (a spawn has no start-up log to warn in). Throws ParameterError with
/// a message naming the key ("spawn: key mass = -1: must be ..."), also when the name or body_frame is taken by
/// a body or an environment shape, or a frame of the body would be the world frame.
BodyConfig parseSpawnedBody(const std::string& yaml, const NodeConfig& scene, const ParameterReader& reader);

/// The index of the body called `name` (its name, or its body_frame for a body without one); scene.bodies.size()
/// when there is none.
std::size_t findBody(const NodeConfig& scene, const std::string& name);

}  // namespace rigid_body_ros
