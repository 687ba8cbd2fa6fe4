// rigid_body_sim/LockstepNodeletProbe (not a test; run by scripts/lockstep_nodelet_speed.sh): an in-process
// subscriber in the simulator's manager that reads every odometry message of one body (an unbounded queue),
// and after ~seconds of wall time from its first message writes one line to ~output: simulated seconds per wall
// second (from the odometry stamps), the messages received against those the stamps say were sent (at
// ~period of simulated time), and the manager's CPU share.
//
// Parameters: ~seconds (10), ~period [s] (0.01: outputs at 100 Hz), ~output (a file path). Topic: odom.
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "process_cpu.hpp"

namespace rigid_body_bench {

class LockstepNodeletProbe : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& private_nh = getPrivateNodeHandle();
    private_nh.param("seconds", seconds_, 10.0);
    private_nh.param("period", period_, 0.01);
    private_nh.param("output", output_, std::string("/dev/stdout"));
    // Queue size 0: unbounded, so that a message the probe is late for waits instead of being dropped.
    subscriber_ = getNodeHandle().subscribe("odom", 0, &LockstepNodeletProbe::onOdometry, this);
  }

  void onOdometry(const nav_msgs::Odometry::ConstPtr& odom) {
    const double stamp = odom->header.stamp.toSec();
    if (received_ == 0) {
      first_stamp_ = stamp;
      start_ = ros::WallTime::now();
      cpu_start_ = cpuSecondsOf(getpid());
    }
    ++received_;
    last_stamp_ = stamp;
    const double wall = (ros::WallTime::now() - start_).toSec();
    if (wall < seconds_ || done_) return;
    done_ = true;
    subscriber_.shutdown();
    const double simulated = last_stamp_ - first_stamp_;
    const long sent = std::lround(simulated / period_) + 1;
    const double cpu = (cpuSecondsOf(getpid()) - cpu_start_) / wall;
    if (std::FILE* file = std::fopen(output_.c_str(), "w")) {
      std::fprintf(file,
                   "%.1f s simulated in %.1f s wall: %.0fx real time; odom read in process: %ld of %ld sent; "
                   "manager cpu %.1f %% of one core\n",
                   simulated, wall, simulated / wall, received_, sent, 100.0 * cpu);
      std::fclose(file);
    }
  }

  double seconds_ = 10.0, period_ = 0.01;
  std::string output_;
  ros::Subscriber subscriber_;
  long received_ = 0;
  bool done_ = false;
  double first_stamp_ = 0.0, last_stamp_ = 0.0, cpu_start_ = 0.0;
  ros::WallTime start_;
};

}  // namespace rigid_body_bench

PLUGINLIB_EXPORT_CLASS(rigid_body_bench::LockstepNodeletProbe, nodelet::Nodelet)
