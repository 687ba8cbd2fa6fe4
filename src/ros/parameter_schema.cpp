#include "rigid_body_sim/ros/parameter_schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "parameter_values.hpp"
#include "rigid_body_sim/number_format.hpp"

namespace rigid_body_ros {

using namespace parameter_values;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kIntMin = std::numeric_limits<int>::min();
constexpr double kIntMax = std::numeric_limits<int>::max();
// [low, high]; (low, high]; ≥ low; > low; none.
constexpr ParameterRange closed(double low, double high) { return {low, high, false, false}; }
constexpr ParameterRange leftOpen(double low, double high) { return {low, high, true, false}; }
constexpr ParameterRange atLeast(double low) { return {low, kInf, false, false}; }
constexpr ParameterRange above(double low) { return {low, kInf, true, false}; }
constexpr ParameterRange anyValue() { return {-kInf, kInf, false, false}; }

// A field of NodeConfig as the schema's store and load (numbers, counts and flags all as double: counts up to
// 2^53 are exact).
#define RBS_FIELD(path)                                                                              \
  [](NodeConfig& c, double v) { c.path = static_cast<decltype(c.path)>(v); },                       \
      [](const NodeConfig& c) { return static_cast<double>(c.path); }
#define RBS_BY_HAND nullptr, nullptr
// Read by hand (its rule involves another key), but a plain field the schema can show and check.
#define RBS_SHOWN(path) nullptr, [](const NodeConfig& c) { return static_cast<double>(c.path); }

}  // namespace

