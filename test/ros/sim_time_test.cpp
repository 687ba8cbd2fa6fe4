// The node on simulated time: this test owns /clock and moves it forward, back and far forward.
#include <gtest/gtest.h>
#include <rosgraph_msgs/Clock.h>

#include "rigid_body_sim/GetState.h"

#include "test_helpers.hpp"

using namespace test_helpers;

namespace {

class SimTime : public ::testing::Test {
 protected:
  SimTime() : clock_publisher_(nh_.advertise<rosgraph_msgs::Clock>("/clock", 10)) {}

  void publishClock(double t) {
    rosgraph_msgs::Clock clock;
    clock.clock = ros::Time(t);
    clock_publisher_.publish(clock);
    now_ = t;
  }

  // Moves the clock from now_ to `until` in steps of 10 ms, giving the node's timer a moment at each.
  void advanceClock(double until) {
    while (now_ < until - 1e-9) {
      publishClock(now_ + 0.01);
      spinFor(0.002);
    }
  }

  ros::NodeHandle nh_;
  ros::Publisher clock_publisher_;
  double now_ = 0.0;
};

}  // namespace

TEST_F(SimTime, StampsFollowTheDrivenClockAndTimeJumpsAreHandled) {
  Diagnostics diagnostics(nh_);
  Recorder<nav_msgs::Odometry> odom(nh_, "clocked/odom");
  // The node waits for the first /clock; t = 100 s is its start.
  ASSERT_TRUE(waitUntil([&] {
    publishClock(100.0);
    return clock_publisher_.getNumSubscribers() > 0 && odom.messages.empty();
  }));
  spinFor(0.5);  // the node starts its clock at 100 s
  advanceClock(102.0);
  ASSERT_GE(odom.messages.size(), 50u);
  for (size_t i = 0; i < odom.messages.size(); ++i) {
    const double stamp = odom.messages[i].header.stamp.toSec();
    // On the dt grid from the start, within the sim time driven so far.
    EXPECT_NEAR(std::remainder(stamp - 100.0, 0.01), 0.0, 1e-6) << stamp;
    EXPECT_LE(stamp, 102.0 + 1e-9);
    EXPECT_GE(stamp, 100.0);
    if (i > 0) {
      ASSERT_GT(odom.messages[i].header.stamp, odom.messages[i - 1].header.stamp) << i;
    }
  }

  // F/M·Δt in sim time: 1 N on 2 kg.
  ros::Publisher publisher = advertiseWrench(nh_, "clocked");
  publisher.publish(wrench("world", 1.0, 0.0, 0.0));
  spinFor(0.1);
  advanceClock(102.2);
  const nav_msgs::Odometry a = odom.messages.back();
  advanceClock(103.2);
  const nav_msgs::Odometry b = odom.messages.back();
  const double dt = (b.header.stamp - a.header.stamp).toSec();
  EXPECT_GT(dt, 0.9);
  EXPECT_NEAR(worldVelocity(b).x() - worldVelocity(a).x(), 0.5 * dt, 1e-9);
  publisher.publish(wrench("world", 0.0, 0.0, 0.0));
  spinFor(0.1);
  advanceClock(103.4);

  // Backwards (a looping bag): re-anchored, counted, the body keeps its state, stamps follow the new time.
  const Eigen::Vector3d before_jump = position(odom.messages.back());
  const size_t count = odom.messages.size();
  publishClock(50.0);
  spinFor(0.1);
  advanceClock(51.0);
  ASSERT_GT(odom.messages.size(), count + 10);
  // Messages published before the jump may still arrive after it: start at the first one in the new time.
  size_t first_after = count;
  while (first_after < odom.messages.size() && odom.messages[first_after].header.stamp.toSec() > 100.0) ++first_after;
  ASSERT_LT(first_after + 10, odom.messages.size());
  for (size_t i = first_after; i < odom.messages.size(); ++i) {
    const double stamp = odom.messages[i].header.stamp.toSec();
    EXPECT_GE(stamp, 50.0);
    EXPECT_LE(stamp, 51.0 + 1e-9);
    if (i > first_after) {
      ASSERT_GT(odom.messages[i].header.stamp, odom.messages[i - 1].header.stamp) << i;
    }
  }
  // Continuous: after a second at constant velocity the body is about v·1 s further, not back at the start.
  const double v = worldVelocity(odom.messages.back()).x();
  EXPECT_NEAR(position(odom.messages.back()).x() - before_jump.x(), v * 1.0, 0.1 * v + 0.02);
  EXPECT_TRUE(diagnostics.waitFor("clocked_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "backward time jumps") == "1";
  }, 3.0));

  // Forward by 100 s in one tick: at most max_substeps = 50 steps, the other 9950 dropped and counted.
  publishClock(now_ + 100.0);
  spinFor(0.2);
  advanceClock(now_ + 2.0);  // lets diagnostics (1 s period in sim time) report
  EXPECT_TRUE(diagnostics.waitFor("clocked_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    const std::string dropped = Diagnostics::value(s, "dropped steps");
    return !dropped.empty() && std::stoll(dropped) >= 9900 && Diagnostics::value(s, "max substeps in one tick") == "50";
  }, 5.0));
  EXPECT_NEAR(odom.messages.back().header.stamp.toSec(), now_, 0.05);  // publishing at the new time

  // Past 2^31 s, where ros::Duration arithmetic would throw: the node goes on, stamps follow the clock.
  publishClock(3e9);
  spinFor(0.2);
  advanceClock(3e9 + 0.5);
  EXPECT_NEAR(odom.messages.back().header.stamp.toSec(), 3e9 + 0.5, 0.05);
  // Toward the end of ROS time (2^32 s): the clock stops a margin before it (two timer periods + 10 s, here
  // 10.04 s), the node says so in its diagnostics and still answers; it does not abort.
  const double end = 4294967295.0 - 10.04;
  publishClock(end - 2.0);
  spinFor(0.2);
  advanceClock(end + 3.0);
  EXPECT_TRUE(diagnostics.waitFor("clocked_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return s.level == diagnostic_msgs::DiagnosticStatus::ERROR && s.message.find("end of") != std::string::npos;
  }, 5.0));
  const double last = odom.messages.back().header.stamp.toSec();
  EXPECT_GE(last, end - 0.05);
  EXPECT_LE(last, end + 1.0);
  ros::ServiceClient get_state = nh_.serviceClient<rigid_body_sim::GetState>("clocked/get_state");
  rigid_body_sim::GetState state;
  ASSERT_TRUE(get_state.call(state));
  EXPECT_NEAR(state.response.stamp.toSec(), last, 1e-6);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "sim_time_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
