// rigid_body_node: one simulated rigid body. Reads and validates ~parameters (exit 2 on an invalid one),
// then runs the timer loop until shut down.
#include <ros/ros.h>

#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/simulator_node.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "rigid_body_node");
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  rigid_body_ros::NodeConfig config;
  try {
    config = rigid_body_ros::loadConfig(private_nh);
  } catch (const rigid_body_ros::ParameterError& error) {
    ROS_FATAL("%s", error.what());
    return 2;
  }
  for (const std::string& name : config.unknown_parameters) {
    ROS_WARN("unknown parameter ~%s is ignored (a typo?)", name.c_str());
  }
  rigid_body_ros::SimulatorNode node(nh, private_nh, config);
  if (config.lockstep) {
    // The node owns simulated time: other nodes follow /clock (as with Gazebo, /use_sim_time is set if unset).
    if (!ros::param::has("/use_sim_time")) ros::param::set("/use_sim_time", true);
    node.start(ros::Time(0));
    node.runLockstep();
    return 0;
  }
  ros::Time::waitForValid();  // under /use_sim_time, until the first /clock message
  node.start(ros::Time::now());
  ros::spin();
  return 0;
}
