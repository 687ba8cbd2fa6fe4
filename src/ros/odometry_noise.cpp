#include "rigid_body_sim/ros/odometry_noise.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>

#include "rigid_body_sim/rotation.hpp"

namespace rigid_body_ros {

namespace {
// The delay queue holds what one delay produces at the publish rate, plus slack, and never more than this.
constexpr std::size_t kMaxDelayedMessages = 100000;
}  // namespace

OdometryNoise::OdometryNoise(ros::NodeHandle& nh, const std::string& topic, uint32_t queue, const NoiseConfig& noise,
                             double rate, std::uint64_t stream)
    : noise_(noise),
      publisher_(nh.advertise<nav_msgs::Odometry>(topic, queue)),
      generator_(static_cast<std::uint64_t>(noise.seed) + stream),
      max_delayed_(static_cast<std::size_t>(
          std::min(static_cast<double>(kMaxDelayedMessages), std::ceil(noise.delay * rate) + 2.0))) {}

void OdometryNoise::publish(const nav_msgs::Odometry& truth, const ros::Time& stamp) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto draw = [&](const Eigen::Vector3d& stddev) {
    return Eigen::Vector3d(stddev.x() * normal(generator_), stddev.y() * normal(generator_),
                           stddev.z() * normal(generator_));
  };
  nav_msgs::Odometry noisy = truth;
  Eigen::Vector3d p, v, w;
  Eigen::Quaterniond q;
  tf2::fromMsg(truth.pose.pose.position, p);
  tf2::fromMsg(truth.pose.pose.orientation, q);
  tf2::fromMsg(truth.twist.twist.linear, v);
  tf2::fromMsg(truth.twist.twist.angular, w);
  noisy.pose.pose.position = tf2::toMsg(Eigen::Vector3d(p + draw(noise_.position_stddev)));
  // A small rotation about the world axes, exp(δ_W) ⊗ q: the pose covariance is declared in the pose's frame
  // (header.frame_id, REP 105), so its rotation block diag(σ²) is about the world axes too. (Drawn in body
  // axes, q ⊗ exp(δ_B), the noise about world axis i of a turned body would be another axis's σ.)
  noisy.pose.pose.orientation =
      tf2::toMsg(Eigen::Quaterniond(rigid_body::quaternionExp(draw(noise_.orientation_stddev)) * q));
  tf2::toMsg(Eigen::Vector3d(v + draw(noise_.linear_velocity_stddev)), noisy.twist.twist.linear);
  tf2::toMsg(Eigen::Vector3d(w + draw(noise_.angular_velocity_stddev)), noisy.twist.twist.angular);
  // Covariances consistent with the noise: diagonal variances, (x, y, z, rotation about x, y, z).
  for (int i = 0; i < 3; ++i) {
    noisy.pose.covariance[7 * i] = noise_.position_stddev(i) * noise_.position_stddev(i);
    noisy.pose.covariance[7 * (i + 3)] = noise_.orientation_stddev(i) * noise_.orientation_stddev(i);
    noisy.twist.covariance[7 * i] = noise_.linear_velocity_stddev(i) * noise_.linear_velocity_stddev(i);
    noisy.twist.covariance[7 * (i + 3)] = noise_.angular_velocity_stddev(i) * noise_.angular_velocity_stddev(i);
  }
  if (delayed_.size() >= max_delayed_) {
    delayed_.pop_front();
    ++dropped_;
  }
  delayed_.push_back(noisy);
  const std::uint64_t delay_ns = static_cast<std::uint64_t>(std::llround(noise_.delay * 1e9));
  while (!delayed_.empty() && delayed_.front().header.stamp.toNSec() + delay_ns <= stamp.toNSec()) {
    publisher_.publish(delayed_.front());
    delayed_.pop_front();
  }
}

void OdometryNoise::setStddevs(const NoiseConfig& noise) {
  noise_.position_stddev = noise.position_stddev;
  noise_.orientation_stddev = noise.orientation_stddev;
  noise_.linear_velocity_stddev = noise.linear_velocity_stddev;
  noise_.angular_velocity_stddev = noise.angular_velocity_stddev;
}

}  // namespace rigid_body_ros
