// The ROS node around one simulated scene. It owns the core World and wires the ROS side to it: wrench
// messages are converted once into World commands (WrenchInput), service requests likewise
// (ControlServices), and the state goes out through Outputs, with NodeDiagnostics reporting. The timer
// only calls update(now); the lockstep driver calls the same update with the World's own clock. Nothing
// here integrates physics: the World does, in update and in a step request.
#pragma once

#include <ros/ros.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rigid_body_sim/ros/control_services.hpp"
#include "rigid_body_sim/ros/imu_outputs.hpp"
#include "rigid_body_sim/ros/node_diagnostics.hpp"
#include "rigid_body_sim/ros/live_parameters.hpp"
#include "rigid_body_sim/ros/markers.hpp"
#include "rigid_body_sim/ros/outputs.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/wrench_input.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

/// The World's settings for a node's configuration: the step caps, the timeout, one tick of jitter, the end
/// of ROS time, lockstep.
rigid_body::WorldSettings worldSettings(const NodeConfig& config);

class SimulatorNode {
 public:
  /// `nh` carries the namespace of the topics and the services, `private_nh` the diagnostics' settings.
  SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const NodeConfig& config);

  /// Anchors simulated time 0 at `start_time`, logs the scene and starts the timer (not in lockstep).
  void start(const ros::Time& start_time);

  /// Lockstep: the node owns simulated time. Steps the scene, publishes /clock and the outputs at `rate`,
  /// paces itself by real_time_factor (0: as fast as possible), and calls `serve_callbacks` between steps
  /// (the node: ros::spinOnce; the nodelet: its own queue's callAvailable), so that wrenches and requests act
  /// between two steps and never during one; returns at shutdown or when `keep_running` says false. Called
  /// instead of ros::spin().
  void runLockstep(const std::function<bool()>& keep_running, const std::function<void()>& serve_callbacks);

  /// One tick: the World integrates up to `now`; the state is published if the clock reached a new grid
  /// point. Published stamps advance by whole steps of dt, so they strictly increase.
  void update(const ros::Time& now);

  const rigid_body::World& world() const { return world_; }

  /// Scene edits (simulator_edits.cpp), also the spawn, remove and list_bodies services: at once, between
  /// two steps (the node's callbacks never run during one). A body spawned from `yaml`, the keys of one
  /// ~bodies item, or the body called `name` removed; false with the reason in `message` when refused, the
  /// scene unchanged.
  bool spawn(const std::string& yaml, std::string& message);
  bool remove(const std::string& name, std::string& message);
  bool lockstep() const { return config_.lockstep; }

 private:
  /// The node's notion of now [ns]: the World's own clock in lockstep, ROS time otherwise.
  rigid_body::Nanoseconds now() const;
  /// The World's update and its report: the one code path of the timer and the lockstep driver.
  rigid_body::UpdateResult advance(rigid_body::Nanoseconds now);
  /// Runs one tick, logging (throttled) instead of dying if anything in it throws.
  void guarded(const std::function<void()>& tick);
  /// Logs what an update did that a user should hear about (drops, divergence, timeouts, jumps).
  void report(const rigid_body::UpdateResult& result);
  void publish();
  /// Logs a body's properties and its step, once (at start-up, at its spawn).
  void logBody(std::size_t body) const;
  void advertiseEditServices();
  /// The config appends `config` and every component takes it, or every component lets the body at `body`
  /// go and the config drops it; the markers and the static frames follow.
  void addToComponents(const BodyConfig& config);
  void removeFromComponents(std::size_t body);
  /// The static tf of the bodies' mesh frames and sensors, in the node's one latched message.
  void publishStaticFrames(const ros::Time& stamp);
  /// Counts a refused spawn or remove and warns (throttled: a client retrying in a loop does not flood the log).
  void refuseEdit(const std::string& message);

  NodeConfig config_;
  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  rigid_body::World world_;
  OwnTransforms own_transforms_;  // before its users: WrenchInput's tf listener, Outputs
  WrenchInput wrench_input_;
  Outputs outputs_;
  Markers markers_;
  ImuOutputs imu_;
  NodeDiagnostics diagnostics_;
  ControlServices services_;
  LiveParameters live_;
  std::vector<ros::ServiceServer> edit_services_;  ///< spawn, remove, list_bodies
  std::uint64_t refused_edits_ = 0;
  ros::Timer timer_;
};

}  // namespace rigid_body_ros