const std::vector<ParameterSpec>& sceneParameterSchema() {
  using T = ParameterType;
  // key, type, default, range, unit, help, where it goes. In the README's order.
  static const std::vector<ParameterSpec> schema = {
      {"rate", T::kNumber, 100.0, closed(1e-3, 1e4), "Hz", "the timer's and the outputs' rate", RBS_FIELD(rate)},
      {"dt", T::kNumber, 0.001, anyValue(), "s", "in [1e-6, 1/rate]", RBS_SHOWN(dt)},
      {"integrator", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"abs_tolerance", T::kNumber, 1e-9, closed(1e-15, 1.0), "", "dopri5's absolute error per step",
       RBS_FIELD(integrator_settings.abs_tolerance)},
      {"rel_tolerance", T::kNumber, 1e-9, closed(1e-15, 1.0), "", "dopri5's relative error per step",
       RBS_FIELD(integrator_settings.rel_tolerance)},
      {"world_frame", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"gravity", T::kList, 0.0, anyValue(), "m/s²", "", RBS_BY_HAND},
      {"wrench_timeout", T::kNumber, 0.0, atLeast(0.0), "s", "0: hold until the next wrench", RBS_FIELD(wrench_timeout)},
      {"max_substeps", T::kInteger, 1000, closed(1, kIntMax), "steps", "", RBS_FIELD(max_substeps)},
      {"max_body_steps_per_tick", T::kInteger, 2000000, closed(1, kIntMax), "body-steps",
       "steps x bodies one tick may integrate", RBS_FIELD(max_body_steps_per_tick)},
      {"max_body_steps_per_request", T::kInteger, 2000000, closed(1, kIntMax), "body-steps",
       "steps x bodies one step request may ask for", RBS_FIELD(max_body_steps_per_request)},
      {"max_tick_seconds", T::kNumber, 0.2, leftOpen(0.0, 3600.0), "s", "wall time one tick may integrate for",
       RBS_FIELD(max_tick_seconds)},
      {"max_request_seconds", T::kNumber, 1.0, leftOpen(0.0, 3600.0), "s", "wall time one step request may take",
       RBS_FIELD(max_request_seconds)},
      {"max_force", T::kNumber, kInf, above(0.0), "N", "leave it unset for no limit", RBS_FIELD(wrench_limits.max_force)},
      {"max_torque", T::kNumber, kInf, above(0.0), "N m", "leave it unset for no limit",
       RBS_FIELD(wrench_limits.max_torque)},
      {"threads", T::kInteger, 0, closed(0, 256), "", "0: as many as the machine has", RBS_FIELD(threads)},
      {"max_energy_growth", T::kNumber, 2.0, above(1.0), "", "energy factor per tick", RBS_FIELD(max_energy_growth)},
      // publish_tf is the older spelling of publish/tf, read together by hand (publish/tf wins).
      {"publish/tf", T::kBool, 1, anyValue(), "", "", RBS_SHOWN(publish.tf)},
      {"publish_tf", T::kBool, 1, anyValue(), "", "", RBS_BY_HAND},
      {"publish/odom", T::kBool, 1, anyValue(), "", "", RBS_FIELD(publish.odom)},
      {"publish/state", T::kBool, 1, anyValue(), "", "", RBS_FIELD(publish.state)},
      {"publish/applied_wrench", T::kBool, 1, anyValue(), "", "", RBS_FIELD(publish.applied_wrench)},
      {"publish/per_body_topics", T::kBool, 1, anyValue(), "", "", RBS_FIELD(publish.per_body_topics)},
      {"publish/body_services", T::kBool, 1, anyValue(), "", "", RBS_FIELD(publish.body_services)},
      {"publish/clock", T::kBool, 0, anyValue(), "", "", RBS_FIELD(publish.clock)},
      {"publish/tf_rate", T::kNumber, 0.0, anyValue(), "Hz", "0 or in [0.001, rate]", RBS_SHOWN(publish.tf_rate)},
      {"publish/odom_rate", T::kNumber, 0.0, anyValue(), "Hz", "0 or in [0.001, rate]", RBS_SHOWN(publish.odom_rate)},
      {"publish/state_rate", T::kNumber, 0.0, anyValue(), "Hz", "0 or in [0.001, rate]",
       RBS_SHOWN(publish.state_rate)},
      {"lockstep", T::kBool, 0, anyValue(), "", "", RBS_FIELD(lockstep)},
      {"real_time_factor", T::kNumber, 1.0, atLeast(0.0), "", "0: as fast as possible", RBS_FIELD(real_time_factor)},
      {"start_paused", T::kBool, 0, anyValue(), "", "", RBS_FIELD(start_paused)},
      {"marker_rate", T::kNumber, 20.0, anyValue(), "Hz", "in [0.001, rate]", RBS_SHOWN(marker_rate)},
      // The contact solver's settings (docs/contact.md has their rows).
      {"contact/iterations", T::kInteger, 20, closed(1, 1000), "", "solver sweeps per step", RBS_FIELD(contact.iterations)},
      {"contact/iterations_dt", T::kNumber, 1e-3, closed(0.0, 1.0), "s", "0: iterations at every step",
       RBS_FIELD(contact.iterations_dt)},
      {"contact/position_iterations", T::kInteger, 4, closed(0, 1000), "", "projection sweeps per step",
       RBS_FIELD(contact.position_iterations)},
      {"contact/restitution_threshold", T::kNumber, 0.05, closed(0.0, 1000.0), "m/s", "",
       RBS_FIELD(contact.restitution_threshold)},
      {"contact/penetration_slop", T::kNumber, 1e-4, closed(0.0, 0.1), "m", "", RBS_FIELD(contact.penetration_slop)},
      {"contact/position_correction", T::kNumber, 0.2, closed(0.0, 1.0), "", "", RBS_FIELD(contact.position_correction)},
      {"contact/event_location", T::kBool, 1, anyValue(), "", "", RBS_FIELD(contact.event_location)},
      {"contact/continuous", T::kBool, 1, anyValue(), "", "", RBS_FIELD(contact.continuous)},
      {"contact/sleep", T::kBool, 1, anyValue(), "", "", RBS_FIELD(contact.sleep)},
      {"contact/sleep_time", T::kNumber, 0.5, closed(0.01, 3600.0), "s", "quiet time before an island sleeps",
       RBS_FIELD(contact.sleep_time)},
      {"contact/reuse_points", T::kBool, 1, anyValue(), "", "", RBS_FIELD(contact.reuse_points)},
      {"noise/position_stddev", T::kList, 0.0, anyValue(), "m", "", RBS_BY_HAND},
      {"noise/orientation_stddev", T::kList, 0.0, anyValue(), "rad", "", RBS_BY_HAND},
      {"noise/linear_velocity_stddev", T::kList, 0.0, anyValue(), "m/s", "", RBS_BY_HAND},
      {"noise/angular_velocity_stddev", T::kList, 0.0, anyValue(), "rad/s", "", RBS_BY_HAND},
      {"noise/seed", T::kInteger, 1, closed(kIntMin, kIntMax), "", "", RBS_FIELD(noise.seed)},
      {"noise/delay", T::kNumber, 0.0, closed(0.0, 3600.0), "s", "", RBS_FIELD(noise.delay)},
  };
  return schema;
}

