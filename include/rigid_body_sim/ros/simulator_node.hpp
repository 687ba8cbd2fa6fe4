// The ROS node around one simulated scene: per body NAME/wrench in, NAME/odom and NAME/state out, the tf of
// every body in one message per tick, a timer that only calls update(now), and diagnostics. It owns the core
// Simulation as a member and adds nothing to the physics. Only the outputs the scene enables have a
// publisher, and only bodies with wrench input a subscriber.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <geometry_msgs/Wrench.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <vector>

#include "rigid_body_sim/ApplyWrench.h"
#include "rigid_body_sim/GetState.h"
#include "rigid_body_sim/RigidBodyState.h"
#include "rigid_body_sim/SetState.h"
#include "rigid_body_sim/Step.h"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/simulation.hpp"

namespace rigid_body_ros {

/// Counts of what the node applied, refused or lost since start-up.
struct Counters {
  std::uint64_t wrenches_applied = 0;         ///< summed over the bodies, as all the counts here
  std::uint64_t rejected_non_finite = 0;     ///< wrenches with a NaN or Inf component
  std::uint64_t rejected_force_limit = 0;    ///< |F| above max_force
  std::uint64_t rejected_torque_limit = 0;   ///< |τ| above max_torque
  std::uint64_t rejected_unknown_frame = 0;  ///< wrenches in a frame tf2 could not resolve
  std::uint64_t dropped_steps = 0;           ///< steps beyond max_substeps in one tick
  std::uint64_t wrench_timeouts = 0;         ///< transitions to zero wrench after wrench_timeout
  std::uint64_t backward_time_jumps = 0;     ///< ROS time went back by more than one tick period
  std::uint64_t timer_overruns = 0;          ///< ticks that took longer than the timer period
  std::int64_t last_substeps = 0;            ///< steps integrated by the last tick
  std::int64_t max_substeps_seen = 0;        ///< most steps one tick integrated

  std::uint64_t rejected() const {
    return rejected_non_finite + rejected_force_limit + rejected_torque_limit + rejected_unknown_frame;
  }
};

class SimulatorNode {
 public:
  /// `nh` carries the namespace of the topics and the services, `private_nh` the diagnostics' settings.
  /// Creates publishers, subscribers, services and the diagnostics; the clock starts with start().
  SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const NodeConfig& config);

  /// Anchors simulated time 0 at `start_time` and starts the timer at config.rate (not in lockstep).
  void start(const ros::Time& start_time);

  /// Lockstep: the node owns simulated time. Steps the scene, publishes /clock and the outputs at `rate`,
  /// paces itself by real_time_factor (0: as fast as possible), serves callbacks between steps; returns at
  /// shutdown. Called instead of ros::spin().
  void runLockstep();

  /// One tick: integrates the whole steps due up to `now` and publishes the state if the clock reached a
  /// new grid point. Published stamps advance by whole steps of dt from the anchor, so they strictly
  /// increase (a backward jump of ROS time re-anchors them to the new time).
  void update(const ros::Time& now);

