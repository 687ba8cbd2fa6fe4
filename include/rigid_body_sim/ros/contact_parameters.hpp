// The contact parameters: the scene's ~environment, each body's collision and ~contact/ solver settings,
// read into the core's plain descriptions. Every failure is a ParameterError naming the parameter.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <optional>
#include <string>
#include <vector>

#include "rigid_body_sim/collision_shape.hpp"
#include "rigid_body_sim/contact.hpp"

namespace rigid_body_ros {

struct BodyConfig;

/// ~environment: a list of static shapes (plane, box, sphere, cylinder, capsule, mesh). Unset: none.
std::vector<rigid_body::CollisionShape> readEnvironment(const XmlRpc::XmlRpcValue& params, std::size_t max_mesh_bytes);

/// A body's `collision` key: absent or false, none; true, the body's own shape; a struct, its keys over the
/// body's own shape. `body` has its shape, size and mesh read already.
std::optional<rigid_body::CollisionShape> readCollision(const XmlRpc::XmlRpcValue& params, const BodyConfig& body);

/// The keys known of an ~environment item and of a body's collision struct (~contact/'s are the parameter
/// schema's rows, parameter_schema.hpp).
extern const char* const kEnvironmentKeys[];
extern const char* const kCollisionKeys[];

}  // namespace rigid_body_ros