const std::vector<ParameterSpec>& bodyParameterSchema() {
  using T = ParameterType;
  // key, type, default (+∞: unset), unit. In the README's order; read by hand (parameters.cpp).
  static const std::vector<ParameterSpec> schema = {
      {"body_frame", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"mass", T::kNumber, 1.0, anyValue(), "kg", "", RBS_BY_HAND},
      {"shape", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"size", T::kList, 0.0, anyValue(), "m", "", RBS_BY_HAND},
      {"inertia", T::kList, 0.0, anyValue(), "kg m²", "", RBS_BY_HAND},
      {"mesh", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"scale", T::kNumber, 1.0, anyValue(), "", "", RBS_BY_HAND},
      {"density", T::kNumber, kInf, anyValue(), "kg/m³", "", RBS_BY_HAND},
      {"inertia_method", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"samples", T::kInteger, 100000, anyValue(), "", "", RBS_BY_HAND},
      {"principal_axes", T::kBool, 0, anyValue(), "", "", RBS_BY_HAND},
      {"max_mesh_bytes", T::kNumber, 268435456.0, anyValue(), "bytes", "", RBS_BY_HAND},
      {"urdf", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"robot_description", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"link", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"mesh_frame", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"initial/position", T::kList, 0.0, anyValue(), "m", "", RBS_BY_HAND},
      {"initial/orientation", T::kList, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"initial/linear_velocity", T::kList, 0.0, anyValue(), "m/s", "", RBS_BY_HAND},
      {"initial/angular_velocity", T::kList, 0.0, anyValue(), "rad/s", "", RBS_BY_HAND},
      {"linear_damping", T::kNumber, 0.0, anyValue(), "N s/m", "", RBS_BY_HAND},
      {"angular_damping", T::kNumber, 0.0, anyValue(), "N m s/rad", "", RBS_BY_HAND},
      {"wrench_input", T::kBool, 1, anyValue(), "", "", RBS_BY_HAND},
      // A sensor on the body (imu_parameters.cpp): the default rate is the node's rate.
      {"imu/frame", T::kString, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"imu/position", T::kList, 0.0, anyValue(), "m", "", RBS_BY_HAND},
      {"imu/orientation", T::kList, 0.0, anyValue(), "", "", RBS_BY_HAND},
      {"imu/rate", T::kNumber, 100.0, anyValue(), "Hz", "", RBS_BY_HAND},
      {"imu/gyro_noise_density", T::kNumber, 0.0, anyValue(), "rad/s/√Hz", "", RBS_BY_HAND},
      {"imu/gyro_random_walk", T::kNumber, 0.0, anyValue(), "rad/s²/√Hz", "", RBS_BY_HAND},
      {"imu/accel_noise_density", T::kNumber, 0.0, anyValue(), "m/s²/√Hz", "", RBS_BY_HAND},
      {"imu/accel_random_walk", T::kNumber, 0.0, anyValue(), "m/s³/√Hz", "", RBS_BY_HAND},
      {"imu/orientation_stddev", T::kNumber, 0.0, anyValue(), "rad", "", RBS_BY_HAND},
      {"imu/seed", T::kInteger, 1, anyValue(), "", "", RBS_BY_HAND},
  };
  return schema;
}

#undef RBS_FIELD
#undef RBS_BY_HAND
#undef RBS_SHOWN

const ParameterSpec* findParameter(const std::string& key) {
  for (const ParameterSpec& spec : sceneParameterSchema()) {
    if (key == spec.key) return &spec;
  }
  return nullptr;
}

