// Reading typed values out of the private namespace's XmlRpc struct, each failure a ParameterError that names
// the parameter, the value and what is allowed. Internal to the ROS layer's parameters.cpp.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "rigid_body_sim/ros/parameters.hpp"

namespace rigid_body_ros {
namespace parameter_values {

using XmlRpc::XmlRpcValue;

/// The value as the message shows it: numbers to 17 digits, strings quoted, lists in brackets.
std::string render(const XmlRpcValue& value);
/// Throws ParameterError("parameter ~NAME = VALUE: ALLOWED").
[[noreturn]] void fail(const std::string& name, const XmlRpcValue& value, const std::string& allowed);
/// fail() for the value NAME has: the one set in `params`, or, when it is not set, `effective`, the value the
/// node would take instead ("parameter ~NAME (not set, so VALUE): ALLOWED"). A check may refuse a
/// default, when the default comes from another parameter (a body_frame from a URDF link's name, an
/// environment shape's name from its type and index), so no failure reads the set value without this.
[[noreturn]] void failAt(const XmlRpcValue& params, const std::string& name, const XmlRpcValue& effective,
                         const std::string& allowed);
bool isNumber(const XmlRpcValue& value);
double asNumber(const XmlRpcValue& value);
/// Looks up a/b/c in nested structs; nullptr when it is not set.
const XmlRpcValue* find(const XmlRpcValue& params, const std::string& name);

// A number in [low, high] (bounds given as text for the message); `accept` says whether value fits.
template <typename Accept>
double readNumber(const XmlRpcValue& params, const std::string& name, double fallback, Accept accept,
                  const std::string& allowed) {
  const XmlRpcValue* value = find(params, name);
  if (!value) return fallback;
  if (!isNumber(*value)) fail(name, *value, allowed);
  const double number = asNumber(*value);
  if (!std::isfinite(number) || !accept(number)) fail(name, *value, allowed);
  return number;
}

/// An integer >= minimum (a double is refused: a count or a seed is not a measurement).
int readInteger(const XmlRpcValue& params, const std::string& name, int fallback, int minimum,
                const std::string& allowed);
/// A list of `length` finite numbers (also given as the text "[a, b, ...]", as roscpp passes rosrun lists).
std::vector<double> readNumbers(const XmlRpcValue& params, const std::string& name, std::vector<double> fallback,
                                size_t length, const std::string& allowed);
Eigen::Vector3d readVector3(const XmlRpcValue& params, const std::string& name, const std::string& unit);
/// A quaternion [x, y, z, w] (identity if unset) whose norm is within 1e-3 of 1, as given (the caller
/// normalises): a hand-typed [0, 0, 0.7071, 0.7071] is accepted.
Eigen::Quaterniond readQuaternion(const XmlRpcValue& params, const std::string& name);
std::string readString(const XmlRpcValue& params, const std::string& name, const std::string& fallback,
                       const std::string& allowed);
/// A non-empty tf2 frame id without a leading '/' or spaces.
std::string readFrame(const XmlRpcValue& params, const std::string& name, const std::string& fallback);
bool readBool(const XmlRpcValue& params, const std::string& name, bool fallback);
/// A key that groups others must be a struct: `_publish:=5` or `noise: loud` is an error, not "unset".
void requireStruct(const XmlRpcValue& params, const std::string& name, const std::string& keys);
/// The names in the struct `params` that `known` lacks, each prefixed, appended to `unknown`.
void collectUnknown(const XmlRpcValue& params, const std::string& prefix, const std::set<std::string>& known,
                    std::vector<std::string>& unknown);

}  // namespace parameter_values
}  // namespace rigid_body_ros
