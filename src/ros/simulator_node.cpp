#include "rigid_body_sim/ros/simulator_node.hpp"

#include <rosgraph_msgs/Clock.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/conversions.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace rigid_body_ros {

namespace {
// Warnings about bad input repeat at most this often [s], however fast the input comes.
constexpr double kWarningPeriod = 2.0;
// How long a wrench in a foreign frame may wait for tf2 to know the frame at its stamp [s]. It is short:
// the subscriber runs on the single spinner thread.
constexpr double kTransformTimeout = 0.01;
// The publish-rate status accepts ±10 % of the configured rate over a window of 10 ticks.
constexpr double kFrequencyTolerance = 0.1;
constexpr int kFrequencyWindow = 10;
// set_state accepts a quaternion whose norm is 1 within this, then normalises it.
constexpr double kUnitQuaternionTolerance = 1e-6;

rigid_body::AppliedWrench& operator+=(rigid_body::AppliedWrench& sum, const rigid_body::AppliedWrench& add) {
  sum.world += add.world;
  sum.body += add.body;
  return sum;
}

std::vector<rigid_body::BodyDefinition> bodyDefinitions(const NodeConfig& config) {
  std::vector<rigid_body::BodyDefinition> bodies;
  for (const BodyConfig& body : config.bodies) bodies.push_back({body.model, body.initial, body.wrench_input});
  return bodies;
}

}  // namespace

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const NodeConfig& config)
    : config_(config),
      simulation_(bodyDefinitions(config), config.integrator, config.dt, config.max_substeps,
                  config.integrator_settings),
      nh_(nh),
      tf_listener_(tf_buffer_),
      diagnostics_(nh, private_nh),
      min_frequency_(config.rate),
      max_frequency_(config.rate),
      publish_frequency_(diagnostic_updater::FrequencyStatusParam(&min_frequency_, &max_frequency_,
                                                                  kFrequencyTolerance, kFrequencyWindow)) {
  simulation_.setMaxEnergyGrowth(config.max_energy_growth);
  // In lockstep at full speed the outputs come in bursts: a deeper queue lets subscribers keep up longer
  // (a subscriber slower than the simulation still misses messages; set real_time_factor then).
  const uint32_t queue = config_.lockstep ? 100 : 10;
  bodies_.resize(config_.bodies.size());
  for (std::size_t body = 0; body < bodies_.size(); ++body) createBodyChannel(body, queue);
  reset_service_ = nh_.advertiseService("reset", &SimulatorNode::onReset, this);
  control_services_ = {
      nh_.advertiseService("reset_time", &SimulatorNode::onResetTime, this),
      nh_.advertiseService("pause", &SimulatorNode::onPause, this),
      nh_.advertiseService("unpause", &SimulatorNode::onUnpause, this),
      nh_.advertiseService("step", &SimulatorNode::onStep, this),
      nh_.advertiseService("clear_wrenches", &SimulatorNode::onClearWrenches, this),
  };
  if (config_.lockstep) clock_publisher_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  simulation_.setPaused(config_.start_paused);

  diagnostics_.setHardwareID(ros::this_node::getName());
  diagnostics_.add(publish_frequency_);
  diagnostics_.add(bodies_.size() == 1 ? "rigid body " + config_.bodies[0].body_frame
                                       : "rigid body scene (" + std::to_string(bodies_.size()) + " bodies)",
                   this, &SimulatorNode::diagnose);
}

