// dynamic_reconfigure under the node's private namespace, as ~live (cfg/RigidBody.cfg): damping, gravity, the
// wrench timeout and limits, the lockstep pace, the noise of odom_noisy and the marker rate, changed while the
// node runs. A change reaches the core as a command stamped with its arrival, so it takes effect from the step
// of its arrival.
//
// Why ~live and not ~ itself: the server writes every value it holds back to the parameter server, and a
// node that starts again (respawn, a second rosrun) reads its start-up parameters from there. Under ~ those
// write-backs would be taken for start-up parameters (a damping beside ~bodies, max_force 0 for "no limit"),
// and the restart would fail.
#pragma once

#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>

#include <boost/thread/recursive_mutex.hpp>
#include <cstdint>
#include <functional>
#include <memory>

#include "rigid_body_sim/RigidBodyConfig.h"
#include "rigid_body_sim/ros/outputs.hpp"
#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/world.hpp"

namespace rigid_body_ros {

class LiveParameters {
 public:
  /// `config` is the node's own, updated in place (the other parts read it each time); `now` the node's clock.
  LiveParameters(const ros::NodeHandle& private_nh, NodeConfig& config, rigid_body::World& world, Outputs& outputs,
                 std::function<rigid_body::Nanoseconds()> now);

  /// The server's view of a node configuration (for its initial values, and for tests).
  static rigid_body_sim::RigidBodyConfig fromNodeConfig(const NodeConfig& config);

 private:
  void onChange(rigid_body_sim::RigidBodyConfig& requested, uint32_t level);
  // A NaN in a request (the server's range clamp lets it through) and a wrench limit not > 0 become the value
  // in force.
  void keepValidValues(rigid_body_sim::RigidBodyConfig& requested);

  NodeConfig& config_;
  rigid_body::World& world_;
  Outputs& outputs_;
  std::function<rigid_body::Nanoseconds()> now_;
  rigid_body_sim::RigidBodyConfig current_;
  std::uint64_t refused_ = 0;  // requests with a non-finite value
  boost::recursive_mutex mutex_;  // the server's: given to it so that our updateConfig takes it too
  std::unique_ptr<dynamic_reconfigure::Server<rigid_body_sim::RigidBodyConfig>> server_;
};

}  // namespace rigid_body_ros