  void onWrench(std::size_t body, const geometry_msgs::WrenchStamped::ConstPtr& message);
  /// wrench_unstamped: world axes about the centre of mass (a drop-in for gazebo_ros_force users).
  void onWrenchUnstamped(std::size_t body, const geometry_msgs::Wrench::ConstPtr& message);
  bool onReset(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onResetTime(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool onPause(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onUnpause(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onStep(rigid_body_sim::Step::Request& request, rigid_body_sim::Step::Response& response);
  bool onApplyWrench(std::size_t body, rigid_body_sim::ApplyWrench::Request& request,
                     rigid_body_sim::ApplyWrench::Response& response);
  bool onClearWrenches(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool onSetState(std::size_t body, rigid_body_sim::SetState::Request& request,
                  rigid_body_sim::SetState::Response& response);
  bool onGetState(std::size_t body, rigid_body_sim::GetState::Request& request,
                  rigid_body_sim::GetState::Response& response);

  const rigid_body::Simulation& simulation() const { return simulation_; }
  const Counters& counters() const { return counters_; }

 private:
  /// A service wrench acting over clock steps [start, end) (end < 0: until cleared).
  struct TimedWrench {
    rigid_body::AppliedWrench wrench;
    std::int64_t start;
    std::int64_t end;
  };

  /// One body's ROS side: its topics and services, its wrench sources, its output messages.
  struct BodyChannel {
    ros::Publisher odom_publisher;
    ros::Publisher state_publisher;
    ros::Publisher applied_wrench_publisher;
    ros::Publisher odom_noisy_publisher;  ///< only with noise
    // Subscribers connected to odom, state and applied_wrench (from the publishers' status callbacks): an
    // output nobody listens to is not even filled. roscpp finds a publication by a linear search over every
    // advertised topic, so publishing 1000 bodies' unheard odometry alone cost O(N²) per tick.
    int odom_subscribers = 0;
    int state_subscribers = 0;
    int applied_wrench_subscribers = 0;
    std::vector<ros::Subscriber> wrench_subscribers;  ///< wrench and wrench_unstamped, only with wrench input
    std::vector<ros::ServiceServer> services;         ///< get_state, set_state, apply_wrench (with wrench input)
    rigid_body::AppliedWrench topic_input;    ///< the latest wrench / wrench_unstamped (latest wins)
    std::vector<TimedWrench> timed_wrenches;  ///< apply_wrench requests (summed)
    bool wrench_active = false;               ///< a topic wrench is applied and may time out
    bool wrench_timed_out = false;
    ros::Time last_wrench_time;
    double max_norm_error = 0.0;              ///< max ||q| − 1| since reset
    std::mt19937_64 noise_generator;
    std::deque<nav_msgs::Odometry> delayed_noisy;  ///< noisy odometry waiting out noise/delay
    // Messages whose constant fields (frame ids, covariances) are filled once.
    nav_msgs::Odometry odom_message;
    rigid_body_sim::RigidBodyState state_message;
    geometry_msgs::WrenchStamped applied_wrench_message;
  };

  /// The node's notion of now: the lockstep clock, or ROS time.
  ros::Time now() const;
  /// Integrates up to `now` (used before an input changes, so an input acts from the step at its arrival).
  void advanceTo(const ros::Time& now);
  /// Integrates up to clock step `target`, switching the input at every start and end of a service wrench.
  void advanceToStep(std::int64_t target);
  /// A body's topic wrench plus every service wrench active at clock step k.
  rigid_body::AppliedWrench inputAtStep(const BodyChannel& channel, std::int64_t k) const;
  /// Gives the simulation every body's input of its current clock step (after any change of the wrench sources).
  void refreshInput();
  /// The same for one body, when only its wrench sources changed (a wrench message costs O(1), not O(bodies)).
  void refreshInput(std::size_t body);
  /// The first body that has diverged, or bodies_.size() when none has.
  std::size_t firstDivergedBody() const;
  /// Turns a validated message wrench (in `frame`) into world- or body-fixed parts, about the centre of mass;
  /// `point`, if given, is where the force acts, in `frame`. False if the frame cannot be resolved.
  bool toAppliedWrench(std::size_t body, const geometry_msgs::Wrench& wrench, const std::string& frame,
                       const ros::Time& stamp, const Eigen::Vector3d* point, rigid_body::AppliedWrench& out);
  bool acceptWrench(const geometry_msgs::Wrench& wrench);
  void setTopicWrench(std::size_t body, const rigid_body::AppliedWrench& input, const ros::Time& now);
  /// Back to the initial states with every wrench cleared (reset and reset_time).
  void resetBodies();
  void publishClock();
  void publishNoisy(BodyChannel& channel, const ros::Time& stamp);
  /// Applies wrench_timeout: a topic wrench acts until last arrival + timeout, then drops to zero.
  void expireWrenches(const ros::Time& now);
  void createBodyChannel(std::size_t body, uint32_t queue);
  void publish();
  ros::Time stampOf(std::int64_t clock_steps) const;
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  NodeConfig config_;
  rigid_body::Simulation simulation_;
  Counters counters_;
  std::vector<BodyChannel> bodies_;  ///< one per body of the scene, in the order of the simulation's

  ros::NodeHandle nh_;
  ros::Publisher clock_publisher_;       ///< lockstep only
  ros::ServiceServer reset_service_;
  std::vector<ros::ServiceServer> control_services_;
  ros::Timer timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> mesh_frame_broadcaster_;  ///< only with a mesh_frame
  diagnostic_updater::Updater diagnostics_;
  double min_frequency_;  ///< bounds of the publish-rate status [Hz]
  double max_frequency_;
  diagnostic_updater::FrequencyStatus publish_frequency_;

  ros::Time start_time_;            ///< simulated time 0
  ros::Time anchor_time_;           ///< stamps are anchor_time_ + (clock steps − anchor_clock_steps_)·dt
  std::int64_t anchor_clock_steps_ = 0;
  ros::Time last_now_;              ///< the latest time seen, to detect backward jumps
  bool started_ = false;
  std::int64_t published_clock_steps_ = -1;  ///< the clock step of the last publication
  std::uint64_t reported_problems_ = 0;      ///< rejections, drops and overruns at the last diagnostics
  ros::Time last_wrench_time_;               ///< the latest wrench on any body, for the diagnostics
  /// Every body's transform, sent as one tf message per tick (frame ids filled once).
  std::vector<geometry_msgs::TransformStamped> transforms_;
};

}  // namespace rigid_body_ros
