#include "rigid_body_sim/ros/node_diagnostics.hpp"

#include <sstream>

#include <string>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

namespace {
// The publish-rate status accepts ±10 % of the configured rate over a window of 10 reports.
constexpr double kFrequencyTolerance = 0.1;
constexpr int kFrequencyWindow = 10;
}  // namespace

NodeDiagnostics::NodeDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeConfig& config,
                                 const rigid_body::World& world, const WrenchInput& wrench_input,
                                 const Outputs& outputs)
    : config_(config),
      world_(world),
      wrench_input_(wrench_input),
      outputs_(outputs),
      updater_(nh, private_nh) {
  updater_.setHardwareID(ros::this_node::getName());
  updater_.add("Frequency Status", this, &NodeDiagnostics::diagnoseFrequency);
  updater_.add(config.bodies.size() == 1 ? "rigid body " + config.bodies[0].body_frame
                                         : "rigid body scene (" + std::to_string(config.bodies.size()) + " bodies)",
               this, &NodeDiagnostics::diagnose);
}

void NodeDiagnostics::tick(rigid_body::Nanoseconds now) {
  ++ticks_;
  last_tick_ = now;
}

void NodeDiagnostics::diagnoseFrequency(diagnostic_updater::DiagnosticStatusWrapper& status) {
  window_.emplace_back(ticks_, last_tick_);
  if (window_.size() > static_cast<std::size_t>(kFrequencyWindow)) window_.erase(window_.begin());
  const std::uint64_t events = window_.back().first - window_.front().first;
  const rigid_body::Nanoseconds span = window_.back().second - window_.front().second;  // both on one clock
  const double seconds = toSeconds(span);
  const double frequency = seconds > 0.0 ? static_cast<double>(events) / seconds : 0.0;
  if (events == 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "No events recorded.");
  } else if (frequency < config_.rate * (1.0 - kFrequencyTolerance)) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "Frequency too low.");
  } else if (frequency > config_.rate * (1.0 + kFrequencyTolerance)) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "Frequency too high.");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "Desired frequency met");
  }
  status.add("Events in window", events);
  status.add("Events since startup", ticks_);
  status.add("Duration of window (s)", seconds);
  status.add("Actual frequency (Hz)", frequency);
  status.add("Target frequency (Hz)", config_.rate);
}

void NodeDiagnostics::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const rigid_body::Scene& scene = world_.scene();
  const rigid_body::WorldCounters& counters = world_.counters();
  const WrenchRejections& rejections = wrench_input_.rejections();
  const std::uint64_t problems = rejections.total() + counters.dropped_steps + timer_overruns_ +
                                 counters.refused_commands + counters.refused_moment_arms + outputs_.withheld();
  const std::size_t bodies = scene.bodyCount();
  const std::size_t first_diverged = scene.firstDiverged();
  const std::size_t diverged = bodies - scene.runningBodies();
  // The reason of the first body that diverged ("none" while none has).
  const char* divergence = rigid_body::divergenceName(first_diverged < bodies ? scene.divergence(first_diverged)
                                                                               : rigid_body::Divergence::kNone);
  if (world_.endOfTime()) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "simulated time reached the end of what ROS time can hold (2^32 s): the clock stopped");
  } else if (diverged > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                    "%zu of %zu bodies diverged (%s): publishing their last good state; call reset", diverged, bodies,
                    divergence);
  } else if (problems > reported_problems_) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "inputs rejected, steps dropped, messages withheld or timer overruns since the last report");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  reported_problems_ = problems;

  status.add("integrator", rigid_body::integratorName(scene.integratorType()));
  status.add("dt [s]", config_.dt);
  status.add("bodies", bodies);
  status.add("divergence", divergence);
  status.add("substeps last tick", counters.last_substeps);
  status.add("max substeps in one tick", counters.max_substeps_seen);
  status.add("dropped steps", counters.dropped_steps);
  status.add("timer overruns", timer_overruns_);
  status.add("backward time jumps", counters.backward_time_jumps);
  status.add("wrenches applied", counters.topic_wrenches);
  status.add("timed wrenches applied", counters.timed_wrenches);
  status.add("rejected non_finite", rejections.non_finite);
  status.add("rejected force_over_limit", rejections.force_limit);
  status.add("rejected torque_over_limit", rejections.torque_limit);
  status.add("rejected unknown_frame", rejections.unknown_frame);
  status.add("rejected by the core", rejections.refused_by_core);
  status.add("rejected unknown_body", rejections.unknown_body);
  status.add("rejected oversized", rejections.oversized);
  status.add("refused commands", counters.refused_commands);
  status.add("refused moment arms", counters.refused_moment_arms);
  status.add("messages withheld (non-finite)", outputs_.withheld());
  if (world_.lastWrenchArrival() >= 0) {
    status.add("time since last wrench [s]", toSeconds(toNanoseconds(ros::Time::now()) - world_.lastWrenchArrival()));
  } else {
    status.add("time since last wrench [s]", "never");
  }
  bool timed_out = false;
  for (std::size_t body = 0; body < bodies; ++body) timed_out = timed_out || world_.wrenchTimedOut(body);
  status.add("wrench timed out", timed_out ? "true" : "false");
  addBodies(status);
}