void SimulatorNode::createBodyChannel(std::size_t body, uint32_t queue) {
  BodyChannel& channel = bodies_[body];
  const BodyConfig& config = config_.bodies[body];
  // Ground truth: the covariances stay zero.
  channel.odom_message.header.frame_id = config_.world_frame;
  channel.odom_message.child_frame_id = config.body_frame;
  channel.state_message.header.frame_id = config_.world_frame;
  channel.state_message.child_frame_id = config.body_frame;
  channel.applied_wrench_message.header.frame_id = config_.world_frame;
  // Counts a publisher's subscribers in `count` (bodies_ is sized once, so the channel stays where it is).
  const auto advertise = [&](auto message, const std::string& topic, int BodyChannel::*count) {
    const ros::SubscriberStatusCallback connected = [this, body, count](const ros::SingleSubscriberPublisher&) {
      ++(bodies_[body].*count);
    };
    const ros::SubscriberStatusCallback disconnected = [this, body, count](const ros::SingleSubscriberPublisher&) {
      --(bodies_[body].*count);
    };
    return nh_.advertise<decltype(message)>(config.topic(topic), queue, connected, disconnected);
  };
  if (config_.publish.odom) {
    channel.odom_publisher = advertise(nav_msgs::Odometry(), "odom", &BodyChannel::odom_subscribers);
  }
  if (config_.publish.state) {
    channel.state_publisher = advertise(rigid_body_sim::RigidBodyState(), "state", &BodyChannel::state_subscribers);
  }
  if (config_.publish.applied_wrench) {
    channel.applied_wrench_publisher = advertise(geometry_msgs::WrenchStamped(), "applied_wrench",
                                                 &BodyChannel::applied_wrench_subscribers);
  }
  if (config_.noise.enabled()) {
    channel.odom_noisy_publisher = nh_.advertise<nav_msgs::Odometry>(config.topic("odom_noisy"), queue);
    channel.noise_generator.seed(static_cast<std::uint64_t>(config_.noise.seed) + body);  // one stream per body
  }
  channel.services.push_back(nh_.advertiseService<rigid_body_sim::GetState::Request, rigid_body_sim::GetState::Response>(
      config.topic("get_state"), [this, body](auto& request, auto& response) { return onGetState(body, request, response); }));
  channel.services.push_back(nh_.advertiseService<rigid_body_sim::SetState::Request, rigid_body_sim::SetState::Response>(
      config.topic("set_state"), [this, body](auto& request, auto& response) { return onSetState(body, request, response); }));
  if (!config.wrench_input) return;  // no input term: no subscriber, no apply_wrench
  channel.wrench_subscribers.push_back(nh_.subscribe<geometry_msgs::WrenchStamped>(
      config.topic("wrench"), 10, [this, body](const geometry_msgs::WrenchStamped::ConstPtr& m) { onWrench(body, m); }));
  channel.wrench_subscribers.push_back(nh_.subscribe<geometry_msgs::Wrench>(
      config.topic("wrench_unstamped"), 10,
      [this, body](const geometry_msgs::Wrench::ConstPtr& m) { onWrenchUnstamped(body, m); }));
  channel.services.push_back(
      nh_.advertiseService<rigid_body_sim::ApplyWrench::Request, rigid_body_sim::ApplyWrench::Response>(
          config.topic("apply_wrench"),
          [this, body](auto& request, auto& response) { return onApplyWrench(body, request, response); }));
}

void SimulatorNode::start(const ros::Time& start_time) {
  start_time_ = anchor_time_ = last_now_ = start_time;
  started_ = true;
  const double period = 1.0 / config_.rate;
  if (!config_.lockstep) {
    timer_ = nh_.createTimer(ros::Duration(period), [this, period](const ros::TimerEvent&) {
      const ros::WallTime begin = ros::WallTime::now();
      update(ros::Time::now());
      if ((ros::WallTime::now() - begin).toSec() > period) ++counters_.timer_overruns;
    });
  }
  ROS_INFO("rigid_body_node: %s", config_.describe().c_str());
  std::vector<geometry_msgs::TransformStamped> mesh_frames;
  for (std::size_t body = 0; body < bodies_.size(); ++body) {
    const BodyConfig& config = config_.bodies[body];
    // Once, at start-up: what this body's step evaluates (the rest of Ẏ is left out: see StepTerms).
    ROS_INFO("rigid_body_node: body %s (%s): step assembled from %s", config.name.empty() ? "(flat)" : config.name.c_str(),
             config.body_frame.c_str(), rigid_body::describeTerms(simulation_.terms(body)).c_str());
    if (config_.publish.tf) {
      geometry_msgs::TransformStamped transform;
      transform.header.frame_id = config_.world_frame;
      transform.child_frame_id = config.body_frame;
      transforms_.push_back(transform);
    }
    if (config.mesh_path.empty()) continue;
    const Eigen::Vector3d& c = config.X_MB.translation();
    const Eigen::Quaterniond q_MB(config.X_MB.linear());
    ROS_INFO("rigid_body_node: body frame %s = mesh frame moved to the centre of mass (%g, %g, %g) m and turned by "
             "q = [%g, %g, %g, %g] (x, y, z, w)%s",
             config.body_frame.c_str(), c.x(), c.y(), c.z(), q_MB.x(), q_MB.y(), q_MB.z(), q_MB.w(),
             config.mesh_frame.empty() ? "" : ("; published as tf " + config.body_frame + " -> " + config.mesh_frame).c_str());
    for (const std::string& warning : config.mesh_warnings) ROS_WARN("rigid_body_node: %s", warning.c_str());
    if (config.mesh_frame.empty()) continue;
    // The mesh's own frame relative to the body frame, X_BM = X_MB⁻¹, so visuals can hang on it.
    geometry_msgs::TransformStamped X_BM = tf2::eigenToTransform(Eigen::Affine3d(config.X_MB.inverse().matrix()));
    X_BM.header.stamp = start_time;
    X_BM.header.frame_id = config.body_frame;
    X_BM.child_frame_id = config.mesh_frame;
    mesh_frames.push_back(X_BM);
  }
  if (!mesh_frames.empty()) {
    mesh_frame_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
    mesh_frame_broadcaster_->sendTransform(mesh_frames);
  }
}

