#include "rigid_body_sim/ros/simulator_node.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include "rigid_body_sim/ros/conversions.hpp"

namespace rigid_body_ros {

namespace {
// Warnings about bad input repeat at most this often [s], however fast the input comes.
constexpr double kWarningPeriod = 2.0;
// How long a wrench in a foreign frame may wait for tf2 to know the frame at its stamp [s]. It is short:
// the subscriber runs on the single spinner thread.
constexpr double kTransformTimeout = 0.01;
}  // namespace

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const NodeConfig& config)
    : config_(config),
      simulation_(config.model, config.initial, config.integrator, config.dt, config.max_substeps,
                  config.integrator_settings),
      nh_(nh),
      tf_listener_(tf_buffer_) {
  odom_publisher_ = nh_.advertise<nav_msgs::Odometry>("odom", 10);
  state_publisher_ = nh_.advertise<rigid_body_sim::RigidBodyState>("state", 10);
  wrench_subscriber_ = nh_.subscribe("wrench", 10, &SimulatorNode::onWrench, this);
  reset_service_ = nh_.advertiseService("reset", &SimulatorNode::onReset, this);

  // Ground truth: the covariances stay zero.
  odom_message_.header.frame_id = config_.world_frame;
  odom_message_.child_frame_id = config_.body_frame;
  transform_message_.header.frame_id = config_.world_frame;
  transform_message_.child_frame_id = config_.body_frame;
  state_message_.header.frame_id = config_.world_frame;
  state_message_.child_frame_id = config_.body_frame;
}

void SimulatorNode::start(const ros::Time& start_time) {
  start_time_ = start_time;
  started_ = true;
  timer_ = nh_.createTimer(ros::Duration(1.0 / config_.rate), [this](const ros::TimerEvent&) { update(ros::Time::now()); });
  ROS_INFO("rigid_body_node: %s", config_.describe().c_str());
}

ros::Time SimulatorNode::stampOf(std::int64_t clock_steps) const {
  return start_time_ + ros::Duration(static_cast<double>(clock_steps) * config_.dt);
}

void SimulatorNode::advanceTo(const ros::Time& now) {
  if (!started_ || now <= start_time_) return;
  const rigid_body::AdvanceResult result = simulation_.advanceTo((now - start_time_).toSec());
  counters_.dropped_steps += static_cast<std::uint64_t>(result.dropped);
  if (result.dropped > 0) {
    ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: %ld steps due in one tick exceed max_substeps = %ld; %ld dropped",
                      static_cast<long>(result.steps + result.dropped), static_cast<long>(config_.max_substeps),
                      static_cast<long>(result.dropped));
  }
  if (result.status == rigid_body::StepStatus::kNonFinite) {
    ++counters_.failed_steps;
    ROS_ERROR_THROTTLE(kWarningPeriod,
                       "rigid_body_node: a step produced a non-finite state; keeping the last good state (call ~reset)");
  }
}

void SimulatorNode::expireWrench(const ros::Time& now) {
  if (!wrench_active_ || config_.wrench_timeout <= 0.0) return;
  const ros::Time expiry = last_wrench_time_ + ros::Duration(config_.wrench_timeout);
  if (now < expiry) return;
  advanceTo(expiry);  // the wrench acts up to its expiry, not up to this tick
  simulation_.clearInput();
  wrench_active_ = false;
  ++counters_.wrench_timeouts;
  ROS_INFO("rigid_body_node: no wrench for %.3f s (wrench_timeout): applied wrench set to zero",
           config_.wrench_timeout);
}

void SimulatorNode::update(const ros::Time& now) {
  expireWrench(now);
  advanceTo(now);
  if (simulation_.clockSteps() > published_clock_steps_) publish();
}

void SimulatorNode::publish() {
  published_clock_steps_ = simulation_.clockSteps();
  const ros::Time stamp = stampOf(published_clock_steps_);
  const rigid_body::State& state = simulation_.state();
  if (config_.publish_tf) {
    transform_message_.header.stamp = stamp;
    fillTransform(state, transform_message_);
    tf_broadcaster_.sendTransform(transform_message_);
  }
  odom_message_.header.stamp = stamp;
  fillOdometry(simulation_.model().mass, state, odom_message_);
  odom_publisher_.publish(odom_message_);
  state_message_.header.stamp = stamp;
  fillStateMessage(simulation_.model(), state, simulation_.input(), state_message_);
  state_publisher_.publish(state_message_);
}

void SimulatorNode::onWrench(const geometry_msgs::WrenchStamped::ConstPtr& message) {
  if (!isFinite(message->wrench)) {
    ++counters_.rejected_non_finite;
    ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench with a non-finite component (%lu so far)",
                      static_cast<unsigned long>(counters_.rejected_non_finite));
    return;
  }
  const ros::Time now = ros::Time::now();
  // Integrate up to the arrival first: the new wrench acts from the step at its arrival time.
  advanceTo(now);
  rigid_body::AppliedWrench input;
  const std::string& frame = message->header.frame_id;
  switch (classifyWrenchFrame(frame, config_.world_frame, config_.body_frame)) {
    case WrenchFrame::kBody:
      input.body = toWrench(message->wrench);
      break;
    case WrenchFrame::kWorld:
      input.world = toWrench(message->wrench);
      break;
    case WrenchFrame::kOther: {
      // At the message's stamp if tf2 knows it, else the latest transform; the result is held in world axes.
      geometry_msgs::TransformStamped X_WF;
      try {
        const ros::Time stamp = message->header.stamp;
        if (!stamp.isZero() && tf_buffer_.canTransform(config_.world_frame, frame, stamp, ros::Duration(kTransformTimeout))) {
          X_WF = tf_buffer_.lookupTransform(config_.world_frame, frame, stamp);
        } else {
          X_WF = tf_buffer_.lookupTransform(config_.world_frame, frame, ros::Time(0));
        }
      } catch (const tf2::TransformException& error) {
        ++counters_.rejected_unknown_frame;
        ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench in frame '%s': %s", frame.c_str(),
                          error.what());
        return;
      }
      input.world = wrenchInWorld(message->wrench, tf2::transformToEigen(X_WF), simulation_.state().p_WB);
      break;
    }
  }
  simulation_.setInput(input);
  ++counters_.wrenches_applied;
  wrench_active_ = true;
  last_wrench_time_ = now;
}

bool SimulatorNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(ros::Time::now());
  simulation_.reset();
  wrench_active_ = false;
  ROS_INFO("rigid_body_node: reset to the initial state, wrench cleared");
  return true;
}

}  // namespace rigid_body_ros
