// Load generator (not a test; run by scripts/load_test.sh): publishes wrenches at a high rate for a while
// and reports what the node made of them: its publish rate, whether the last wrench applied is the last one
// sent, the node's CPU share and its timer overruns (from /diagnostics).
//
//   wrench_load NAMESPACE NODE_PID [RATE_HZ=10000] [SECONDS=10]
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "process_cpu.hpp"
#include "rigid_body_sim/RigidBodyState.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "wrench_load", ros::init_options::AnonymousName);
  if (argc < 3) {
    std::fprintf(stderr, "usage: wrench_load NAMESPACE NODE_PID [RATE_HZ=10000] [SECONDS=10]\n");
    return 2;
  }
  const std::string ns = argv[1];
  const int pid = std::stoi(argv[2]);
  const double rate = argc > 3 ? std::stod(argv[3]) : 10000.0;
  const double seconds = argc > 4 ? std::stod(argv[4]) : 10.0;
  ros::NodeHandle nh;
  ros::Publisher publisher = nh.advertise<geometry_msgs::WrenchStamped>(ns + "/wrench", 100);
  int odom_count = 0;
  bool counting = false;
  ros::Subscriber odom = nh.subscribe<nav_msgs::Odometry>(ns + "/odom", 1000, [&](const nav_msgs::Odometry::ConstPtr&) {
    if (counting) ++odom_count;
  });
  rigid_body_sim::RigidBodyState last_state;
  ros::Subscriber state = nh.subscribe<rigid_body_sim::RigidBodyState>(
      ns + "/state", 10, [&](const rigid_body_sim::RigidBodyState::ConstPtr& m) { last_state = *m; });
  std::string overruns = "?", applied = "?";
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& array) {
        for (const auto& status : array->status) {
          for (const auto& pair : status.values) {
            if (pair.key == "timer overruns") overruns = pair.value;
            if (pair.key == "wrenches applied") applied = pair.value;
          }
        }
      });
  // Wait for the connection, handling (and not counting) what arrives meanwhile.
  const ros::WallTime connect = ros::WallTime::now();
  while (ros::ok() && (publisher.getNumSubscribers() == 0 || (ros::WallTime::now() - connect).toSec() < 0.5)) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }

  geometry_msgs::WrenchStamped message;
  message.header.frame_id = "world";
  counting = true;
  const double cpu_start = cpuSecondsOf(pid);
  const ros::WallTime start = ros::WallTime::now();
  ros::WallRate loop(rate);
  long sent = 0;
  while (ros::ok() && (ros::WallTime::now() - start).toSec() < seconds) {
    // A force that differs in every message, so the last one applied can be told from the others.
    message.header.stamp = ros::Time::now();
    message.wrench.force.x = 1e-3 * static_cast<double>(++sent % 1000);
    message.wrench.force.y = static_cast<double>(sent);
    publisher.publish(message);
    ros::spinOnce();
    loop.sleep();
  }
  const double elapsed = (ros::WallTime::now() - start).toSec();
  const double cpu = cpuSecondsOf(pid) - cpu_start;
  counting = false;
  const ros::WallTime settle = ros::WallTime::now();
  while ((ros::WallTime::now() - settle).toSec() < 2.5) {  // the last state and a diagnostics report
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  const bool last_applied = last_state.applied_wrench.force.y == message.wrench.force.y;
  std::printf("wrenches sent: %ld in %.2f s (%.0f Hz)\n", sent, elapsed, sent / elapsed);
  std::printf("wrenches applied by the node (diagnostics): %s\n", applied.c_str());
  std::printf("odometry received: %d (%.1f Hz)\n", odom_count, odom_count / elapsed);
  std::printf("last wrench applied = last sent: %s (force.y %.0f vs %.0f)\n", last_applied ? "yes" : "no",
              last_state.applied_wrench.force.y, message.wrench.force.y);
  std::printf("node CPU: %.1f %% of one core\n", 100.0 * cpu / elapsed);
  std::printf("timer overruns (diagnostics): %s\n", overruns.c_str());
  return last_applied ? 0 : 1;
}
