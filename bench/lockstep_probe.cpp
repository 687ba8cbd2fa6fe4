// Lockstep speed probe (not a test; run by scripts/lockstep_speed.sh): with a lockstep node already running
// at real_time_factor 0, measures over a wall-clock window how much simulated time passes (from /clock),
// the node's CPU share, and how many odometry and tf messages this probe receives while subscribed to one
// body's odom and to /tf (so that the node fills and serialises both at every output).
//
// With OUTPUTS=clock it subscribes to /clock only: what the node costs when nobody reads its tf and odometry.
//
//   lockstep_probe BODY_NAMESPACE NODE_PID [SECONDS=10] [OUTPUTS=all|clock]
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_msgs/TFMessage.h>

#include <cstdio>
#include <string>

#include "process_cpu.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "lockstep_probe", ros::init_options::AnonymousName);
  if (argc < 3) {
    std::fprintf(stderr, "usage: lockstep_probe BODY_NAMESPACE NODE_PID [SECONDS=10] [OUTPUTS=all|clock]\n");
    return 2;
  }
  const std::string body = argv[1];
  const int pid = std::stoi(argv[2]);
  const double seconds = argc > 3 ? std::stod(argv[3]) : 10.0;
  const bool outputs = argc <= 4 || std::string(argv[4]) != "clock";
  ros::NodeHandle nh;
  double clock = -1.0;
  std::size_t clocks = 0, odoms = 0, tfs = 0;
  // Queues of one: the probe wants the newest clock, not every one (the node publishes faster than any
  // subscriber reads); it counts what it received.
  ros::Subscriber clock_sub = nh.subscribe<rosgraph_msgs::Clock>("/clock", 1, [&](const rosgraph_msgs::Clock::ConstPtr& m) {
    clock = m->clock.toSec();
    ++clocks;
  });
  ros::Subscriber odom, tf;
  if (outputs) {
    odom = nh.subscribe<nav_msgs::Odometry>(body + "/odom", 1, [&](const nav_msgs::Odometry::ConstPtr&) { ++odoms; });
    tf = nh.subscribe<tf2_msgs::TFMessage>("/tf", 1, [&](const tf2_msgs::TFMessage::ConstPtr&) { ++tfs; });
  }
  const ros::WallTime connect = ros::WallTime::now();
  while (ros::ok() && (clock_sub.getNumPublishers() == 0 || (outputs && (odom.getNumPublishers() == 0 || tf.getNumPublishers() == 0)) ||
                       clock < 0.0 || (ros::WallTime::now() - connect).toSec() < 1.0)) {
    if ((ros::WallTime::now() - connect).toSec() > 30.0) {
      std::fprintf(stderr, "lockstep_probe: no /clock%s from the node within 30 s\n", outputs ? ", tf or odom" : "");
      return 1;
    }
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ros::spinOnce();
  const double clock_start = clock;
  clocks = odoms = tfs = 0;
  const double cpu_start = cpuSecondsOf(pid);
  const ros::WallTime start = ros::WallTime::now();
  while (ros::ok() && (ros::WallTime::now() - start).toSec() < seconds) {
    ros::spinOnce();
    ros::WallDuration(0.0005).sleep();
  }
  ros::spinOnce();
  const double wall = (ros::WallTime::now() - start).toSec();
  const double cpu = (cpuSecondsOf(pid) - cpu_start) / wall;
  const double simulated = clock - clock_start;
  std::printf("%.1f s simulated in %.1f s wall: %.0fx real time; node cpu %.1f %% of one core; received "
              "/clock %.0f Hz, odom %.0f Hz, tf %.0f Hz (wall)\n",
              simulated, wall, simulated / wall, 100.0 * cpu, clocks / wall, odoms / wall, tfs / wall);
  return simulated > 0.0 ? 0 : 1;
}