ros::Time SimulatorNode::stampOf(std::int64_t clock_steps) const {
  return anchor_time_ + ros::Duration(static_cast<double>(clock_steps - anchor_clock_steps_) * config_.dt);
}

void SimulatorNode::advanceTo(const ros::Time& now) {
  // In lockstep the clock is ours and moves only by steps (runLockstep, step): nothing is ever "due".
  if (!started_ || config_.lockstep) return;
  // ROS time went back (rosbag play --loop, a restarted /clock). A step back of less than one tick period is
  // clock jitter: it is waited out (no step is due until time passes the last grid point again). A larger
  // one re-anchors: the body keeps its state and the stamps follow the new time from here.
  if (now < last_now_) {
    const double back = (last_now_ - now).toSec();
    if (back > 1.0 / config_.rate) {
      ++counters_.backward_time_jumps;
      ROS_WARN("rigid_body_node: ROS time jumped back by %.3f s; re-anchoring the simulation clock at %.3f", back,
               now.toSec());
      simulation_.reanchor((now - start_time_).toSec());
      anchor_time_ = now;
      anchor_clock_steps_ = simulation_.clockSteps();
      published_clock_steps_ = simulation_.clockSteps() - 1;  // publish the current state at the new time
      last_now_ = now;
      // diagnostic_updater schedules its next report at a ROS time that is now far ahead: report now, which
      // also reschedules it from the new time.
      diagnostics_.force_update();
    }
    return;
  }
  last_now_ = now;
  advanceToStep(simulation_.clockStepsAt((now - start_time_).toSec()));
}

void SimulatorNode::advanceToStep(std::int64_t target) {
  while (simulation_.clockSteps() < target) {
    const std::int64_t k = simulation_.clockSteps();
    std::int64_t next = target;  // the next step at which a service wrench starts or ends
    for (const BodyChannel& channel : bodies_) {
      for (const TimedWrench& timed : channel.timed_wrenches) {
        if (timed.start > k) next = std::min(next, timed.start);
        if (timed.end > k) next = std::min(next, timed.end);
      }
    }
    refreshInput();
    const rigid_body::AdvanceResult result = simulation_.advanceToStep(next);
    counters_.last_substeps = result.steps;
    counters_.max_substeps_seen = std::max(counters_.max_substeps_seen, result.steps);
    counters_.dropped_steps += static_cast<std::uint64_t>(result.dropped);
    if (result.dropped > 0) {
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: %ld steps due in one tick exceed max_substeps = %ld; %ld dropped",
                        static_cast<long>(result.steps + result.dropped), static_cast<long>(config_.max_substeps),
                        static_cast<long>(result.dropped));
    }
    if (result.diverged) {
      for (std::size_t body = 0; body < bodies_.size(); ++body) {
        if (simulation_.divergence(body) == rigid_body::Divergence::kNone) continue;
        ROS_ERROR_THROTTLE(kWarningPeriod,
                           "rigid_body_node: body %s diverged (%s); publishing its last good state until ~reset",
                           config_.bodies[body].body_frame.c_str(),
                           rigid_body::divergenceName(simulation_.divergence(body)));
      }
    }
  }
  const std::int64_t k = simulation_.clockSteps();
  for (BodyChannel& channel : bodies_) {
    std::vector<TimedWrench>& timed = channel.timed_wrenches;
    timed.erase(std::remove_if(timed.begin(), timed.end(),
                               [k](const TimedWrench& t) { return t.end >= 0 && t.end <= k; }),
                timed.end());
  }
  refreshInput();
}

void SimulatorNode::refreshInput() {
  for (std::size_t body = 0; body < bodies_.size(); ++body) refreshInput(body);
}

void SimulatorNode::refreshInput(std::size_t body) {
  if (config_.bodies[body].wrench_input) simulation_.setInput(body, inputAtStep(bodies_[body], simulation_.clockSteps()));
}

std::size_t SimulatorNode::firstDivergedBody() const {
  std::size_t body = 0;
  while (body < bodies_.size() && simulation_.divergence(body) == rigid_body::Divergence::kNone) ++body;
  return body;
}

