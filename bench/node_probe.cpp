// Node load probe (not a test; run by scripts/node_load.sh): with a node already running, measures
//   - its CPU share over a window, while this probe subscribes to /tf (every body's transform, so the node
//     serialises its one tf message per tick) and to one body's odom;
//   - timer jitter: the spread of that odom's arrival intervals (wall clock) around the publish period;
//   - wrench-to-odometry latency: from publishing a wrench to a body at rest to the first odom that shows it
//     moving, over repeated trials (reset between them). This is an upper bound of "arrival to first odom
//     that includes it": it also holds the transport of the wrench to the node.
//
//   node_probe BODY_NAMESPACE RESET_SERVICE NODE_PID [SECONDS=10] [TRIALS=30]
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "process_cpu.hpp"

namespace {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(std::lround(p * static_cast<double>(values.size() - 1)))];
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "node_probe", ros::init_options::AnonymousName);
  if (argc < 4) {
    std::fprintf(stderr, "usage: node_probe BODY_NAMESPACE RESET_SERVICE NODE_PID [SECONDS=10] [TRIALS=30]\n");
    return 2;
  }
  const std::string body = argv[1];
  const std::string reset_service = argv[2];
  const int pid = std::stoi(argv[3]);
  const double seconds = argc > 4 ? std::stod(argv[4]) : 10.0;
  const int trials = argc > 5 ? std::stoi(argv[5]) : 30;
  ros::NodeHandle nh;
  std::vector<double> arrivals;  // wall times of odom arrivals
  bool moving = false;
  ros::Subscriber odom = nh.subscribe<nav_msgs::Odometry>(body + "/odom", 1000, [&](const nav_msgs::Odometry::ConstPtr& m) {
    arrivals.push_back(ros::WallTime::now().toSec());
    const auto& v = m->twist.twist.linear;
    moving = std::abs(v.x) + std::abs(v.y) + std::abs(v.z) > 0.0;
  });
  std::size_t transforms = 0, tf_messages = 0;
  ros::Subscriber tf = nh.subscribe<tf2_msgs::TFMessage>("/tf", 1000, [&](const tf2_msgs::TFMessage::ConstPtr& m) {
    transforms = m->transforms.size();
    ++tf_messages;
  });
  ros::Publisher wrench = nh.advertise<geometry_msgs::WrenchStamped>(body + "/wrench", 10);
  ros::ServiceClient reset = nh.serviceClient<std_srvs::Empty>(reset_service);
  const ros::WallTime connect = ros::WallTime::now();
  while (ros::ok() && (wrench.getNumSubscribers() == 0 || odom.getNumPublishers() == 0 || tf.getNumPublishers() == 0 ||
                       (ros::WallTime::now() - connect).toSec() < 1.0)) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }

  // CPU and jitter, with nothing but the subscriptions.
  arrivals.clear();
  tf_messages = 0;
  const double cpu_start = cpuSecondsOf(pid);
  const ros::WallTime start = ros::WallTime::now();
  while (ros::ok() && (ros::WallTime::now() - start).toSec() < seconds) {
    ros::spinOnce();
    ros::WallDuration(0.0005).sleep();
  }
  const double wall = (ros::WallTime::now() - start).toSec();
  const double cpu = (cpuSecondsOf(pid) - cpu_start) / wall;
  std::vector<double> intervals;
  for (std::size_t i = 1; i < arrivals.size(); ++i) intervals.push_back(arrivals[i] - arrivals[i - 1]);
  const double mean = intervals.empty() ? NAN : std::accumulate(intervals.begin(), intervals.end(), 0.0) / intervals.size();
  std::vector<double> deviation;
  for (double interval : intervals) deviation.push_back(std::abs(interval - mean));
  std::printf("cpu: %.1f %% of one core over %.1f s; odom %.1f Hz, tf %.1f Hz with %zu transforms per message\n",
              100.0 * cpu, wall, intervals.size() / wall, tf_messages / wall, transforms);
  std::printf("timer jitter (odom arrival interval around its mean %.2f ms): median %.3f ms, p99 %.3f ms, max %.3f ms\n",
              1e3 * mean, 1e3 * percentile(deviation, 0.5), 1e3 * percentile(deviation, 0.99),
              1e3 * percentile(deviation, 1.0));

  // Latency trials.
  std::vector<double> latencies;
  geometry_msgs::WrenchStamped push;
  push.header.frame_id = "world";
  push.wrench.force.x = 1.0;
  for (int trial = 0; trial < trials && ros::ok(); ++trial) {
    std_srvs::Empty call;
    if (!reset.call(call)) {
      std::fprintf(stderr, "node_probe: %s failed\n", reset_service.c_str());
      return 1;
    }
    // Wait until an odom after the reset shows the body at rest, then a random phase within the tick.
    moving = true;
    const ros::WallTime settle = ros::WallTime::now();
    while (ros::ok() && (moving || (ros::WallTime::now() - settle).toSec() < 0.05)) {
      ros::spinOnce();
      ros::WallDuration(0.0002).sleep();
    }
    ros::WallDuration(0.001 * (trial % 10)).sleep();
    ros::spinOnce();
    moving = false;
    push.header.stamp = ros::Time::now();
    const ros::WallTime sent = ros::WallTime::now();
    wrench.publish(push);
    while (ros::ok() && !moving && (ros::WallTime::now() - sent).toSec() < 1.0) {
      ros::spinOnce();
      ros::WallDuration(0.0001).sleep();
    }
    if (moving) latencies.push_back((ros::WallTime::now() - sent).toSec());
  }
  std::printf("wrench-to-odom latency over %zu trials: median %.2f ms, p90 %.2f ms, max %.2f ms\n", latencies.size(),
              1e3 * percentile(latencies, 0.5), 1e3 * percentile(latencies, 0.9), 1e3 * percentile(latencies, 1.0));
  return latencies.size() == static_cast<std::size_t>(trials) ? 0 : 1;
}
