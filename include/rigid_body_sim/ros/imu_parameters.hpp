// A body's `imu` key: absent, no sensor; true, a sensor at the published frame's origin with its axes and
// no noise; a struct, its keys (imu/frame, position, orientation, rate, the noise densities, seed). Every
// failure is a ParameterError naming the key.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <optional>
#include <string>
#include <vector>

#include "rigid_body_sim/ros/parameters.hpp"

namespace rigid_body_ros {

/// `body` has its frame, mass properties and published offset read already; `scene` its rate and world frame.
/// Keys of the struct the node does not know go to `unknown` as imu/KEY.
std::optional<ImuConfig> readImu(const XmlRpc::XmlRpcValue& params, const BodyConfig& body, const NodeConfig& scene,
                                 std::vector<std::string>& unknown);

}  // namespace rigid_body_ros