rigid_body::AppliedWrench SimulatorNode::inputAtStep(const BodyChannel& channel, std::int64_t k) const {
  rigid_body::AppliedWrench input = channel.topic_input;
  for (const TimedWrench& timed : channel.timed_wrenches) {
    if (timed.start <= k && (timed.end < 0 || k < timed.end)) input += timed.wrench;
  }
  return input;
}

ros::Time SimulatorNode::now() const {
  return config_.lockstep ? stampOf(simulation_.clockSteps()) : ros::Time::now();
}

void SimulatorNode::expireWrenches(const ros::Time& now) {
  if (config_.wrench_timeout <= 0.0) return;
  const ros::Duration timeout(config_.wrench_timeout);
  // In the order of expiry, so that each wrench acts exactly up to its own.
  for (;;) {
    std::size_t first = bodies_.size();
    for (std::size_t body = 0; body < bodies_.size(); ++body) {
      const BodyChannel& channel = bodies_[body];
      if (channel.wrench_active && channel.last_wrench_time + timeout <= now &&
          (first == bodies_.size() || channel.last_wrench_time < bodies_[first].last_wrench_time)) {
        first = body;
      }
    }
    if (first == bodies_.size()) return;
    BodyChannel& channel = bodies_[first];
    advanceTo(channel.last_wrench_time + timeout);  // the wrench acts up to its expiry, not up to this tick
    channel.topic_input = rigid_body::AppliedWrench();
    refreshInput(first);
    channel.wrench_active = false;
    channel.wrench_timed_out = true;
    ++counters_.wrench_timeouts;
    ROS_INFO("rigid_body_node: %s: no wrench for %.3f s (wrench_timeout): applied wrench set to zero",
             config_.bodies[first].body_frame.c_str(), config_.wrench_timeout);
  }
}

void SimulatorNode::update(const ros::Time& now) {
  expireWrenches(now);
  advanceTo(now);
  if (simulation_.clockSteps() > published_clock_steps_) publish();
  diagnostics_.update();  // rate-limited by diagnostic_updater itself (~diagnostic_period, 1 s)
}

void SimulatorNode::publish() {
  published_clock_steps_ = simulation_.clockSteps();
  const ros::Time stamp = stampOf(published_clock_steps_);
  for (std::size_t body = 0; body < bodies_.size(); ++body) {
    BodyChannel& channel = bodies_[body];
    const rigid_body::State& state = simulation_.state(body);
    channel.max_norm_error = std::max(channel.max_norm_error, std::abs(rigid_body::quaternionNormError(state)));
    if (config_.publish.tf) {
      transforms_[body].header.stamp = stamp;
      fillTransform(state, transforms_[body]);
    }
    const bool odom = channel.odom_subscribers > 0;
    if (odom || config_.noise.enabled()) {
      channel.odom_message.header.stamp = stamp;
      fillOdometry(simulation_.model(body).mass, state, channel.odom_message);
      if (odom) channel.odom_publisher.publish(channel.odom_message);
    }
    const bool applied_wrench = channel.applied_wrench_subscribers > 0;
    if (channel.state_subscribers > 0 || applied_wrench) {
      channel.state_message.header.stamp = stamp;
      fillStateMessage(simulation_.model(body), state, simulation_.input(body), channel.state_message);
      if (channel.state_subscribers > 0) channel.state_publisher.publish(channel.state_message);
    }
    if (applied_wrench) {
      channel.applied_wrench_message.header.stamp = stamp;
      channel.applied_wrench_message.wrench = channel.state_message.applied_wrench;  // world axes, about the CoM
      channel.applied_wrench_publisher.publish(channel.applied_wrench_message);
    }
    publishNoisy(channel, stamp);
  }
  if (config_.publish.tf) tf_broadcaster_.sendTransform(transforms_);  // every body in one tf message
  publish_frequency_.tick();
}

