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
}  // namespace

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const NodeConfig& config)
    : config_(config),
      simulation_(config.model, config.initial, config.integrator, config.dt, config.max_substeps,
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
  odom_publisher_ = nh_.advertise<nav_msgs::Odometry>("odom", queue);
  state_publisher_ = nh_.advertise<rigid_body_sim::RigidBodyState>("state", queue);
  wrench_subscriber_ = nh_.subscribe("wrench", 10, &SimulatorNode::onWrench, this);
  reset_service_ = nh_.advertiseService("reset", &SimulatorNode::onReset, this);
  wrench_unstamped_subscriber_ = nh_.subscribe("wrench_unstamped", 10, &SimulatorNode::onWrenchUnstamped, this);
  applied_wrench_publisher_ = nh_.advertise<geometry_msgs::WrenchStamped>("applied_wrench", queue);
  control_services_ = {
      nh_.advertiseService("reset_time", &SimulatorNode::onResetTime, this),
      nh_.advertiseService("pause", &SimulatorNode::onPause, this),
      nh_.advertiseService("unpause", &SimulatorNode::onUnpause, this),
      nh_.advertiseService("step", &SimulatorNode::onStep, this),
      nh_.advertiseService("apply_wrench", &SimulatorNode::onApplyWrench, this),
      nh_.advertiseService("clear_wrenches", &SimulatorNode::onClearWrenches, this),
      nh_.advertiseService("set_state", &SimulatorNode::onSetState, this),
      nh_.advertiseService("get_state", &SimulatorNode::onGetState, this),
  };
  if (config_.lockstep) clock_publisher_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  if (config_.noise.enabled()) {
    odom_noisy_publisher_ = nh_.advertise<nav_msgs::Odometry>("odom_noisy", queue);
    noise_generator_.seed(static_cast<std::uint64_t>(config_.noise.seed));
  }
  simulation_.setPaused(config_.start_paused);
  applied_wrench_message_.header.frame_id = config_.world_frame;

  diagnostics_.setHardwareID(ros::this_node::getName());
  diagnostics_.add(publish_frequency_);
  diagnostics_.add("rigid body " + config_.body_frame, this, &SimulatorNode::diagnose);

  // Ground truth: the covariances stay zero.
  odom_message_.header.frame_id = config_.world_frame;
  odom_message_.child_frame_id = config_.body_frame;
  transform_message_.header.frame_id = config_.world_frame;
  transform_message_.child_frame_id = config_.body_frame;
  state_message_.header.frame_id = config_.world_frame;
  state_message_.child_frame_id = config_.body_frame;
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
  if (!config_.mesh_path.empty()) {
    const Eigen::Vector3d& c = config_.X_MB.translation();
    const Eigen::Quaterniond q_MB(config_.X_MB.linear());
    ROS_INFO("rigid_body_node: body frame %s = mesh frame moved to the centre of mass (%g, %g, %g) m and turned by "
             "q = [%g, %g, %g, %g] (x, y, z, w)%s",
             config_.body_frame.c_str(), c.x(), c.y(), c.z(), q_MB.x(), q_MB.y(), q_MB.z(), q_MB.w(),
             config_.mesh_frame.empty() ? "" : ("; published as tf " + config_.body_frame + " -> " + config_.mesh_frame).c_str());
    for (const std::string& warning : config_.mesh_warnings) ROS_WARN("rigid_body_node: %s", warning.c_str());
  }
  if (!config_.mesh_frame.empty()) {
    // The mesh's own frame relative to the body frame, X_BM = X_MB⁻¹, so visuals can hang on it.
    mesh_frame_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
    geometry_msgs::TransformStamped X_BM = tf2::eigenToTransform(Eigen::Affine3d(config_.X_MB.inverse().matrix()));
    X_BM.header.stamp = start_time;
    X_BM.header.frame_id = config_.body_frame;
    X_BM.child_frame_id = config_.mesh_frame;
    mesh_frame_broadcaster_->sendTransform(X_BM);
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
    for (const TimedWrench& timed : timed_wrenches_) {
      if (timed.start > k) next = std::min(next, timed.start);
      if (timed.end > k) next = std::min(next, timed.end);
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
      ROS_ERROR("rigid_body_node: the simulation diverged (%s); publishing the last good state until ~reset",
                rigid_body::divergenceName(simulation_.divergence()));
    }
  }
  const std::int64_t k = simulation_.clockSteps();
  timed_wrenches_.erase(std::remove_if(timed_wrenches_.begin(), timed_wrenches_.end(),
                                       [k](const TimedWrench& timed) { return timed.end >= 0 && timed.end <= k; }),
                        timed_wrenches_.end());
  refreshInput();
}

void SimulatorNode::refreshInput() { simulation_.setInput(inputAtStep(simulation_.clockSteps())); }

