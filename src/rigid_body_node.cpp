// rigid_body_node: one simulated scene. Reads and validates ~parameters (exit 2 on an invalid one), then
// runs the timer loop (or the lockstep loop) until shut down.
#include <ros/ros.h>

#include <atomic>
#include <csignal>
#include <memory>

#include "rigid_body_sim/ros/simulator_startup.hpp"

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
  // Every failure of start-up is one line and exit code 2, whatever threw: a parameter, a mesh, memory.
  std::unique_ptr<rigid_body_ros::SimulatorNode> node = rigid_body_ros::startSimulator(nh, private_nh);
  if (!node) return 2;
  if (node->lockstep()) {
    g_lockstep = true;
    rigid_body_ros::SimTimeClaim sim_time;
    node->start(ros::Time(0));
    node->runLockstep([] { return !g_stop_requested; }, [] { ros::spinOnce(); });
    sim_time.release();
    node.reset();
    ros::shutdown();
    return 0;
  }
  ros::Time::waitForValid();  // under /use_sim_time, until the first /clock message
  node->start(ros::Time::now());
  ros::spin();
  return 0;
}
