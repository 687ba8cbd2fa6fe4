#include "rigid_body_sim/ros/simulator_startup.hpp"

#include <xmlrpcpp/XmlRpcException.h>

#include <exception>
#include <string>

namespace rigid_body_ros {

namespace {

// Per-body topics and services register with the ROS master one by one, at ~1 ms of the master's time each
// (docs/scenes.md): from this many bodies on, the wait before the first output is worth a warning.
constexpr std::size_t kManyBodies = 1000;

NodeConfig checkedConfig(const ros::NodeHandle& private_nh) {
  NodeConfig config = loadConfig(private_nh);
  for (const std::string& name : config.unknown_parameters) {
    ROS_WARN("unknown parameter ~%s is ignored (a typo?)", name.c_str());
  }
  if (config.publish.per_body_topics && config.bodies.size() >= kManyBodies) {
    ROS_WARN("rigid_body_node: %zu bodies on per-body topics: their registrations with the ROS master take "
             "~1 ms each (10 000 bodies ~40 s) before the first output; publish/per_body_topics: false puts "
             "the scene on bodies/odom and bodies/wrench, a few registrations in all",
             config.bodies.size());
  }
  if (config.publish.clock && !config.lockstep && ros::Time::isSimTime()) {
    throw ParameterError(
        "parameter ~publish/clock = true: not allowed under /use_sim_time = true, where the node follows "
        "another /clock; lockstep: true makes the node the owner of simulated time and of /clock");
  }
  return config;
}

}  // namespace

std::unique_ptr<SimulatorNode> startSimulator(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh) {
  const ros::WallTime begin = ros::WallTime::now();
  try {
    const NodeConfig config = checkedConfig(private_nh);
    const ros::WallTime parsed = ros::WallTime::now();
    auto node = std::make_unique<SimulatorNode>(nh, private_nh, config);
    ROS_INFO("rigid_body_node: start-up: parameters read in %.3f s, %zu bodies' topics and services set up in %.3f s",
             (parsed - begin).toSec(), config.bodies.size(), (ros::WallTime::now() - parsed).toSec());
    return node;
  } catch (const ParameterError& error) {
    ROS_FATAL("%s", error.what());
  } catch (const std::exception& error) {
    ROS_FATAL("rigid_body_node: cannot start: %s", error.what());
  } catch (const XmlRpc::XmlRpcException& error) {  // not a std::exception: a value read as the wrong type
    ROS_FATAL("rigid_body_node: cannot start: a parameter of an unexpected type: %s", error.getMessage().c_str());
  }
  return nullptr;
}

SimTimeClaim::SimTimeClaim() : set_(!ros::param::has("/use_sim_time")) {
  if (set_) ros::param::set("/use_sim_time", true);
}

void SimTimeClaim::release() {
  if (set_) ros::param::del("/use_sim_time");
  set_ = false;
}

}  // namespace rigid_body_ros
