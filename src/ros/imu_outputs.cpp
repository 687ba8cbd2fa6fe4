#include "rigid_body_sim/ros/imu_outputs.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <cmath>

#include "rigid_body_sim/imu.hpp"
#include "rigid_body_sim/rotation.hpp"
#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

namespace {

constexpr double kWarningPeriod = 2.0;  // [s] between repeats of the same warning

// Each sensor's three generators draw apart: seed, seed + 1, seed + 2 for gyroscope, accelerometer and
// orientation (a body's seed is its own; two bodies with one seed read alike, as two units of one batch).
constexpr std::uint64_t kGyroStream = 0, kAccelStream = 1, kOrientationStream = 2;

void setDiagonal(boost::array<double, 9>& covariance, double stddev) {
  covariance.fill(0.0);
  for (int i = 0; i < 3; ++i) covariance[4 * i] = stddev * stddev;
}

}  // namespace

ImuOutputs::ImuOutputs(ros::NodeHandle& nh, const NodeConfig& config) : config_(config), nh_(nh) {
  for (std::size_t body = 0; body < config.bodies.size(); ++body) addBody(body);
}

void ImuOutputs::addBody(std::size_t body) {
  const std::optional<ImuConfig>& imu = config_.bodies[body].imu;
  if (!imu) return;
  const uint32_t queue = config_.lockstep ? 100 : 10;
  const double period = 1.0 / imu->rate;
  const std::uint64_t seed = static_cast<std::uint64_t>(static_cast<std::int64_t>(imu->seed));
  std::unique_ptr<Sensor>& added = sensors_.append(body).handles;
  added.reset(new Sensor{
      *imu, nh_.advertise<sensor_msgs::Imu>(config_.bodies[body].topic("imu"), queue), OutputSchedule(),
      rigid_body::SensorNoiseModel(imu->gyro, period, seed + kGyroStream),
      rigid_body::SensorNoiseModel(imu->accel, period, seed + kAccelStream),
      // Orientation noise is white per sample: a density of σ √Δt gives the sample's σ.
      rigid_body::SensorNoiseModel({imu->orientation_stddev * std::sqrt(period), 0.0}, period, seed + kOrientationStream),
      sensor_msgs::Imu()});
  Sensor& sensor = *added;
  sensor.message.header.frame_id = imu->frame;
  // The covariance of one sample's white part (the bias is not in it: it is a slowly changing offset).
  setDiagonal(sensor.message.angular_velocity_covariance, sensor.gyro_noise.whiteStddev());
  setDiagonal(sensor.message.linear_acceleration_covariance, sensor.accel_noise.whiteStddev());
  setDiagonal(sensor.message.orientation_covariance, imu->orientation_stddev);
}

void ImuOutputs::removeBody(std::size_t body) { sensors_.erase(body); }

std::vector<geometry_msgs::TransformStamped> ImuOutputs::sensorFrames(const ros::Time& stamp) const {
  std::vector<geometry_msgs::TransformStamped> frames;
  for (const auto& entry : sensors_.entries()) {
    const Sensor* sensor = entry->handles.get();
    Eigen::Isometry3d X_PS = Eigen::Isometry3d::Identity();
    X_PS.linear() = sensor->config.orientation.toRotationMatrix();
    X_PS.translation() = sensor->config.position;
    geometry_msgs::TransformStamped frame = tf2::eigenToTransform(Eigen::Affine3d(X_PS.matrix()));
    frame.header.stamp = stamp;
    frame.header.frame_id = config_.bodies[entry->body].body_frame;
    frame.child_frame_id = sensor->config.frame;
    frames.push_back(frame);
  }
  return frames;
}

void ImuOutputs::publish(const rigid_body::World& world) {
  for (const auto& entry : sensors_.entries()) {
    Sensor& sensor = *entry->handles;
    if (sensor.schedule.due(world.stamp(), rigid_body::toNanoseconds(1.0 / sensor.config.rate))) {
      publishSensor(world, entry->body, sensor);
    }
  }
}

void ImuOutputs::publishSensor(const rigid_body::World& world, std::size_t body, Sensor& sensor) {
  const rigid_body::Scene& scene = world.scene();
  // The contacts of the last step act through their mean force over it (imu.hpp); a body without a
  // collision shape has none.
  const rigid_body::Wrench contact =
      scene.collides(body) ? rigid_body::contactWrench(scene.contacts(body), scene.state(body).p_WB, scene.dt())
                           : rigid_body::Wrench();
  const rigid_body::ImuReading reading =
      rigid_body::imuReading(scene.model(body), scene.state(body), scene.input(body), contact, sensor.config.mount);
  // The noise is drawn even when the reading is withheld, so that the sequence depends on the samples only.
  const Eigen::Vector3d gyro = reading.angular_velocity_S + sensor.gyro_noise.next();
  const Eigen::Vector3d accel = reading.specific_force_S + sensor.accel_noise.next();
  // A small rotation about the sensor's own axes, q ⊗ exp(δ_S), as the covariance is declared.
  const Eigen::Quaterniond q_WS = reading.q_WS * rigid_body::quaternionExp(sensor.orientation_noise.next());
  if (!gyro.allFinite() || !accel.allFinite() || !q_WS.coeffs().allFinite()) {
    ++withheld_;
    ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: %s: imu withheld: a non-finite reading",
                      config_.bodies[body].body_frame.c_str());
    return;
  }
  sensor.message.header.stamp = toRosTime(world.stamp());
  sensor.message.orientation = tf2::toMsg(q_WS);
  tf2::toMsg(gyro, sensor.message.angular_velocity);
  tf2::toMsg(accel, sensor.message.linear_acceleration);
  sensor.publisher.publish(sensor.message);
}

}  // namespace rigid_body_ros
