// The noisy copy of a body's odometry (odom_noisy): seeded Gaussian noise on pose and twist, covariances
// that match it, and a publication delay held in a bounded queue.
#pragma once

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include <cstdint>
#include <deque>
#include <random>

#include "rigid_body_sim/ros/parameters.hpp"

namespace rigid_body_ros {

class OdometryNoise {
 public:
  /// `stream` separates the generators of the bodies (seed + stream).
  OdometryNoise(ros::NodeHandle& nh, const std::string& topic, uint32_t queue, const NoiseConfig& noise, double rate,
                std::uint64_t stream);

  /// New standard deviations (a live change); the generator's stream and the delay go on.
  void setStddevs(const NoiseConfig& noise);

  /// Draws the noise onto a copy of `truth` and publishes what the delay lets through at `stamp`.
  void publish(const nav_msgs::Odometry& truth, const ros::Time& stamp);

  /// Messages dropped because more than the queue's bound waited out the delay.
  std::uint64_t dropped() const { return dropped_; }

 private:
  NoiseConfig noise_;
  ros::Publisher publisher_;
  std::mt19937_64 generator_;
  std::deque<nav_msgs::Odometry> delayed_;
  std::size_t max_delayed_;
  std::uint64_t dropped_ = 0;
};

}  // namespace rigid_body_ros
