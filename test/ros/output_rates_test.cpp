// publish/odom_rate, state_rate and tf at every tick against a lockstep node (output_rates.test): each
// output's stamps on the grid of its own period, served by the first tick at or after each grid point.
#include <gtest/gtest.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "rigid_body_sim/RigidBodyState.h"
#include "test_helpers.hpp"

using namespace test_helpers;

namespace {

constexpr std::int64_t kTick = 10000000;  // 1/rate [ns]

// Stamp k lies within a tick after the k-th point of a grid of P: its lateness against k P, measured from
// the first message received (itself up to a tick late), spans less than a tick; a skipped or doubled
// message moves it by a whole P, and a schedule counted from the tick that served the last one drifts out.
void expectOnGrid(const std::vector<std::int64_t>& stamps, std::int64_t period, const char* what) {
  ASSERT_GE(stamps.size(), 5u) << what;
  std::int64_t earliest = 0, latest = 0;
  for (std::size_t k = 1; k < stamps.size(); ++k) {
    const std::int64_t late = (stamps[k] - stamps[0]) - static_cast<std::int64_t>(k) * period;
    earliest = std::min(earliest, late);
    latest = std::max(latest, late);
    EXPECT_EQ((stamps[k] - stamps[0]) % kTick, 0) << what << ": a stamp off the tick grid";
  }
  EXPECT_LT(latest - earliest, kTick) << what << ": lateness from " << earliest << " to " << latest << " ns";
}

}  // namespace

TEST(OutputRates, EachOutputKeepsItsOwnRateOnTheGridOfSimulatedTime) {
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> odom(nh, "rates/odom");
  Recorder<rigid_body_sim::RigidBodyState> state(nh, "rates/state");
  std::vector<std::int64_t> tf_stamps;
  ros::Subscriber tf = nh.subscribe<tf2_msgs::TFMessage>("/tf", 1000, [&](const tf2_msgs::TFMessage::ConstPtr& m) {
    for (const auto& t : m->transforms) {
      if (t.child_frame_id == "rates_link") tf_stamps.push_back(static_cast<std::int64_t>(t.header.stamp.toNSec()));
    }
  });
  ASSERT_TRUE(odom.waitForConnection());
  ASSERT_TRUE(state.waitForConnection());
  ASSERT_TRUE(waitUntil([&] { return tf.getNumPublishers() > 0; }));
  // About 1.5 s of simulated time at real-time pace: ~45 odometry, ~15 state, ~150 tf messages.
  ASSERT_TRUE(odom.waitForCount(45));
  std::vector<std::int64_t> odom_stamps, state_stamps;
  for (const auto& m : odom.messages) odom_stamps.push_back(static_cast<std::int64_t>(m.header.stamp.toNSec()));
  for (const auto& m : state.messages) state_stamps.push_back(static_cast<std::int64_t>(m.header.stamp.toNSec()));
  expectOnGrid(odom_stamps, 1000000000 / 30, "odom at 30 Hz");
  expectOnGrid(state_stamps, 100000000, "state at 10 Hz");
  expectOnGrid(tf_stamps, kTick, "tf at every tick");
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "output_rates_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
