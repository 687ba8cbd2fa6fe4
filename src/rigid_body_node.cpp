// rigid_body_node: one simulated scene. Reads and validates ~parameters (exit 2 on an invalid one), then
// runs the timer loop (or the lockstep loop) until shut down.
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcException.h>

#include <atomic>
#include <csignal>
#include <exception>
#include <memory>

#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/simulator_node.hpp"

namespace {

// Set by SIGINT/SIGTERM. The lockstep loop stops on it and the node then undoes what it changed on the master
// (/use_sim_time) before it shuts down: roscpp's own handler would end the master connection first.
std::atomic<bool> g_stop_requested{false};
bool g_lockstep = false;

void requestStop(int /*signal*/) {
  g_stop_requested = true;
  if (!g_lockstep) ros::requestShutdown();  // async-signal-safe: it only sets roscpp's flag
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "rigid_body_node", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  rigid_body_ros::NodeConfig config;
  std::unique_ptr<rigid_body_ros::SimulatorNode> node;
  // Every failure of start-up is one line and exit code 2, whatever threw: a parameter, a mesh, memory.
  const ros::WallTime begin = ros::WallTime::now();
  try {
    config = rigid_body_ros::loadConfig(private_nh);
    const ros::WallTime parsed = ros::WallTime::now();
    for (const std::string& name : config.unknown_parameters) {
      ROS_WARN("unknown parameter ~%s is ignored (a typo?)", name.c_str());
    }
    // Per-body topics and services register with the ROS master one by one, at ~1 ms of the master's time
    // each (docs/scenes.md): a scene of thousands waits tens of seconds before its first output.
    constexpr std::size_t kManyBodies = 1000;
    if (config.publish.per_body_topics && config.bodies.size() >= kManyBodies) {
      ROS_WARN("rigid_body_node: %zu bodies on per-body topics: their registrations with the ROS master take "
               "~1 ms each (10 000 bodies ~40 s) before the first output; publish/per_body_topics: false puts "
               "the scene on bodies/odom and bodies/wrench, a few registrations in all",
               config.bodies.size());
    }
    if (config.publish.clock && !config.lockstep && ros::Time::isSimTime()) {
      throw rigid_body_ros::ParameterError(
          "parameter ~publish/clock = true: not allowed under /use_sim_time = true, where the node follows "
          "another /clock; lockstep: true makes the node the owner of simulated time and of /clock");
    }
    node = std::make_unique<rigid_body_ros::SimulatorNode>(nh, private_nh, config);
    ROS_INFO("rigid_body_node: start-up: parameters read in %.3f s, %zu bodies' topics and services set up in %.3f s",
             (parsed - begin).toSec(), config.bodies.size(), (ros::WallTime::now() - parsed).toSec());
  } catch (const rigid_body_ros::ParameterError& error) {
    ROS_FATAL("%s", error.what());
    return 2;
  } catch (const std::exception& error) {
    ROS_FATAL("rigid_body_node: cannot start: %s", error.what());
    return 2;
  } catch (const XmlRpc::XmlRpcException& error) {  // not a std::exception: a value read as the wrong type
    ROS_FATAL("rigid_body_node: cannot start: a parameter of an unexpected type: %s", error.getMessage().c_str());
    return 2;
  }
  if (config.lockstep) {
    // The node owns simulated time: other nodes follow /clock (as with Gazebo, /use_sim_time is set if unset),
    // and a parameter it set is deleted at exit, so that the next node started on this master is on wall time.
    g_lockstep = true;
    const bool set_sim_time = !ros::param::has("/use_sim_time");
    if (set_sim_time) ros::param::set("/use_sim_time", true);
    node->start(ros::Time(0));
    node->runLockstep([] { return !g_stop_requested; });
    if (set_sim_time) ros::param::del("/use_sim_time");
    node.reset();
    ros::shutdown();
    return 0;
  }
  ros::Time::waitForValid();  // under /use_sim_time, until the first /clock message
  node->start(ros::Time::now());
  ros::spin();
  return 0;
}
