// The fault suite, seen from outside: over-limit and oddly stamped wrenches, an overflowing momentum and a
// blow-up scene. Each case asserts what reaches odometry and what /diagnostics says.
#include <gtest/gtest.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>

#include "test_helpers.hpp"

using namespace test_helpers;

namespace {

bool isLevel(const diagnostic_msgs::DiagnosticStatus& status, unsigned char level) { return status.level == level; }

}  // namespace

TEST(Faults, OverLimitWrenchesAreRejectedCountedAndLeaveTheStateAlone) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  Recorder<nav_msgs::Odometry> odom(nh, "limited/odom");
  ros::Publisher publisher = advertiseWrench(nh, "limited");
  publisher.publish(wrench("world", 20.0, 0.0, 0.0));  // |F| = 20 > max_force = 10
  geometry_msgs::WrenchStamped twist_hard = wrench("world", 0.0, 0.0, 0.0);
  twist_hard.wrench.torque.z = 2.0;                    // |τ| = 2 > max_torque = 1
  publisher.publish(twist_hard);
  ASSERT_TRUE(diagnostics.waitFor("limited_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "rejected force_over_limit") == "1" &&
           Diagnostics::value(s, "rejected torque_over_limit") == "1";
  }));
  ASSERT_TRUE(odom.waitForCount(10));
  EXPECT_EQ(worldVelocity(odom.messages.back()), Eigen::Vector3d::Zero());
  EXPECT_EQ(odom.messages.back().twist.twist.angular.z, 0.0);
  // Within the limits: applied.
  publisher.publish(wrench("world", 5.0, 0.0, 0.0));
  EXPECT_TRUE(waitUntil([&] { return worldVelocity(odom.messages.back()).x() > 0.0; }));
  EXPECT_TRUE(diagnostics.waitFor("limited_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "wrenches applied") == "1";
  }));
}

TEST(Faults, StaleAndFutureStampsAreAppliedAtArrival) {
  // Documented: a world- or body-frame wrench acts from its arrival whatever its stamp (rostopic pub stamps
  // with wall time, a bag with its own): the stamp only picks the transform of a foreign frame.
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> odom(nh, "stamps/odom");
  ros::Publisher publisher = advertiseWrench(nh, "stamps");
  geometry_msgs::WrenchStamped stale = wrench("world", 1.0, 0.0, 0.0);
  stale.header.stamp = ros::Time::now() - ros::Duration(100.0);
  publisher.publish(stale);
  ASSERT_TRUE(waitUntil([&] { return !odom.messages.empty() && worldVelocity(odom.messages.back()).x() > 0.0; }));
  geometry_msgs::WrenchStamped future = wrench("world", 0.0, 0.0, 0.0);
  future.header.stamp = ros::Time::now() + ros::Duration(100.0);
  publisher.publish(future);
  spinFor(0.3);
  const double v = worldVelocity(odom.messages.back()).x();
  spinFor(0.3);
  EXPECT_EQ(worldVelocity(odom.messages.back()).x(), v);  // the zero wrench took effect: no more acceleration
}

TEST(Faults, AnOverflowingMomentumLatchesTheLastGoodStateAndResetRecovers) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  Recorder<nav_msgs::Odometry> odom(nh, "overflow/odom");
  ros::Publisher publisher = advertiseWrench(nh, "overflow");
  publisher.publish(wrench("world", 1e308, 0.0, 0.0));  // finite, accepted with no limit set
  ASSERT_TRUE(diagnostics.waitFor("overflow_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return isLevel(s, diagnostic_msgs::DiagnosticStatus::ERROR) &&
           Diagnostics::value(s, "divergence") == "non-finite state";
  }));
  const size_t count = odom.messages.size();
  ASSERT_TRUE(odom.waitForCount(count + 10));  // still publishing
  for (const auto& message : odom.messages) ASSERT_TRUE(allFinite(message));
  EXPECT_GT(worldVelocity(odom.messages.back()).x(), 1e300);  // the last good state, huge but finite

  ros::ServiceClient reset = nh.serviceClient<std_srvs::Empty>("overflow/reset");
  std_srvs::Empty call;
  ASSERT_TRUE(reset.call(call));
  EXPECT_TRUE(diagnostics.waitFor("overflow_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return !isLevel(s, diagnostic_msgs::DiagnosticStatus::ERROR) && Diagnostics::value(s, "divergence") == "none";
  }));
  const size_t after = odom.messages.size();
  ASSERT_TRUE(odom.waitForCount(after + 3));
  EXPECT_EQ(worldVelocity(odom.messages.back()), Eigen::Vector3d::Zero());
}