std::string describeBodyStep(const rigid_body::Scene& scene, std::size_t body, const NodeConfig& config) {
  std::string line = rigid_body::describeTerms(scene.terms(body));
  if (!scene.collides(body)) return line;
  const rigid_body::ContactMaterial& material = config.bodies[body].collision->material;
  std::ostringstream contact;
  contact << ", contact (" << rigid_body::shapeTypeName(config.bodies[body].collision->type) << ", restitution "
          << material.restitution << ", friction " << material.friction << ")";
  return line + contact.str();
}

void NodeDiagnostics::addBodies(diagnostic_updater::DiagnosticStatusWrapper& status) const {
  const rigid_body::Scene& scene = world_.scene();
  const std::size_t bodies = scene.bodyCount();
  if (scene.hasContact()) {
    const rigid_body::ContactStatistics contact = scene.contactStatistics();
    std::size_t points = 0;
    for (std::size_t body = 0; body < bodies; ++body) points += scene.contactCount(body);
    status.add("contact points", points);
    status.add("max penetration since reset [m]", contact.max_penetration);
    status.add("impacts located in time", contact.located_impacts);
    status.add("impacts found by the swept test", contact.swept_impacts);
    status.add("steps split for a fast body", contact.split_steps);
    status.add("contact steps refused (non-finite)", contact.refused_steps);
    status.add("bodies out of contact range (1e6 m)", contact.out_of_range);
    status.add("bodies asleep", contact.sleeping_bodies);
    status.add("islands woken since reset", contact.wakes);
  }
  // Drift per body, keyed by the body frame when the scene has several.
  for (std::size_t body = 0; body < bodies; ++body) {
    const rigid_body::Model& model = scene.model(body);
    const auto energy = [&](const rigid_body::State& s) {
      return rigid_body::kineticEnergy(model.mass, s) + rigid_body::potentialEnergy(model.mass, model.forces, s);
    };
    const rigid_body::State& state = scene.state(body);
    const rigid_body::State& initial = scene.initialState(body);
    const std::string prefix = bodies == 1 ? "" : config_.bodies[body].body_frame + ": ";
    if (bodies > 1) status.add(prefix + "divergence", rigid_body::divergenceName(scene.divergence(body)));
    status.add(prefix + "step terms", describeBodyStep(scene, body, config_));
    status.add(prefix + "energy change since reset [J]", energy(state) - energy(initial));
    status.add(prefix + "|L| change since reset [kg m^2/s]", state.L_W.norm() - initial.L_W.norm());
    status.add(prefix + "max ||q| - 1| since reset", outputs_.maxNormError(body));
  }
}

}  // namespace rigid_body_ros