void SimulatorNode::publishNoisy(BodyChannel& channel, const ros::Time& stamp) {
  if (!config_.noise.enabled()) return;
  const NoiseConfig& noise = config_.noise;
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto draw = [&](const Eigen::Vector3d& stddev) {
    return Eigen::Vector3d(stddev.x() * normal(channel.noise_generator), stddev.y() * normal(channel.noise_generator),
                           stddev.z() * normal(channel.noise_generator));
  };
  nav_msgs::Odometry noisy = channel.odom_message;
  Eigen::Vector3d p, v, w;
  Eigen::Quaterniond q;
  tf2::fromMsg(noisy.pose.pose.position, p);
  tf2::fromMsg(noisy.pose.pose.orientation, q);
  tf2::fromMsg(noisy.twist.twist.linear, v);
  tf2::fromMsg(noisy.twist.twist.angular, w);
  noisy.pose.pose.position = tf2::toMsg(Eigen::Vector3d(p + draw(noise.position_stddev)));
  noisy.pose.pose.orientation = tf2::toMsg(Eigen::Quaterniond(q * rigid_body::quaternionExp(draw(noise.orientation_stddev))));
  tf2::toMsg(Eigen::Vector3d(v + draw(noise.linear_velocity_stddev)), noisy.twist.twist.linear);
  tf2::toMsg(Eigen::Vector3d(w + draw(noise.angular_velocity_stddev)), noisy.twist.twist.angular);
  // Covariances consistent with the noise: diagonal variances, (x, y, z, rotation about x, y, z).
  for (int i = 0; i < 3; ++i) {
    noisy.pose.covariance[7 * i] = noise.position_stddev(i) * noise.position_stddev(i);
    noisy.pose.covariance[7 * (i + 3)] = noise.orientation_stddev(i) * noise.orientation_stddev(i);
    noisy.twist.covariance[7 * i] = noise.linear_velocity_stddev(i) * noise.linear_velocity_stddev(i);
    noisy.twist.covariance[7 * (i + 3)] = noise.angular_velocity_stddev(i) * noise.angular_velocity_stddev(i);
  }
  channel.delayed_noisy.push_back(noisy);
  while (!channel.delayed_noisy.empty() &&
         channel.delayed_noisy.front().header.stamp + ros::Duration(noise.delay) <= stamp) {
    channel.odom_noisy_publisher.publish(channel.delayed_noisy.front());
    channel.delayed_noisy.pop_front();
  }
}

void SimulatorNode::publishClock() {
  rosgraph_msgs::Clock clock;
  clock.clock = stampOf(simulation_.clockSteps());
  clock_publisher_.publish(clock);
}

void SimulatorNode::runLockstep() {
  const std::int64_t steps_per_publish = std::max<std::int64_t>(1, std::llround(1.0 / (config_.rate * config_.dt)));
  publishClock();
  ros::WallTime pace_start = ros::WallTime::now();
  std::int64_t pace_steps = simulation_.clockSteps();
  while (ros::ok()) {
    ros::spinOnce();  // wrenches and services act between two steps
    if (simulation_.paused()) {
      ros::WallDuration(0.001).sleep();
      pace_start = ros::WallTime::now();
      pace_steps = simulation_.clockSteps();
      continue;
    }
    expireWrenches(now());
    advanceToStep(simulation_.clockSteps() + 1);
    if (simulation_.clockSteps() % steps_per_publish == 0) {
      publishClock();
      publish();
      diagnostics_.update();
    }
    if (config_.real_time_factor > 0.0) {
      const double simulated = static_cast<double>(simulation_.clockSteps() - pace_steps) * config_.dt;
      const ros::WallTime due = pace_start + ros::WallDuration(simulated / config_.real_time_factor);
      const ros::WallDuration wait = due - ros::WallTime::now();
      if (wait > ros::WallDuration(0)) wait.sleep();
    }
  }
}

bool SimulatorNode::acceptWrench(const geometry_msgs::Wrench& wrench) {
  // The limits are on the magnitudes as sent (the same in any axes), before any change of frame.
  switch (rigid_body::checkWrench(toWrench(wrench), config_.wrench_limits)) {
    case rigid_body::WrenchVerdict::kAccepted:
      return true;
    case rigid_body::WrenchVerdict::kNonFinite:
      ++counters_.rejected_non_finite;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench with a non-finite component (%lu so far)",
                        static_cast<unsigned long>(counters_.rejected_non_finite));
      return false;
    case rigid_body::WrenchVerdict::kForceOverLimit:
      ++counters_.rejected_force_limit;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench: |force| above max_force = %g N (%lu so far)",
                        config_.wrench_limits.max_force, static_cast<unsigned long>(counters_.rejected_force_limit));
      return false;
    case rigid_body::WrenchVerdict::kTorqueOverLimit:
      ++counters_.rejected_torque_limit;
      ROS_WARN_THROTTLE(kWarningPeriod,
                        "rigid_body_node: rejected a wrench: |torque| above max_torque = %g N m (%lu so far)",
                        config_.wrench_limits.max_torque, static_cast<unsigned long>(counters_.rejected_torque_limit));
      return false;
  }
  return false;
}