rigid_body::AppliedWrench SimulatorNode::inputAtStep(std::int64_t k) const {
  rigid_body::AppliedWrench input = topic_input_;
  for (const TimedWrench& timed : timed_wrenches_) {
    if (timed.start <= k && (timed.end < 0 || k < timed.end)) input += timed.wrench;
  }
  return input;
}

ros::Time SimulatorNode::now() const {
  return config_.lockstep ? stampOf(simulation_.clockSteps()) : ros::Time::now();
}

void SimulatorNode::expireWrench(const ros::Time& now) {
  if (!wrench_active_ || config_.wrench_timeout <= 0.0) return;
  const ros::Time expiry = last_wrench_time_ + ros::Duration(config_.wrench_timeout);
  if (now < expiry) return;
  advanceTo(expiry);  // the wrench acts up to its expiry, not up to this tick
  topic_input_ = rigid_body::AppliedWrench();
  refreshInput();
  wrench_active_ = false;
  wrench_timed_out_ = true;
  ++counters_.wrench_timeouts;
  ROS_INFO("rigid_body_node: no wrench for %.3f s (wrench_timeout): applied wrench set to zero",
           config_.wrench_timeout);
}

void SimulatorNode::update(const ros::Time& now) {
  expireWrench(now);
  advanceTo(now);
  if (simulation_.clockSteps() > published_clock_steps_) publish();
  diagnostics_.update();  // rate-limited by diagnostic_updater itself (~diagnostic_period, 1 s)
}

void SimulatorNode::publish() {
  published_clock_steps_ = simulation_.clockSteps();
  const ros::Time stamp = stampOf(published_clock_steps_);
  const rigid_body::State& state = simulation_.state();
  max_norm_error_ = std::max(max_norm_error_, std::abs(rigid_body::quaternionNormError(state)));
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
  applied_wrench_message_.header.stamp = stamp;
  applied_wrench_message_.wrench = state_message_.applied_wrench;  // world axes about the centre of mass
  applied_wrench_publisher_.publish(applied_wrench_message_);
  publishNoisy(stamp);
  publish_frequency_.tick();
}

