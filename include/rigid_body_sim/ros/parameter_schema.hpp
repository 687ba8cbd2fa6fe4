// The scene-wide scalar parameters, one row each: key, type, default, range, unit and a word of help. The
// rows drive their reading (with the range's error message), the known-key lists and the comparison with
// the README's parameter table (test_parameter_schema.cpp), and NodeConfig::describe()'s settings. Parameters whose rule depends on another
// (dt ≤ 1/rate, marker_rate ≤ rate), strings, frames and lists are read by hand in parameters.cpp and named
// here too (without a store) so that the known keys and the README check still cover them. A new scalar
// parameter is one row, its field in NodeConfig and its README row.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <limits>
#include <set>
#include <string>
#include <vector>

#include "rigid_body_sim/ros/parameters.hpp"

namespace rigid_body_ros {

enum class ParameterType { kNumber, kInteger, kBool, kString, kList };

/// [low, high], each end open or closed; ±∞ for no bound.
struct ParameterRange {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool low_open = false;
  bool high_open = false;
  bool contains(double value) const {
    return (low_open ? value > low : value >= low) && (high_open ? value < high : value <= high);
  }
};

struct ParameterSpec {
  const char* key;  ///< as the parameter server spells it under ~, e.g. "publish/tf"
  ParameterType type;
  /// The value taken when it is not set (numbers, integers, booleans as 0/1); +∞: unset means "no limit".
  double default_value;
  ParameterRange range;
  const char* unit;  ///< "" for a pure number
  const char* help;  ///< what the value means, for the error message
  /// Writes a read value into the config; null for a key read by hand in parameters.cpp.
  void (*store)(NodeConfig& config, double value);
  /// The value in a config, for describe() and the test that the struct's default is the schema's; null for
  /// a key that is not a plain field (strings, lists, publish_tf).
  double (*load)(const NodeConfig& config);
};

/// Every scene-wide scalar key, in the README's order.
const std::vector<ParameterSpec>& sceneParameterSchema();
/// Every key of one body (flat at the top level, or in each item of ~bodies; initial/ under it), read by
/// hand in parameters.cpp (their rules depend on the shape and on each other: no store): their type,
/// default and unit for the known keys and the README check. `name` and `collision` (a bool or a struct)
/// are known keys besides.
const std::vector<ParameterSpec>& bodyParameterSchema();
/// The keys of the body schema under `prefix` ("" or "initial/"), as schemaKeys does for the scene's.
std::set<std::string> bodySchemaKeys(const std::string& prefix);
/// The row of `key`, or null.
const ParameterSpec* findParameter(const std::string& key);
/// A row's range as the README writes it: "(0, 3600]", "≥ 0", "> 1", "" for none (an integer's bounds at the
/// int type's own limits are none).
std::string rangeText(const ParameterSpec& spec);
/// What an error says the value must be: "must be a finite number in (0, 3600] [s] (wall time ...)".
std::string allowedText(const ParameterSpec& spec);
/// Reads every row with a store from `params` into `config`, in the schema's order.
void readSchemaParameters(const XmlRpc::XmlRpcValue& params, NodeConfig& config);
/// "key value unit, ..." for every row the config holds as a plain field, for the start-up log.
std::string describeSchemaParameters(const NodeConfig& config);
/// The keys of the schema under `prefix` ("" for the top level, "publish/", "noise/"), prefix removed;
/// keys with a further '/' below are left out.
std::set<std::string> schemaKeys(const std::string& prefix);

}  // namespace rigid_body_ros