bool SimulatorNode::toAppliedWrench(std::size_t body, const geometry_msgs::Wrench& wrench, const std::string& frame,
                                    const ros::Time& stamp, const Eigen::Vector3d* point,
                                    rigid_body::AppliedWrench& out) {
  rigid_body::Wrench given = toWrench(wrench);
  const Eigen::Vector3d& p_WB = simulation_.state(body).p_WB;
  switch (classifyWrenchFrame(frame, config_.world_frame, config_.bodies[body].body_frame)) {
    case WrenchFrame::kBody:
      // Body axes about the centre of mass (the body frame's origin): turns with the body.
      if (point) given.torque += point->cross(given.force);
      out.body = given;
      return true;
    case WrenchFrame::kWorld:
      // About the centre of mass unless a point is given (world axes: the transform is the identity).
      out.world = point ? wrenchInWorld(wrench, Eigen::Isometry3d::Identity(), p_WB, point) : given;
      return true;
    case WrenchFrame::kOther:
      break;
  }
  // At the stamp if tf2 knows it, else the latest transform; the result is held in world axes.
  geometry_msgs::TransformStamped X_WF;
  try {
    if (!stamp.isZero() && tf_buffer_.canTransform(config_.world_frame, frame, stamp, ros::Duration(kTransformTimeout))) {
      X_WF = tf_buffer_.lookupTransform(config_.world_frame, frame, stamp);
    } else {
      X_WF = tf_buffer_.lookupTransform(config_.world_frame, frame, ros::Time(0));
    }
  } catch (const tf2::TransformException& error) {
    ++counters_.rejected_unknown_frame;
    ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench in frame '%s': %s", frame.c_str(), error.what());
    return false;
  }
  out.world = wrenchInWorld(wrench, tf2::transformToEigen(X_WF), p_WB, point);
  return true;
}

void SimulatorNode::setTopicWrench(std::size_t body, const rigid_body::AppliedWrench& input, const ros::Time& now) {
  BodyChannel& channel = bodies_[body];
  channel.topic_input = input;
  refreshInput(body);
  ++counters_.wrenches_applied;
  channel.wrench_active = true;
  channel.wrench_timed_out = false;
  channel.last_wrench_time = last_wrench_time_ = now;
}

void SimulatorNode::onWrench(std::size_t body, const geometry_msgs::WrenchStamped::ConstPtr& message) {
  if (!acceptWrench(message->wrench)) return;
  // The wrench acts from its arrival; its stamp only chooses the transform of a foreign frame (a stamp far
  // in the past or the future, as `rostopic pub` gives under sim time, neither delays nor drops it).
  const ros::Time arrival = now();
  advanceTo(arrival);  // integrate up to the arrival first: the new wrench acts from the step at its arrival
  rigid_body::AppliedWrench input;
  if (!toAppliedWrench(body, message->wrench, message->header.frame_id, message->header.stamp, nullptr, input)) return;
  setTopicWrench(body, input, arrival);
}

void SimulatorNode::onWrenchUnstamped(std::size_t body, const geometry_msgs::Wrench::ConstPtr& message) {
  if (!acceptWrench(*message)) return;
  const ros::Time arrival = now();
  advanceTo(arrival);
  rigid_body::AppliedWrench input;
  input.world = toWrench(*message);
  setTopicWrench(body, input, arrival);
}

void SimulatorNode::resetBodies() {
  simulation_.reset();
  for (BodyChannel& channel : bodies_) {
    channel.topic_input = rigid_body::AppliedWrench();
    channel.timed_wrenches.clear();
    channel.wrench_active = false;
    channel.max_norm_error = 0.0;
  }
}

bool SimulatorNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(now());
  resetBodies();
  ROS_INFO("rigid_body_node: reset to the initial state, wrenches cleared");
  return true;
}

bool SimulatorNode::onResetTime(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  if (!config_.lockstep) {
    response.success = false;
    response.message = "reset_time rewinds simulated time, which only a lockstep node owns; use reset";
    return true;
  }
  resetBodies();
  simulation_.rewindClock();
  anchor_time_ = start_time_;
  anchor_clock_steps_ = 0;
  published_clock_steps_ = -1;
  publishClock();
  publish();
  response.success = true;
  response.message = "state and simulated time back to the start";
  ROS_INFO("rigid_body_node: reset_time: state and /clock back to the start");
  return true;
}

bool SimulatorNode::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(now());  // integrate up to the request, then hold
  simulation_.setPaused(true);
  return true;
}

bool SimulatorNode::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(now());  // the paused interval passes without motion
  simulation_.setPaused(false);
  return true;
}

