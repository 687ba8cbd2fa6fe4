// What the parameter tests share: the message a parameter set raises.
#pragma once

#include <string>

#include "rigid_body_sim/ros/parameters.hpp"

namespace parameter_test {

/// The message of the ParameterError that `params` raises, or "" if it parses.
inline std::string errorOf(const XmlRpc::XmlRpcValue& params) {
  try {
    rigid_body_ros::parseConfig(params);
  } catch (const rigid_body_ros::ParameterError& error) {
    return error.what();
  }
  return "";
}

}  // namespace parameter_test
