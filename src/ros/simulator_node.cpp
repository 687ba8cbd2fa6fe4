#include "rigid_body_sim/ros/simulator_node.hpp"

#include <algorithm>
#include <cmath>

#include "rigid_body_sim/integrators.hpp"
#include "rigid_body_sim/ros/body_properties.hpp"
#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

namespace {

// Warnings about the same thing repeat at most this often [s].
constexpr double kWarningPeriod = 2.0;
// Lockstep, paused: how long the driver sleeps between looks at its callbacks [s].
constexpr double kPausedPoll = 0.001;
// Lockstep pacing sleeps at most this long at a time [s], so a slow real_time_factor still answers shutdown.
constexpr double kPacingSlice = 0.1;

std::vector<rigid_body::BodyDefinition> bodyDefinitions(const NodeConfig& config) {
  std::vector<rigid_body::BodyDefinition> bodies;
  bodies.reserve(config.bodies.size());
  for (const BodyConfig& body : config.bodies) bodies.push_back({body.model, body.initial, body.wrench_input});
  return bodies;
}

}  // namespace

rigid_body::WorldSettings worldSettings(const NodeConfig& config) {
  rigid_body::WorldSettings settings;
  settings.dt = config.dt;
  settings.max_substeps = config.max_substeps;
  settings.max_body_steps_per_tick = config.max_body_steps_per_tick;
  settings.max_body_steps_per_request = config.max_body_steps_per_request;
  settings.max_request_seconds = config.max_request_seconds;
  settings.max_tick_seconds = config.max_tick_seconds;
  settings.threads = config.threads;
  settings.wrench_timeout = config.wrench_timeout;
  // ROS time going back by less than one tick period is clock jitter, waited out; more re-anchors the grid.
  settings.jitter_tolerance = rigid_body::toNanoseconds(1.0 / config.rate);
  // roscpp's timer and diagnostic_updater add their periods to ROS time and throw past 2^32 s: the clock
  // stops two timer periods and 10 s before that, and the node stops its timer there.
  settings.end_of_time = kEndOfRosTime - rigid_body::toNanoseconds(2.0 / config.rate + 10.0);
  settings.owns_clock = config.lockstep;
  settings.start_paused = config.start_paused;
  settings.max_energy_growth = config.max_energy_growth;
  return settings;
}

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const NodeConfig& config)
    : config_(config),
      nh_(nh),
      private_nh_(private_nh),
      world_(bodyDefinitions(config_), config_.integrator, config_.integrator_settings, worldSettings(config_),
             rigid_body::StepAssembly::kLeaveOut, config_.contactSetup()),
      wrench_input_(nh_, config_, world_, [this] { return now(); }, own_transforms_),
      outputs_(nh_, config_, own_transforms_),
      markers_(nh_, config_),
      imu_(nh_, config_),
      diagnostics_(nh_, private_nh_, config_, world_, wrench_input_, outputs_),
      services_(nh_, config_, world_, wrench_input_, [this] { return now(); },
                [this] {
                  outputs_.publishClock(world_);
                  publish();
                }),
      live_(private_nh_, config_, world_, outputs_, [this] { return now(); }) {
  advertiseEditServices();
}

void SimulatorNode::guarded(const std::function<void()>& tick) {
  // A tick must not take the node down: an exception from a library's own arithmetic (ros::Time, tf2,
  // diagnostic_updater) is logged and the next tick tries again. The core throws nothing in a tick.
  try {
    tick();
  } catch (const std::exception& error) {
    ROS_ERROR_THROTTLE(kWarningPeriod, "rigid_body_node: a tick failed: %s", error.what());
  }
}

rigid_body::Nanoseconds SimulatorNode::now() const {
  return config_.lockstep ? world_.stamp() : toNanoseconds(ros::Time::now());
}

void SimulatorNode::start(const ros::Time& start_time) {
  world_.start(toNanoseconds(start_time));
  // A colliding body's contacts are kept for its state (their count) and its contacts topic.
  world_.setRecordContacts(true);
  ROS_INFO("rigid_body_node: %s", config_.describe().c_str());
  for (std::size_t body = 0; body < config_.bodies.size(); ++body) logBody(body);
  publishStaticFrames(start_time);
  if (config_.lockstep) return;
  const double period = 1.0 / config_.rate;
  timer_ = nh_.createTimer(ros::Duration(period), [this, period](const ros::TimerEvent&) {
    const ros::WallTime begin = ros::WallTime::now();
    guarded([this] { update(ros::Time::now()); });
    if ((ros::WallTime::now() - begin).toSec() > period) diagnostics_.countOverrun();
  });
}

void SimulatorNode::publishStaticFrames(const ros::Time& stamp) {
  outputs_.publishStaticFrames(stamp, imu_.sensorFrames(stamp));
}

