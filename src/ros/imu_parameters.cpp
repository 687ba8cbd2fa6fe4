#include "rigid_body_sim/ros/imu_parameters.hpp"

#include <limits>

#include "parameter_values.hpp"
#include "rigid_body_sim/ros/parameter_schema.hpp"
#include "rigid_body_sim/number_format.hpp"

namespace rigid_body_ros {

using namespace parameter_values;

namespace {

double readDensity(const XmlRpcValue& params, const std::string& key, const std::string& unit) {
  return readNumber(params, key, 0.0, [](double v) { return v >= 0.0; }, "must be a finite number >= 0 [" + unit + "]");
}

}  // namespace

std::optional<ImuConfig> readImu(const XmlRpcValue& params, const BodyConfig& body, const NodeConfig& scene,
                                 std::vector<std::string>& unknown) {
  const XmlRpcValue* value = find(params, "imu");
  if (!value) return std::nullopt;
  if (value->getType() == XmlRpcValue::TypeBoolean) {
    if (!static_cast<const bool&>(*value)) return std::nullopt;
  } else {
    requireStruct(params, "imu", "frame, position, orientation, rate, gyro_noise_density, gyro_random_walk, "
                                 "accel_noise_density, accel_random_walk, orientation_stddev, seed (or true)");
    collectUnknown(*value, "imu/", bodySchemaKeys("imu/"), unknown);
  }
  ImuConfig imu;
  imu.frame = readFrame(params, "imu/frame", body.body_frame + "_imu");
  if (imu.frame == body.body_frame || imu.frame == scene.world_frame) {
    failAt(params, "imu/frame", XmlRpcValue(imu.frame), "must differ from the body's body_frame and from ~world_frame");
  }
  imu.position = readVector3(params, "imu/position", "[m], in body_frame");
  imu.orientation = readQuaternion(params, "imu/orientation").normalized();
  // The sensor reads at ticks: it cannot read more often than the node ticks.
  const std::string rate_rule = "must be a finite number in (0, rate = " + rigid_body::formatNumber(scene.rate, 6) + "] [Hz]";
  imu.rate = readNumber(params, "imu/rate", scene.rate, [&](double r) { return r > 0.0 && r <= scene.rate; }, rate_rule);
  imu.gyro.noise_density = readDensity(params, "imu/gyro_noise_density", "rad/s/sqrt(Hz)");
  imu.gyro.random_walk = readDensity(params, "imu/gyro_random_walk", "rad/s^2/sqrt(Hz)");
  imu.accel.noise_density = readDensity(params, "imu/accel_noise_density", "m/s^2/sqrt(Hz)");
  imu.accel.random_walk = readDensity(params, "imu/accel_random_walk", "m/s^3/sqrt(Hz)");
  imu.orientation_stddev = readDensity(params, "imu/orientation_stddev", "rad");
  imu.seed = readInteger(params, "imu/seed", 1, std::numeric_limits<int>::min(), "must be an integer");
  // The position and axes are given in the published frame P (body_frame); the core wants them in B.
  imu.mount.p_BS_B = body.X_BP * imu.position;
  imu.mount.q_BS = (Eigen::Quaterniond(body.X_BP.linear()) * imu.orientation).normalized();
  return imu;
}

}  // namespace rigid_body_ros