bool SimulatorNode::onStep(rigid_body_sim::Step::Request& request, rigid_body_sim::Step::Response& response) {
  if (!simulation_.paused() || request.steps < 1) {
    response.success = false;
    response.message = request.steps < 1 ? "steps must be >= 1" : "call pause first: step advances a paused simulation";
    return true;
  }
  if (config_.lockstep) {
    // The clock is ours: it advances with the N steps, and the state is published at the new time.
    simulation_.setPaused(false);
    advanceToStep(simulation_.clockSteps() + request.steps);
    simulation_.setPaused(true);
    publishClock();
    publish();
  } else {
    // ROS time belongs to someone else: the body takes N steps now, the clock stays where it is.
    advanceTo(now());
    refreshInput();
    simulation_.stepNow(request.steps);
  }
  const std::size_t diverged = firstDivergedBody();
  response.success = diverged == bodies_.size();
  response.message = response.success ? ""
                                      : config_.bodies[diverged].body_frame + ": " +
                                            rigid_body::divergenceName(simulation_.divergence(diverged));
  response.sim_time = stampOf(simulation_.clockSteps()).toSec();
  response.total_steps = simulation_.integratedSteps();
  return true;
}

bool SimulatorNode::onApplyWrench(std::size_t body, rigid_body_sim::ApplyWrench::Request& request,
                                  rigid_body_sim::ApplyWrench::Response& response) {
  if (!acceptWrench(request.wrench)) {
    response.success = false;
    response.message = "wrench rejected: non-finite or above max_force / max_torque";
    return true;
  }
  const ros::Time current = now();
  advanceTo(current);
  Eigen::Vector3d point;
  tf2::fromMsg(request.point, point);
  TimedWrench timed;
  if (!point.allFinite() ||
      !toAppliedWrench(body, request.wrench, request.frame_id, request.start_time,
                       request.use_point ? &point : nullptr, timed.wrench)) {
    response.success = false;
    response.message = "frame '" + request.frame_id + "' cannot be resolved by tf2 (or the point is not finite)";
    return true;
  }
  // Start and end on the step grid: the wrench acts over whole steps, so its impulse is exact to one step.
  const std::int64_t k = simulation_.clockSteps();
  timed.start = request.start_time.isZero()
                    ? k
                    : std::max(k, simulation_.clockStepsAt((request.start_time - start_time_).toSec()));
  const double duration = request.duration.toSec();
  timed.end = duration < 0.0 ? -1
                             : timed.start + std::max<std::int64_t>(1, std::llround(duration / config_.dt));
  bodies_[body].timed_wrenches.push_back(timed);
  refreshInput(body);
  response.success = true;
  response.message = "acting from step " + std::to_string(timed.start) +
                     (timed.end < 0 ? " until clear_wrenches" : " to step " + std::to_string(timed.end));
  return true;
}

bool SimulatorNode::onClearWrenches(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(now());
  for (BodyChannel& channel : bodies_) {
    channel.timed_wrenches.clear();
    channel.topic_input = rigid_body::AppliedWrench();
    channel.wrench_active = false;
  }
  refreshInput();
  return true;
}

bool SimulatorNode::onSetState(std::size_t body, rigid_body_sim::SetState::Request& request,
                               rigid_body_sim::SetState::Response& response) {
  Eigen::Vector3d p, v, w;
  Eigen::Quaterniond q;
  tf2::fromMsg(request.pose.position, p);
  tf2::fromMsg(request.pose.orientation, q);
  tf2::fromMsg(request.twist.linear, v);
  tf2::fromMsg(request.twist.angular, w);
  response.success = false;
  if (!p.allFinite() || !q.coeffs().allFinite() || !v.allFinite() || !w.allFinite()) {
    response.message = "refused: a non-finite value in pose or twist";
    return true;
  }
  if (std::abs(q.norm() - 1.0) > kUnitQuaternionTolerance) {
    response.message = "refused: the orientation is not a unit quaternion (|q| = " + std::to_string(q.norm()) +
                       ", allowed 1 +- 1e-6)";
    return true;
  }
  const std::string& frame = request.twist_frame;
  if (!frame.empty() && frame != "body" && frame != "world") {
    response.message = "refused: twist_frame must be 'body' (or empty) or 'world', got '" + frame + "'";
    return true;
  }
  q.normalize();
  const bool world = frame == "world";
  const Eigen::Vector3d v_W = world ? v : Eigen::Vector3d(q * v);
  const Eigen::Vector3d w_B = world ? Eigen::Vector3d(q.conjugate() * w) : w;
  advanceTo(now());
  rigid_body::State state = rigid_body::stateFromVelocities(simulation_.model(body).mass, p, q, v_W, w_B);
  state.t = simulation_.state(body).t;
  response.success = simulation_.setState(body, state);
  response.message = response.success ? "" : "refused: the state is not finite";
  return true;
}