void SimulatorNode::publishNoisy(const ros::Time& stamp) {
  if (!config_.noise.enabled()) return;
  const NoiseConfig& noise = config_.noise;
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto draw = [&](const Eigen::Vector3d& stddev) {
    return Eigen::Vector3d(stddev.x() * normal(noise_generator_), stddev.y() * normal(noise_generator_),
                           stddev.z() * normal(noise_generator_));
  };
  nav_msgs::Odometry noisy = odom_message_;
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
  delayed_noisy_.push_back(noisy);
  while (!delayed_noisy_.empty() && delayed_noisy_.front().header.stamp + ros::Duration(noise.delay) <= stamp) {
    odom_noisy_publisher_.publish(delayed_noisy_.front());
    delayed_noisy_.pop_front();
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
    expireWrench(now());
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

bool SimulatorNode::toAppliedWrench(const geometry_msgs::Wrench& wrench, const std::string& frame,
                                    const ros::Time& stamp, const Eigen::Vector3d* point,
                                    rigid_body::AppliedWrench& out) {
  rigid_body::Wrench given = toWrench(wrench);
  switch (classifyWrenchFrame(frame, config_.world_frame, config_.body_frame)) {
    case WrenchFrame::kBody:
      // Body axes about the centre of mass (the body frame's origin): turns with the body.
      if (point) given.torque += point->cross(given.force);
      out.body = given;
      return true;
    case WrenchFrame::kWorld:
      // About the centre of mass unless a point is given (world axes: the transform is the identity).
      out.world = point ? wrenchInWorld(wrench, Eigen::Isometry3d::Identity(), simulation_.state().p_WB, point) : given;
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
  out.world = wrenchInWorld(wrench, tf2::transformToEigen(X_WF), simulation_.state().p_WB, point);
  return true;
}

void SimulatorNode::setTopicWrench(const rigid_body::AppliedWrench& input, const ros::Time& now) {
  topic_input_ = input;
  refreshInput();
  ++counters_.wrenches_applied;
  wrench_active_ = true;
  wrench_timed_out_ = false;
  last_wrench_time_ = now;
}

void SimulatorNode::onWrench(const geometry_msgs::WrenchStamped::ConstPtr& message) {
  if (!acceptWrench(message->wrench)) return;
  // The wrench acts from its arrival; its stamp only chooses the transform of a foreign frame (a stamp far
  // in the past or the future, as `rostopic pub` gives under sim time, neither delays nor drops it).
  const ros::Time arrival = now();
  advanceTo(arrival);  // integrate up to the arrival first: the new wrench acts from the step at its arrival
  rigid_body::AppliedWrench input;
  if (!toAppliedWrench(message->wrench, message->header.frame_id, message->header.stamp, nullptr, input)) return;
  setTopicWrench(input, arrival);
}

void SimulatorNode::onWrenchUnstamped(const geometry_msgs::Wrench::ConstPtr& message) {
  if (!acceptWrench(*message)) return;
  const ros::Time arrival = now();
  advanceTo(arrival);
  rigid_body::AppliedWrench input;
  input.world = toWrench(*message);
  setTopicWrench(input, arrival);
}

void SimulatorNode::resetBody() {
  simulation_.reset();
  topic_input_ = rigid_body::AppliedWrench();
  timed_wrenches_.clear();
  wrench_active_ = false;
  max_norm_error_ = 0.0;
}

bool SimulatorNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(now());
  resetBody();
  ROS_INFO("rigid_body_node: reset to the initial state, wrenches cleared");
  return true;
}

bool SimulatorNode::onResetTime(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  if (!config_.lockstep) {
    response.success = false;
    response.message = "reset_time rewinds simulated time, which only a lockstep node owns; use reset";
    return true;
  }
  resetBody();
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
  response.success = simulation_.divergence() == rigid_body::Divergence::kNone;
  response.message = response.success ? "" : rigid_body::divergenceName(simulation_.divergence());
  response.sim_time = stampOf(simulation_.clockSteps()).toSec();
  response.total_steps = simulation_.integratedSteps();
  return true;
}

bool SimulatorNode::onApplyWrench(rigid_body_sim::ApplyWrench::Request& request,
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
      !toAppliedWrench(request.wrench, request.frame_id, request.start_time, request.use_point ? &point : nullptr,
                       timed.wrench)) {
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
  timed_wrenches_.push_back(timed);
  refreshInput();
  response.success = true;
  response.message = "acting from step " + std::to_string(timed.start) +
                     (timed.end < 0 ? " until clear_wrenches" : " to step " + std::to_string(timed.end));
  return true;
}

bool SimulatorNode::onClearWrenches(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(now());
  timed_wrenches_.clear();
  topic_input_ = rigid_body::AppliedWrench();
  wrench_active_ = false;
  refreshInput();
  return true;
}

bool SimulatorNode::onSetState(rigid_body_sim::SetState::Request& request, rigid_body_sim::SetState::Response& response) {
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
  rigid_body::State state = rigid_body::stateFromVelocities(simulation_.model().mass, p, q, v_W, w_B);
  state.t = simulation_.state().t;
  response.success = simulation_.setState(state);
  response.message = response.success ? "" : "refused: the state is not finite";
  return true;
}

bool SimulatorNode::onGetState(rigid_body_sim::GetState::Request&, rigid_body_sim::GetState::Response& response) {
  advanceTo(now());
  const rigid_body::State& state = simulation_.state();
  const rigid_body::Motion motion = rigid_body::motionOf(simulation_.model().mass, state);
  response.stamp = stampOf(simulation_.clockSteps());
  response.pose.position = tf2::toMsg(state.p_WB);
  response.pose.orientation = tf2::toMsg(state.q_WB);
  tf2::toMsg(motion.v_WB_W, response.twist_world.linear);
  tf2::toMsg(motion.w_WB_W, response.twist_world.angular);
  tf2::toMsg(Eigen::Vector3d(motion.R_WB.transpose() * motion.v_WB_W), response.twist_body.linear);
  tf2::toMsg(Eigen::Vector3d(motion.R_WB.transpose() * motion.w_WB_W), response.twist_body.angular);
  response.total_steps = simulation_.integratedSteps();
  response.paused = simulation_.paused();
  return true;
}

void SimulatorNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const rigid_body::Simulation& sim = simulation_;
  const rigid_body::Model& model = sim.model();
  const std::uint64_t problems = counters_.rejected() + counters_.dropped_steps + counters_.timer_overruns;
  if (sim.divergence() != rigid_body::Divergence::kNone) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                    "diverged (%s): publishing the last good state; call reset",
                    rigid_body::divergenceName(sim.divergence()));
  } else if (problems > reported_problems_) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "inputs rejected, steps dropped or timer overruns since the last report");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  reported_problems_ = problems;

  const rigid_body::State& state = sim.state();
  const rigid_body::State& initial = sim.initialState();
  const auto energy = [&](const rigid_body::State& s) {
    return rigid_body::kineticEnergy(model.mass, s) + rigid_body::potentialEnergy(model.mass, model.forces, s);
  };
  status.add("integrator", rigid_body::integratorName(sim.integratorType()));
  status.add("dt [s]", config_.dt);
  status.add("divergence", rigid_body::divergenceName(sim.divergence()));
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
  status.add("wrench timed out", wrench_timed_out_ ? "true" : "false");
  status.add("energy change since reset [J]", energy(state) - energy(initial));
  status.add("|L| change since reset [kg m^2/s]", state.L_W.norm() - initial.L_W.norm());
  status.add("max ||q| - 1| since reset", max_norm_error_);
}

}  // namespace rigid_body_ros
