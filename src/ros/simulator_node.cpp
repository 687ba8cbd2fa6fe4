#include "rigid_body_sim/ros/simulator_node.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/conversions.hpp"

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
  odom_publisher_ = nh_.advertise<nav_msgs::Odometry>("odom", 10);
  state_publisher_ = nh_.advertise<rigid_body_sim::RigidBodyState>("state", 10);
  wrench_subscriber_ = nh_.subscribe("wrench", 10, &SimulatorNode::onWrench, this);
  reset_service_ = nh_.advertiseService("reset", &SimulatorNode::onReset, this);

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
  timer_ = nh_.createTimer(ros::Duration(period), [this, period](const ros::TimerEvent&) {
    const ros::WallTime begin = ros::WallTime::now();
    update(ros::Time::now());
    if ((ros::WallTime::now() - begin).toSec() > period) ++counters_.timer_overruns;
  });
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
  if (!started_) return;
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
  const rigid_body::AdvanceResult result = simulation_.advanceTo((now - start_time_).toSec());
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

void SimulatorNode::expireWrench(const ros::Time& now) {
  if (!wrench_active_ || config_.wrench_timeout <= 0.0) return;
  const ros::Time expiry = last_wrench_time_ + ros::Duration(config_.wrench_timeout);
  if (now < expiry) return;
  advanceTo(expiry);  // the wrench acts up to its expiry, not up to this tick
  simulation_.clearInput();
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
  publish_frequency_.tick();
}

void SimulatorNode::onWrench(const geometry_msgs::WrenchStamped::ConstPtr& message) {
  // The limits are on the magnitudes as sent (the same in any axes), before any change of frame.
  const rigid_body::WrenchVerdict verdict = rigid_body::checkWrench(toWrench(message->wrench), config_.wrench_limits);
  switch (verdict) {
    case rigid_body::WrenchVerdict::kAccepted:
      break;
    case rigid_body::WrenchVerdict::kNonFinite:
      ++counters_.rejected_non_finite;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench with a non-finite component (%lu so far)",
                        static_cast<unsigned long>(counters_.rejected_non_finite));
      return;
    case rigid_body::WrenchVerdict::kForceOverLimit:
      ++counters_.rejected_force_limit;
      ROS_WARN_THROTTLE(kWarningPeriod, "rigid_body_node: rejected a wrench: |force| above max_force = %g N (%lu so far)",
                        config_.wrench_limits.max_force, static_cast<unsigned long>(counters_.rejected_force_limit));
      return;
    case rigid_body::WrenchVerdict::kTorqueOverLimit:
      ++counters_.rejected_torque_limit;
      ROS_WARN_THROTTLE(kWarningPeriod,
                        "rigid_body_node: rejected a wrench: |torque| above max_torque = %g N m (%lu so far)",
                        config_.wrench_limits.max_torque, static_cast<unsigned long>(counters_.rejected_torque_limit));
      return;
  }
  // The wrench acts from its arrival; its stamp only chooses the transform of a foreign frame (a stamp far
  // in the past or the future, as `rostopic pub` gives under sim time, neither delays nor drops it).
  const ros::Time now = ros::Time::now();
  advanceTo(now);  // integrate up to the arrival first: the new wrench acts from the step at its arrival
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
  wrench_timed_out_ = false;
  last_wrench_time_ = now;
}

bool SimulatorNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  advanceTo(ros::Time::now());
  simulation_.reset();
  wrench_active_ = false;
  max_norm_error_ = 0.0;
  ROS_INFO("rigid_body_node: reset to the initial state, wrench cleared");
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