TEST(Faults, ABlowUpSceneIsCaughtAndNeverReachesTheWire) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  Recorder<nav_msgs::Odometry> odom(nh, "blowup/odom");
  ASSERT_TRUE(diagnostics.waitFor("blowup_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return isLevel(s, diagnostic_msgs::DiagnosticStatus::ERROR) &&
           Diagnostics::value(s, "divergence") == "energy growth beyond max_energy_growth";
  }));
  ASSERT_TRUE(odom.waitForCount(5));
  for (const auto& message : odom.messages) {
    ASSERT_TRUE(allFinite(message));
    // The last good state is the initial one: ω_B = (100, 5, 0), as configured.
    EXPECT_NEAR(message.twist.twist.angular.x, 100.0, 1e-9);
    EXPECT_NEAR(message.twist.twist.angular.y, 5.0, 1e-9);
  }
}

TEST(Faults, AStreamOfUnknownFramesIsRejectedAtOnceAndTheRateHolds) {
  // 200 wrenches a second in frames tf2 does not know, stamped now (the case a waiting lookup would block
  // on): every one is rejected and counted, the body does not move, and odometry keeps its 100 Hz. A frame
  // with a leading '/' is the frame without it.
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  Recorder<nav_msgs::Odometry> odom(nh, "stream/odom");
  ros::Publisher publisher = advertiseWrench(nh, "stream");
  ASSERT_TRUE(odom.waitForCount(5));
  const std::size_t first = odom.messages.size();
  int sent = 0;
  ros::Rate rate(200.0);
  for (int i = 0; i < 600; ++i) {  // 3 s
    geometry_msgs::WrenchStamped message = wrench(i % 2 ? "/no_such_frame_" + std::to_string(i % 7) : "ghost", 1.0, 0.0, 0.0);
    message.header.stamp = ros::Time::now();
    publisher.publish(message);
    ++sent;
    ros::spinOnce();
    rate.sleep();
  }
  ASSERT_TRUE(odom.waitForCount(first + 10));
  const auto& early = odom.messages[first];
  const auto& late = odom.messages.back();
  const double span = (late.header.stamp - early.header.stamp).toSec();
  const double hz = static_cast<double>(odom.messages.size() - 1 - first) / span;
  EXPECT_GT(hz, 90.0) << odom.messages.size() - first << " messages over " << span << " s";
  EXPECT_LT(hz, 110.0);
  EXPECT_EQ(worldVelocity(late), Eigen::Vector3d::Zero());
  ASSERT_TRUE(diagnostics.waitFor("stream_link", [&](const diagnostic_msgs::DiagnosticStatus& s) {
    const std::string value = Diagnostics::value(s, "rejected unknown_frame");
    return !value.empty() && std::stoi(value) >= sent * 9 / 10 && std::stoi(value) <= sent &&
           Diagnostics::value(s, "wrenches applied") == "0";
  }));
  // "/world" is the world frame: accepted.
  publisher.publish(wrench("/world", 1.0, 0.0, 0.0));
  EXPECT_TRUE(waitUntil([&] { return worldVelocity(odom.messages.back()).x() > 0.0; }));
}

TEST(Faults, TransformsStampedAtTheEndOfRosTimeAreRefusedAndEveryNodeGoesOn) {
  // tf2's cache adds its storage time to a stamp, and ros::Time throws past 2^32 s: a foreign /tf stamped
  // there must be refused, not end the node (every node of this suite listens to /tf; all are required).
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> odom(nh, "stamps/odom");
  ros::Publisher tf = nh.advertise<tf2_msgs::TFMessage>("/tf", 10);
  ASSERT_TRUE(waitUntil([&] { return tf.getNumSubscribers() >= 5; }));
  ASSERT_TRUE(odom.waitForCount(5));
  for (const std::uint32_t seconds : {4294967295u, 4294967290u, 4294967000u}) {
    tf2_msgs::TFMessage message;
    geometry_msgs::TransformStamped transform;
    transform.header.frame_id = "late_parent";
    transform.child_frame_id = "late_child";
    transform.header.stamp = ros::Time(seconds, 999999999u);
    transform.transform.rotation.w = 1.0;
    message.transforms = {transform, transform};
    tf.publish(message);
  }
  const std::size_t before = odom.messages.size();
  spinFor(1.0);
  EXPECT_TRUE(odom.waitForCount(before + 20));
}

TEST(Faults, DiagnosticsReportTheNodesState) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  EXPECT_TRUE(diagnostics.waitFor("limited_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "integrator") == "rk4" && Diagnostics::value(s, "dt [s]") == "0.001" &&
           !Diagnostics::value(s, "energy change since reset [J]").empty() &&
           !Diagnostics::value(s, "max ||q| - 1| since reset").empty() &&
           Diagnostics::value(s, "timer overruns") != "" && Diagnostics::value(s, "wrench timed out") == "false";
  }));
  // The publish-rate status of diagnostic_updater's FrequencyStatus.
  EXPECT_TRUE(diagnostics.waitFor("limited", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return s.name.find("Frequency") != std::string::npos && !Diagnostics::value(s, "Actual frequency (Hz)").empty();
  }));
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "faults_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
