#include "rigid_body_sim/ros/live_parameters.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <dynamic_reconfigure/Config.h>

namespace rigid_body_ros {

namespace {

// Seconds between two warnings about refused values (a flood of requests warns once per period).
constexpr double kRefusedWarningPeriod = 2.0;

}  // namespace

rigid_body_sim::RigidBodyConfig LiveParameters::fromNodeConfig(const NodeConfig& config) {
  rigid_body_sim::RigidBodyConfig live;
  // A scene's bodies may have dampings of their own: the live value starts at the first body's.
  live.linear_damping = config.bodies.front().model.forces.linear_damping;
  live.angular_damping = config.bodies.front().model.forces.angular_damping;
  live.gravity_x = config.gravity_W.x();
  live.gravity_y = config.gravity_W.y();
  live.gravity_z = config.gravity_W.z();
  live.wrench_timeout = config.wrench_timeout;
  live.max_force = config.wrench_limits.max_force;  // +inf when unset: no limit
  live.max_torque = config.wrench_limits.max_torque;
  live.real_time_factor = config.real_time_factor;
  live.marker_rate = config.marker_rate;
  // The noise is per axis at start-up; live, one value for every axis (it starts at the x axis's).
  live.noise_position_stddev = config.noise.position_stddev.x();
  live.noise_orientation_stddev = config.noise.orientation_stddev.x();
  live.noise_linear_velocity_stddev = config.noise.linear_velocity_stddev.x();
  live.noise_angular_velocity_stddev = config.noise.angular_velocity_stddev.x();
  return live;
}

LiveParameters::LiveParameters(const ros::NodeHandle& private_nh, NodeConfig& config, rigid_body::World& world,
                               Outputs& outputs, std::function<rigid_body::Nanoseconds()> now)
    : config_(config), world_(world), outputs_(outputs), now_(std::move(now)), current_(fromNodeConfig(config)) {
  server_ = std::make_unique<dynamic_reconfigure::Server<rigid_body_sim::RigidBodyConfig>>(
      mutex_, ros::NodeHandle(private_nh, kLiveNamespace));
  // The server starts from the node's values (not the .cfg defaults), so the first call changes nothing.
  server_->updateConfig(current_);
  server_->setCallback([this](rigid_body_sim::RigidBodyConfig& requested, uint32_t level) { onChange(requested, level); });
}

void LiveParameters::keepValidValues(rigid_body_sim::RigidBodyConfig& requested) {
  // The server clamps each value into the .cfg's range, but a NaN fails both of its comparisons and passes.
  // Every double of the config is checked by its message form, so that a parameter added later is too.
  // (An infinity is clamped to a finite end, except the limits' open top, where +inf means no limit.) A
  // limit of 0 or below (clamped to 0) would reject every wrench: refused, not read as "no limit".
  dynamic_reconfigure::Config asked, kept;
  requested.__toMessage__(asked);
  current_.__toMessage__(kept);
  std::string refused;
  for (dynamic_reconfigure::DoubleParameter& value : asked.doubles) {
    const bool limit = value.name == "max_force" || value.name == "max_torque";
    if (!std::isnan(value.value) && !(limit && value.value <= 0.0)) continue;
    for (const dynamic_reconfigure::DoubleParameter& in_force : kept.doubles) {
      if (in_force.name == value.name) value.value = in_force.value;
    }
    refused += (refused.empty() ? "" : ", ") + value.name;
  }
  if (refused.empty()) return;
  requested.__fromMessage__(asked);
  ++refused_;
  ROS_WARN_THROTTLE(kRefusedWarningPeriod,
                    "rigid_body_node: live parameters: %s refused (NaN, or a limit not > 0), the values in force "
                    "kept (%llu requests refused so far)",
                    refused.c_str(), static_cast<unsigned long long>(refused_));
}

void LiveParameters::onChange(rigid_body_sim::RigidBodyConfig& requested, uint32_t) {
  keepValidValues(requested);  // what the server then writes back to the parameter server, too
  const rigid_body::Nanoseconds arrival = now_();
  // Forces: applied to every body when one of them changed (gravity is the scene's; damping is set for all).
  const bool damping = requested.linear_damping != current_.linear_damping ||
                       requested.angular_damping != current_.angular_damping;
  const bool gravity = requested.gravity_x != current_.gravity_x || requested.gravity_y != current_.gravity_y ||
                       requested.gravity_z != current_.gravity_z;
  if (damping || gravity) {
    config_.gravity_W = Eigen::Vector3d(requested.gravity_x, requested.gravity_y, requested.gravity_z);
    for (std::size_t body = 0; body < config_.bodies.size(); ++body) {
      rigid_body::ForceModel forces = world_.scene().model(body).forces;
      forces.gravity_W = config_.gravity_W;
      if (damping) {
        forces.linear_damping = requested.linear_damping;
        forces.angular_damping = requested.angular_damping;
      }
      config_.bodies[body].model.forces = forces;
      const rigid_body::CommandReply reply = world_.setForceModel(body, forces, arrival);
      if (!reply.accepted) ROS_WARN("rigid_body_node: live parameters: %s", reply.message.c_str());
    }
  }
  if (requested.wrench_timeout != current_.wrench_timeout) {
    config_.wrench_timeout = requested.wrench_timeout;
    world_.setWrenchTimeout(requested.wrench_timeout, arrival);
  }
  config_.wrench_limits.max_force = requested.max_force;
  config_.wrench_limits.max_torque = requested.max_torque;
  config_.real_time_factor = requested.real_time_factor;
  // The marker rate stays within the node's rate, as at start-up.
  requested.marker_rate = std::min(requested.marker_rate, config_.rate);
  config_.marker_rate = requested.marker_rate;
  if (requested.noise_position_stddev != current_.noise_position_stddev ||
      requested.noise_orientation_stddev != current_.noise_orientation_stddev ||
      requested.noise_linear_velocity_stddev != current_.noise_linear_velocity_stddev ||
      requested.noise_angular_velocity_stddev != current_.noise_angular_velocity_stddev) {
    config_.noise.position_stddev.setConstant(requested.noise_position_stddev);
    config_.noise.orientation_stddev.setConstant(requested.noise_orientation_stddev);
    config_.noise.linear_velocity_stddev.setConstant(requested.noise_linear_velocity_stddev);
    config_.noise.angular_velocity_stddev.setConstant(requested.noise_angular_velocity_stddev);
    outputs_.setNoise(config_.noise);
  }
  current_ = requested;
}

}  // namespace rigid_body_ros