rigid_body::UpdateResult SimulatorNode::advance(rigid_body::Nanoseconds now) {
  const rigid_body::UpdateResult result = world_.update(now);
  report(result);
  return result;
}

void SimulatorNode::update(const ros::Time& now) {
  if (advance(toNanoseconds(now)).advanced) publish();
  diagnostics_.update();  // rate-limited by diagnostic_updater itself (~diagnostic_period, 1 s)
}

void SimulatorNode::publish() {
  // Outside lockstep /clock goes out with each publication, before the outputs it stamps (lockstep's driver
  // publishes its own, also after a step request).
  if (config_.publish.clock && !config_.lockstep) outputs_.publishClock(world_);
  outputs_.publish(world_);
  markers_.publish(world_);
  imu_.publish(world_);
  diagnostics_.tick(world_.stamp());
}

void SimulatorNode::report(const rigid_body::UpdateResult& result) {
  if (result.dropped > 0) {
    ROS_WARN_THROTTLE(kWarningPeriod,
                      "rigid_body_node: %ld steps due in one tick exceed the catch-up cap (max_substeps = %ld, "
                      "max_body_steps_per_tick = %ld); %ld passed without motion",
                      static_cast<long>(result.steps + result.dropped), static_cast<long>(config_.max_substeps),
                      static_cast<long>(config_.max_body_steps_per_tick), static_cast<long>(result.dropped));
  }
  if (result.diverged) {
    const rigid_body::Scene& scene = world_.scene();
    for (std::size_t body = 0; body < scene.bodyCount(); ++body) {
      if (scene.divergence(body) == rigid_body::Divergence::kNone) continue;
      ROS_ERROR_THROTTLE(kWarningPeriod, "rigid_body_node: body %s diverged (%s); publishing its last good state until ~reset",
                         config_.bodies[body].body_frame.c_str(), rigid_body::divergenceName(scene.divergence(body)));
    }
  }
  for (std::size_t body : result.timed_out) {
    ROS_INFO("rigid_body_node: %s: no wrench for %.3f s (wrench_timeout): applied wrench set to zero",
             config_.bodies[body].body_frame.c_str(), config_.wrench_timeout);
  }
  if (result.reanchored) {
    ROS_WARN("rigid_body_node: ROS time jumped back; re-anchoring the simulation clock at %.3f s",
             toSeconds(world_.stamp()));
    diagnostics_.forceUpdate();  // diagnostic_updater's next report is scheduled far ahead now
  }
  if (result.end_of_time && timer_.isValid()) {
    // Nothing more can happen on this clock: stop the timer before roscpp's own arithmetic overflows.
    timer_.stop();
    timer_ = ros::Timer();
    ROS_ERROR("rigid_body_node: simulated time reached the end of what ROS time can hold (2^32 s, less a margin): "
              "the clock and the timer stopped; services still answer; restart with an earlier clock");
    diagnostics_.forceUpdate();
  }
}

void SimulatorNode::runLockstep(const std::function<bool()>& keep_running,
                                const std::function<void()>& serve_callbacks) {
  const std::int64_t steps_per_publish =
      std::max<std::int64_t>(1, std::llround(std::min(1e12, 1.0 / (config_.rate * config_.dt))));
  outputs_.publishClock(world_);
  ros::WallTime pace_start = ros::WallTime::now();
  std::int64_t pace_steps = world_.clockSteps();
  while (ros::ok() && keep_running()) {
    serve_callbacks();  // wrenches and services act between two steps
    if (world_.paused() || world_.endOfTime()) {
      ros::WallDuration(kPausedPoll).sleep();
      pace_start = ros::WallTime::now();
      pace_steps = world_.clockSteps();
      continue;
    }
    guarded([&] {
      // The timer's update, on our own clock: up to the next output at once (one look at the callbacks per
      // output: wrenches and services act at the output grid), within the catch-up caps so nothing is dropped.
      const std::int64_t steps = world_.clockSteps();
      const std::int64_t to_output = steps_per_publish - steps % steps_per_publish;
      const std::int64_t chunk = std::min(to_output, world_.updateBudget());
      advance(world_.timeOfStep(steps + chunk));
      if (world_.clockSteps() % steps_per_publish == 0) {
        outputs_.publishClock(world_);
        publish();
        diagnostics_.update();
      }
    });
    if (config_.real_time_factor > 0.0) {
      // Sleep until wall time catches up with simulated time / factor, in slices so shutdown is noticed.
      const double simulated = static_cast<double>(world_.clockSteps() - pace_steps) * config_.dt;
      const double wait = simulated / config_.real_time_factor - (ros::WallTime::now() - pace_start).toSec();
      if (wait > 0.0) ros::WallDuration(std::min(wait, kPacingSlice)).sleep();
    }
  }
}

}  // namespace rigid_body_ros
