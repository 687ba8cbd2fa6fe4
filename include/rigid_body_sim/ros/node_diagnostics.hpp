// diagnostic_updater for the node: the publish rate, and one status with every counter of the World, the
// wrench input and the outputs, divergence and the end of time as ERROR, new problems as WARN.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "rigid_body_sim/ros/outputs.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/wrench_input.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

/// "translation, rotation, gravity, contact (restitution 0.5, friction 0.5)": a body's assembled step, with
/// the contact term only for a body that collides.
std::string describeBodyStep(const rigid_body::Scene& scene, std::size_t body, const NodeConfig& config);

class NodeDiagnostics {
 public:
  NodeDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeConfig& config,
                  const rigid_body::World& world, const WrenchInput& wrench_input, const Outputs& outputs);

  /// A publication happened at `now` on the node's clock (for the rate status).
  void tick(rigid_body::Nanoseconds now);
  /// A timer tick took longer than its period.
  void countOverrun() { ++timer_overruns_; }
  /// Reports if the diagnostics period has passed (diagnostic_updater's own rate limit).
  void update() { updater_.update(); }
  /// Reports now (after a backward time jump, which leaves diagnostic_updater's schedule far ahead).
  void forceUpdate() { updater_.force_update(); }

 private:
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  /// Per body: divergence (with several bodies), the step terms, and the drift since reset.
  void addBodies(diagnostic_updater::DiagnosticStatusWrapper& status) const;
  /// The publish rate over the last kFrequencyWindow reports, within ±10 % of `rate` (as diagnostic_updater's
  /// FrequencyStatus, whose ros::Time subtraction throws after a jump of more than 2^31 s: here in ns).
  void diagnoseFrequency(diagnostic_updater::DiagnosticStatusWrapper& status);

  const NodeConfig& config_;
  const rigid_body::World& world_;
  const WrenchInput& wrench_input_;
  const Outputs& outputs_;
  diagnostic_updater::Updater updater_;
  std::uint64_t ticks_ = 0;                          ///< publications since start-up
  std::vector<std::pair<std::uint64_t, rigid_body::Nanoseconds>> window_;  ///< (ticks, time) at each report
  rigid_body::Nanoseconds last_tick_ = 0;
  std::uint64_t timer_overruns_ = 0;
  std::uint64_t reported_problems_ = 0;  ///< rejections, drops and overruns at the last report
};

}  // namespace rigid_body_ros