namespace {
// A bound as a person writes it: whole numbers in full (10000, not 1e+04), others in their shortest form.
std::string boundText(double value) {
  if (value == std::floor(value) && std::abs(value) < 1e15) return std::to_string(static_cast<long long>(value));
  return rigid_body::formatNumber(value);
}

// An integer row's bounds that are the int type's own are no bound at all.
bool isBound(const ParameterSpec* spec, double bound) {
  return std::isfinite(bound) && !(spec && spec->type == ParameterType::kInteger && (bound == kIntMin || bound == kIntMax));
}

std::string rangeText(const ParameterRange& range, const ParameterSpec* spec, const char* at_least) {
  const bool low = isBound(spec, range.low), high = isBound(spec, range.high);
  if (low && high) {
    return std::string(range.low_open ? "(" : "[") + boundText(range.low) + ", " + boundText(range.high) +
           (range.high_open ? ")" : "]");
  }
  if (low) return std::string(range.low_open ? "> " : at_least) + boundText(range.low);
  if (high) return std::string(range.high_open ? "< " : "<= ") + boundText(range.high);
  return "";
}
}  // namespace

std::string rangeText(const ParameterSpec& spec) { return rangeText(spec.range, &spec, "≥ "); }

std::string allowedText(const ParameterSpec& spec) {
  std::string text;
  switch (spec.type) {
    case ParameterType::kBool:
      return "must be true or false";
    case ParameterType::kNumber:
      text = "must be a finite number";
      break;
    case ParameterType::kInteger:
      text = "must be an integer";
      break;
    case ParameterType::kString:
    case ParameterType::kList:
      return spec.help;
  }
  const std::string range = rangeText(spec.range, &spec, ">= ");
  if (!range.empty()) text += (range[0] == '[' || range[0] == '(' ? " in " : " ") + range;
  if (*spec.unit != '\0') text += std::string(" [") + spec.unit + "]";
  if (*spec.help != '\0') text += std::string(" (") + spec.help + ")";
  return text;
}

void readSchemaParameters(const XmlRpcValue& params, NodeConfig& config) {
  for (const ParameterSpec& spec : sceneParameterSchema()) {
    if (!spec.store) continue;
    const std::string allowed = allowedText(spec);
    double value = spec.default_value;
    switch (spec.type) {
      case ParameterType::kNumber:
        value = readNumber(params, spec.key, spec.default_value, [&](double v) { return spec.range.contains(v); }, allowed);
        break;
      case ParameterType::kInteger: {
        const double low = std::max(spec.range.low, kIntMin);
        value = readInteger(params, spec.key, static_cast<int>(spec.default_value), static_cast<int>(low), allowed);
        if (!spec.range.contains(value)) failAt(params, spec.key, XmlRpcValue(), allowed);
        break;
      }
      case ParameterType::kBool:
        value = readBool(params, spec.key, spec.default_value != 0.0) ? 1.0 : 0.0;
        break;
      case ParameterType::kString:
      case ParameterType::kList:
        continue;
    }
    spec.store(config, value);
  }
}

std::string describeSchemaParameters(const NodeConfig& config) {
  std::string text;
  for (const ParameterSpec& spec : sceneParameterSchema()) {
    if (!spec.load) continue;
    const double value = spec.load(config);
    text += (text.empty() ? "" : ", ") + std::string(spec.key) + " ";
    if (spec.type == ParameterType::kBool) {
      text += value != 0.0 ? "true" : "false";
    } else if (std::isinf(value)) {
      text += "unset";
    } else {
      text += rigid_body::formatNumber(value, 6) + (*spec.unit != '\0' ? std::string(" ") + spec.unit : "");
    }
  }
  return text;
}

namespace {
std::set<std::string> keysUnder(const std::vector<ParameterSpec>& schema, const std::string& prefix) {
  std::set<std::string> keys;
  for (const ParameterSpec& spec : schema) {
    const std::string key = spec.key;
    if (key.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = key.substr(prefix.size());
    if (rest.find('/') == std::string::npos) keys.insert(rest);
  }
  return keys;
}
}  // namespace

std::set<std::string> schemaKeys(const std::string& prefix) { return keysUnder(sceneParameterSchema(), prefix); }

std::set<std::string> bodySchemaKeys(const std::string& prefix) {
  std::set<std::string> keys = keysUnder(bodyParameterSchema(), prefix);
  if (prefix.empty()) keys.insert({"name", "collision", "initial", "imu"});
  return keys;
}

}  // namespace rigid_body_ros
