// real_time_factor and noise/delay of a lockstep node, seen from outside.
#include <gtest/gtest.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Empty.h>

#include <algorithm>

#include "test_helpers.hpp"

using namespace test_helpers;

TEST(Pacing, SimulatedTimeRunsNoFasterThanTheRealTimeFactor) {
  ros::NodeHandle nh;
  Recorder<rosgraph_msgs::Clock> clock(nh, "/clock");
  ASSERT_TRUE(clock.waitForCount(2));
  const double sim_start = clock.messages.back().clock.toSec();
  const ros::WallTime wall_start = ros::WallTime::now();
  spinFor(1.5);
  const double simulated = clock.messages.back().clock.toSec() - sim_start;
  const double wall = (ros::WallTime::now() - wall_start).toSec();
  // Paced at 2: at most 2 s of simulated time per wall second (plus one publish period of /clock); a node
  // that ignored the factor would run at full speed, tens of times faster. No lower bound on speed: a
  // loaded machine may run slower than the factor, which is allowed.
  EXPECT_LE(simulated, 2.0 * wall + 0.02) << simulated << " s simulated in " << wall << " s";
  EXPECT_GT(simulated, 0.0);  // it runs
}

TEST(Pacing, NoisyOdometryLagsByItsDelay) {
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> truth(nh, "paced/odom"), noisy(nh, "paced/odom_noisy");
  ASSERT_TRUE(truth.waitForCount(20) && noisy.waitForCount(20));
  ros::ServiceClient pause = nh.serviceClient<std_srvs::Empty>("paced/pause");
  std_srvs::Empty call;
  ASSERT_TRUE(pause.call(call));
  spinFor(0.5);  // everything published before the pause arrives
  const auto latest = [](const std::vector<nav_msgs::Odometry>& messages) {
    ros::Time t;
    for (const auto& m : messages) t = std::max(t, m.header.stamp);
    return t.toSec();
  };
  // The noisy copy of stamp s is published once the clock reaches s + 0.05: when the clock stops, the last
  // 5 publications' copies are still held back.
  EXPECT_NEAR(latest(truth.messages) - latest(noisy.messages), 0.05, 1e-9);
  for (const auto& m : noisy.messages) {  // and each is a copy of a true stamp, on the 10 ms grid
    EXPECT_NEAR(std::remainder(m.header.stamp.toSec(), 0.01), 0.0, 1e-9);
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "pacing_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
