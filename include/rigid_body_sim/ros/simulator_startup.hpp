// Start-up of the simulator, shared by the node (rigid_body_node) and the nodelet (RigidBodyNodelet): read
// and check the parameters, then build the SimulatorNode. Every failure is one FATAL line naming what failed;
// the node then exits with code 2, the nodelet fails its load.
#pragma once

#include <ros/ros.h>

#include <memory>

#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/simulator_node.hpp"

namespace rigid_body_ros {

/// Reads `private_nh`'s parameters (warning about unknown names and about registering thousands of per-body
/// topics) and builds the simulator on `nh` (topics, services) and `private_nh` (diagnostics, live
/// parameters). Returns null after logging the failure as one FATAL line: an invalid parameter, a mesh that
/// cannot be read, `publish/clock` under another node's /clock, memory.
std::unique_ptr<SimulatorNode> startSimulator(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

/// Lockstep's hold on /use_sim_time: set to true if unset (as Gazebo does, so that other nodes follow the
/// simulator's /clock), and deleted again by release() or the destructor, so that the next node started on
/// this master is on wall time.
class SimTimeClaim {
 public:
  SimTimeClaim();
  ~SimTimeClaim() { release(); }
  SimTimeClaim(const SimTimeClaim&) = delete;
  SimTimeClaim& operator=(const SimTimeClaim&) = delete;
  void release();

 private:
  bool set_ = false;
};

}  // namespace rigid_body_ros