bool SimulatorNode::onGetState(std::size_t body, rigid_body_sim::GetState::Request&,
                               rigid_body_sim::GetState::Response& response) {
  advanceTo(now());
  const rigid_body::State& state = simulation_.state(body);
  const rigid_body::Motion motion = rigid_body::motionOf(simulation_.model(body).mass, state);
  response.stamp = stampOf(simulation_.clockSteps());
  response.pose.position = tf2::toMsg(state.p_WB);
  response.pose.orientation = tf2::toMsg(state.q_WB);
  tf2::toMsg(motion.v_WB_W, response.twist_world.linear);
  tf2::toMsg(motion.w_WB_W, response.twist_world.angular);
  tf2::toMsg(Eigen::Vector3d(motion.R_WB.transpose() * motion.v_WB_W), response.twist_body.linear);
  tf2::toMsg(Eigen::Vector3d(motion.R_WB.transpose() * motion.w_WB_W), response.twist_body.angular);
  response.total_steps = simulation_.integratedSteps(body);
  response.paused = simulation_.paused();
  return true;
}

void SimulatorNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const rigid_body::Simulation& sim = simulation_;
  const std::uint64_t problems = counters_.rejected() + counters_.dropped_steps + counters_.timer_overruns;
  std::size_t diverged = 0;
  for (std::size_t body = 0; body < bodies_.size(); ++body) diverged += sim.divergence(body) != rigid_body::Divergence::kNone;
  const std::size_t first_diverged = firstDivergedBody();
  // The reason of the first body that diverged ("none" while none has).
  const char* divergence = rigid_body::divergenceName(
      first_diverged < bodies_.size() ? sim.divergence(first_diverged) : rigid_body::Divergence::kNone);
  if (diverged > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                    "%zu of %zu bodies diverged (%s): publishing their last good state; call reset", diverged,
                    bodies_.size(), divergence);
  } else if (problems > reported_problems_) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "inputs rejected, steps dropped or timer overruns since the last report");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  reported_problems_ = problems;

  status.add("integrator", rigid_body::integratorName(sim.integratorType()));
  status.add("dt [s]", config_.dt);
  status.add("bodies", bodies_.size());
  status.add("divergence", divergence);
  status.add("substeps last tick", counters_.last_substeps);
  status.add("max substeps in one tick", counters_.max_substeps_seen);
  status.add("dropped steps", counters_.dropped_steps);
  status.add("timer overruns", counters_.timer_overruns);
  status.add("backward time jumps", counters_.backward_time_jumps);
  status.add("wrenches applied", counters_.wrenches_applied);
  status.add("rejected non_finite", counters_.rejected_non_finite);
  status.add("rejected force_over_limit", counters_.rejected_force_limit);
  status.add("rejected torque_over_limit", counters_.rejected_torque_limit);
  status.add("rejected unknown_frame", counters_.rejected_unknown_frame);
  if (counters_.wrenches_applied > 0) {
    status.add("time since last wrench [s]", (ros::Time::now() - last_wrench_time_).toSec());
  } else {
    status.add("time since last wrench [s]", "never");
  }
  const bool timed_out =
      std::any_of(bodies_.begin(), bodies_.end(), [](const BodyChannel& c) { return c.wrench_timed_out; });
  status.add("wrench timed out", timed_out ? "true" : "false");
  // Drift per body, keyed by the body frame when the scene has several.
  for (std::size_t body = 0; body < bodies_.size(); ++body) {
    const rigid_body::Model& model = sim.model(body);
    const rigid_body::State& state = sim.state(body);
    const rigid_body::State& initial = sim.initialState(body);
    const auto energy = [&](const rigid_body::State& s) {
      return rigid_body::kineticEnergy(model.mass, s) + rigid_body::potentialEnergy(model.mass, model.forces, s);
    };
    const std::string prefix = bodies_.size() == 1 ? "" : config_.bodies[body].body_frame + ": ";
    if (bodies_.size() > 1) status.add(prefix + "divergence", rigid_body::divergenceName(sim.divergence(body)));
    status.add(prefix + "step terms", rigid_body::describeTerms(sim.terms(body)));
    status.add(prefix + "energy change since reset [J]", energy(state) - energy(initial));
    status.add(prefix + "|L| change since reset [kg m^2/s]", state.L_W.norm() - initial.L_W.norm());
    status.add(prefix + "max ||q| - 1| since reset", bodies_[body].max_norm_error);
  }
}

}  // namespace rigid_body_ros
