// What the parameter tests share: a list value and the message a parameter set raises.
#pragma once

#include <initializer_list>
#include <string>

#include "rigid_body_sim/ros/parameters.hpp"

namespace parameter_test {

/// An XmlRpc array of doubles.
inline XmlRpc::XmlRpcValue list(std::initializer_list<double> values) {
  XmlRpc::XmlRpcValue array;
  array.setSize(static_cast<int>(values.size()));
  int i = 0;
  for (double v : values) array[i++] = v;
  return array;
}

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
