// NAME/imu (sensor_msgs/Imu) of every body with an `imu`: the core's reading (imu.hpp) at the sensor's rate
// on a grid of simulated time, with the sensor's noise (imu_noise.hpp) drawn at that rate, stamped with the
// world's stamp, in the sensor's frame (REP 145: specific force, a body at rest on the ground reads +g up).
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "rigid_body_sim/imu_noise.hpp"
#include "rigid_body_sim/ros/body_list.hpp"
#include "rigid_body_sim/ros/output_schedule.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

class ImuOutputs {
 public:
  ImuOutputs(ros::NodeHandle& nh, const NodeConfig& config);

  /// Every sensor that is due at the world's stamp.
  void publish(const rigid_body::World& world);
  /// The fixed transforms body_frame → sensor frame, for the node's one static broadcast.
  std::vector<geometry_msgs::TransformStamped> sensorFrames(const ros::Time& stamp) const;
  /// The body the config now has last, at `body`: its sensor, if it has one.
  void addBody(std::size_t body);
  /// The body at `body` is gone: its sensor's publisher shuts down, the later bodies move down one index.
  void removeBody(std::size_t body);
  /// Readings withheld because a value was not finite.
  std::uint64_t withheld() const { return withheld_; }

 private:
  struct Sensor {
    ImuConfig config;  ///< a copy: the config's body list moves when bodies are spawned
    ros::Publisher publisher;
    OutputSchedule schedule;
    rigid_body::SensorNoiseModel gyro_noise;
    rigid_body::SensorNoiseModel accel_noise;
    rigid_body::SensorNoiseModel orientation_noise;
    sensor_msgs::Imu message;  ///< frame and covariances filled once
  };
  void publishSensor(const rigid_body::World& world, std::size_t body, Sensor& sensor);

  const NodeConfig& config_;
  ros::NodeHandle nh_;
  BodyList<std::unique_ptr<Sensor>> sensors_;  ///< per body with an `imu`
  std::uint64_t withheld_ = 0;
};

}  // namespace rigid_body_ros
