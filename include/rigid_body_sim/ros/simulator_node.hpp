// The ROS node around one simulated body: wrench in, tf2 + odometry + state out, a timer that only calls
// update(now). It owns the core Simulation as a member and adds nothing to the physics.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <cstdint>

#include "rigid_body_sim/RigidBodyState.h"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/simulation.hpp"

namespace rigid_body_ros {

/// Counts of what the node refused or lost since start-up.
struct Counters {
  std::uint64_t wrenches_applied = 0;
  std::uint64_t rejected_non_finite = 0;    ///< wrenches with a NaN or Inf component
  std::uint64_t rejected_unknown_frame = 0; ///< wrenches in a frame tf2 could not resolve
  std::uint64_t dropped_steps = 0;          ///< steps beyond max_substeps in one tick
  std::uint64_t failed_steps = 0;           ///< steps whose result was not finite (state kept)
  std::uint64_t wrench_timeouts = 0;        ///< transitions to zero wrench after wrench_timeout
};

class SimulatorNode {
 public:
  /// `nh` carries the namespace of the topics and the reset service. Creates publishers, the subscriber
  /// and the service; the clock starts with start().
  SimulatorNode(const ros::NodeHandle& nh, const NodeConfig& config);

  /// Anchors simulated time 0 at `start_time` and starts the timer at config.rate.
  void start(const ros::Time& start_time);

  /// One tick: integrates the whole steps due up to `now` and publishes the state if the clock reached a
  /// new grid point. Published stamps are start + clock steps · dt, so they strictly increase.
  void update(const ros::Time& now);

  void onWrench(const geometry_msgs::WrenchStamped::ConstPtr& message);
  bool onReset(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);

  const rigid_body::Simulation& simulation() const { return simulation_; }
  const Counters& counters() const { return counters_; }

 private:
  /// Integrates up to `now` (used before an input changes, so an input acts from the step at its arrival).
  void advanceTo(const ros::Time& now);
  /// Applies wrench_timeout: the wrench acts until last arrival + timeout, then drops to zero.
  void expireWrench(const ros::Time& now);
  void publish();
  ros::Time stampOf(std::int64_t clock_steps) const;

  NodeConfig config_;
  rigid_body::Simulation simulation_;
  Counters counters_;

  ros::NodeHandle nh_;
  ros::Publisher odom_publisher_;
  ros::Publisher state_publisher_;
  ros::Subscriber wrench_subscriber_;
  ros::ServiceServer reset_service_;
  ros::Timer timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;

  ros::Time start_time_;
  bool started_ = false;
  std::int64_t published_clock_steps_ = -1;  ///< the clock step of the last publication
  bool wrench_active_ = false;               ///< a wrench is applied and may time out
  ros::Time last_wrench_time_;

  // Messages whose constant fields (frame ids, covariances) are filled once.
  nav_msgs::Odometry odom_message_;
  geometry_msgs::TransformStamped transform_message_;
  rigid_body_sim::RigidBodyState state_message_;
};

}  // namespace rigid_body_ros
