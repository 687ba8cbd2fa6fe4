// diagnostic_updater for the node: the publish rate, and one status with every counter of the World, the
// wrench input and the outputs, divergence and the end of time as ERROR, new problems as WARN.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <ros/ros.h>

#include <cstdint>

#include "rigid_body_sim/ros/outputs.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/wrench_input.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

class NodeDiagnostics {
 public:
  NodeDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeConfig& config,
                  const rigid_body::World& world, const WrenchInput& wrench_input, const Outputs& outputs);

  /// A publication happened (for the rate status).
  void tick() { publish_frequency_.tick(); }
  /// A timer tick took longer than its period.
  void countOverrun() { ++timer_overruns_; }
  /// Reports if the diagnostics period has passed (diagnostic_updater's own rate limit).
  void update() { updater_.update(); }
  /// Reports now (after a backward time jump, which leaves diagnostic_updater's schedule far ahead).
  void forceUpdate() { updater_.force_update(); }

 private:
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  const NodeConfig& config_;
  const rigid_body::World& world_;
  const WrenchInput& wrench_input_;
  const Outputs& outputs_;
  diagnostic_updater::Updater updater_;
  double min_frequency_;  ///< bounds of the publish-rate status [Hz]
  double max_frequency_;
  diagnostic_updater::FrequencyStatus publish_frequency_;
  std::uint64_t timer_overruns_ = 0;
  std::uint64_t reported_problems_ = 0;  ///< rejections, drops and overruns at the last report
};

}  // namespace rigid_body_ros
