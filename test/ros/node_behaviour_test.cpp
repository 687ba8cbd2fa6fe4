// The running node, seen from outside as a user sees it: topics, tf, services. Every wait is bounded.
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Empty.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include "rigid_body_sim/RigidBodyState.h"
#include "test_helpers.hpp"

namespace {

using namespace test_helpers;

class NodeBehaviour : public ::testing::Test {
 protected:
  ros::Publisher advertiseWrench(const std::string& ns) {
    ros::Publisher publisher = test_helpers::advertiseWrench(nh_, ns);
    EXPECT_GT(publisher.getNumSubscribers(), 0u) << ns << "/wrench has no subscriber";
    return publisher;
  }
  ros::NodeHandle nh_;
};

}  // namespace

TEST_F(NodeBehaviour, PublishesOdometryAndTfAtTheConfiguredRateWithOneStamp) {
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  Recorder<nav_msgs::Odometry> odom(nh_, "push/odom");
  ASSERT_TRUE(odom.waitForCount(1));
  odom.messages.clear();
  spinFor(2.0);
  const std::vector<nav_msgs::Odometry>& messages = odom.messages;
  ASSERT_GE(messages.size(), 50u);
  // The node runs at rate 50: the stamps advance by 1/50 s on average, strictly increasing.
  for (size_t i = 1; i < messages.size(); ++i) {
    ASSERT_GT(messages[i].header.stamp, messages[i - 1].header.stamp) << i;
  }
  const double span = (messages.back().header.stamp - messages.front().header.stamp).toSec();
  EXPECT_NEAR((messages.size() - 1) / span, 50.0, 2.5);
  // Received at that rate as well (a generous band: the wall clock of a loaded CI machine).
  EXPECT_NEAR(messages.size() / 2.0, 50.0, 10.0);
  EXPECT_EQ(messages.back().header.frame_id, "world");
  EXPECT_EQ(messages.back().child_frame_id, "push_link");

  // tf carries the same pose under the same stamp.
  const nav_msgs::Odometry& last = messages.back();
  ASSERT_TRUE(waitUntil([&] { return buffer.canTransform("world", "push_link", last.header.stamp); }));
  const geometry_msgs::TransformStamped transform = buffer.lookupTransform("world", "push_link", last.header.stamp);
  EXPECT_EQ(transform.header.stamp, last.header.stamp);
  EXPECT_DOUBLE_EQ(transform.transform.translation.x, last.pose.pose.position.x);
  EXPECT_DOUBLE_EQ(transform.transform.rotation.w, last.pose.pose.orientation.w);
}

TEST_F(NodeBehaviour, TfCarriesTheOdometryPoseOfAMovingTurningBodyInAllSevenFields) {
  // The spinner moves along world x at 1 m/s while it spins about body z: every field of the transform must
  // be the odometry's pose at the same stamp (a swapped axis or a stale stamp would differ).
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  Recorder<nav_msgs::Odometry> odom(nh_, "spinner/odom");
  ASSERT_TRUE(odom.waitForCount(30));
  const nav_msgs::Odometry last = odom.messages.back();
  ASSERT_GT(std::abs(last.pose.pose.position.x), 0.1);   // it has moved
  ASSERT_GT(std::abs(last.pose.pose.orientation.z), 0.05);  // and turned
  ASSERT_TRUE(waitUntil([&] { return buffer.canTransform("world", "spinner_link", last.header.stamp); }));
  const geometry_msgs::TransformStamped transform = buffer.lookupTransform("world", "spinner_link", last.header.stamp);
  EXPECT_EQ(transform.header.stamp, last.header.stamp);
  EXPECT_EQ(transform.header.frame_id, last.header.frame_id);
  EXPECT_EQ(transform.child_frame_id, last.child_frame_id);
  const auto& t = transform.transform;
  const auto& p = last.pose.pose;
  EXPECT_EQ(t.translation.x, p.position.x);
  EXPECT_EQ(t.translation.y, p.position.y);
  EXPECT_EQ(t.translation.z, p.position.z);
  EXPECT_EQ(t.rotation.x, p.orientation.x);
  EXPECT_EQ(t.rotation.y, p.orientation.y);
  EXPECT_EQ(t.rotation.z, p.orientation.z);
  EXPECT_EQ(t.rotation.w, p.orientation.w);
}

TEST_F(NodeBehaviour, WorldForceChangesVelocityByForceOverMassTimesTime) {
  Recorder<nav_msgs::Odometry> odom(nh_, "push/odom");
  ros::Publisher publisher = advertiseWrench("push");
  const Eigen::Vector3d force(1.0, 0.0, 0.5);
  const double mass = 2.0;
  publisher.publish(wrench("world", force.x(), force.y(), force.z()));
  // a: the first message whose velocity shows the push; b: one about half a second later.
  ASSERT_TRUE(waitUntil([&] { return !odom.messages.empty() && worldVelocity(odom.messages.back()).x() > 0.0; }));
  const nav_msgs::Odometry a = odom.messages.back();
  nav_msgs::Odometry b;
  ASSERT_TRUE(odom.waitForStampAfter(a.header.stamp + ros::Duration(0.5), b));
  const double dt = (b.header.stamp - a.header.stamp).toSec();
  const Eigen::Vector3d dv = worldVelocity(b) - worldVelocity(a);
  const Eigen::Vector3d expected = force / mass * dt;
  // A constant force between two grid stamps: rk4 integrates it exactly, so only rounding may differ.
  EXPECT_NEAR(dv.x(), expected.x(), 1e-9 * expected.x());
  EXPECT_NEAR(dv.z(), expected.z(), 1e-9 * expected.z());
  EXPECT_NEAR(dv.y(), 0.0, 1e-12);
  publisher.publish(wrench("world", 0.0, 0.0, 0.0));
}

TEST_F(NodeBehaviour, BodyFrameForceOnARotatedBodyShowsUpRotatedInTheWorld) {
  Recorder<nav_msgs::Odometry> odom(nh_, "yawed/odom");
  ros::Publisher publisher = advertiseWrench("yawed");
  const double mass = 0.5, force = 0.25;
  // frame_id = body frame: body axes. The body is yawed by 90°, so body x is world y.
  publisher.publish(wrench("yawed_link", force, 0.0, 0.0));
  ASSERT_TRUE(waitUntil([&] { return !odom.messages.empty() && worldVelocity(odom.messages.back()).y() > 0.0; }));
  const nav_msgs::Odometry a = odom.messages.back();
  nav_msgs::Odometry b;
  ASSERT_TRUE(odom.waitForStampAfter(a.header.stamp + ros::Duration(0.5), b));
  const double dt = (b.header.stamp - a.header.stamp).toSec();
  const Eigen::Vector3d dv = worldVelocity(b) - worldVelocity(a);
  EXPECT_NEAR(dv.y(), force / mass * dt, 1e-9 * force / mass * dt);  // exact but for rounding
  EXPECT_NEAR(dv.x(), 0.0, 1e-9);
  // In body axes the body moves along its own x.
  EXPECT_GT(b.twist.twist.linear.x, 0.0);
  EXPECT_NEAR(b.twist.twist.linear.y, 0.0, 1e-9);
  publisher.publish(wrench("yawed_link", 0.0, 0.0, 0.0));
}

TEST_F(NodeBehaviour, OdometryTwistIsExpressedInTheBodyFrame) {
  Recorder<nav_msgs::Odometry> odom(nh_, "spinner/odom");
  ASSERT_TRUE(odom.waitForCount(1));
  // After about a second the body has yawed by ~0.5 rad while still moving along world x.
  nav_msgs::Odometry late;
  ASSERT_TRUE(odom.waitForStampAfter(odom.messages.front().header.stamp + ros::Duration(1.0), late));
  for (const nav_msgs::Odometry& message : odom.messages) {
    // ω in body axes is the configured (0, 0, 0.5); v turned back into world axes is (1, 0, 0).
    EXPECT_NEAR(message.twist.twist.angular.z, 0.5, 1e-9);
    EXPECT_NEAR(message.twist.twist.angular.x, 0.0, 1e-9);
    EXPECT_TRUE(worldVelocity(message).isApprox(Eigen::Vector3d(1.0, 0.0, 0.0), 1e-9))
        << worldVelocity(message).transpose();
  }
  // The body-axes velocity is (cos ψ, −sin ψ, 0) with yaw ψ = 2 atan2(q_z, q_w): not world axes.
  const double yaw = 2.0 * std::atan2(late.pose.pose.orientation.z, late.pose.pose.orientation.w);
  EXPECT_GT(yaw, 0.4);
  EXPECT_NEAR(late.twist.twist.linear.x, std::cos(yaw), 1e-9);
  EXPECT_NEAR(late.twist.twist.linear.y, -std::sin(yaw), 1e-9);
}

TEST_F(NodeBehaviour, ResetReturnsToTheInitialStateAndKeepsStampsIncreasing) {
  Recorder<nav_msgs::Odometry> odom(nh_, "guarded/odom");
  ros::Publisher publisher = advertiseWrench("guarded");
  publisher.publish(wrench("world", 0.0, 3.0, 0.0));
  ASSERT_TRUE(waitUntil([&] { return !odom.messages.empty() && position(odom.messages.back()).y() > 0.01; }));
  const ros::Time before_reset = odom.messages.back().header.stamp;

  ros::ServiceClient reset = nh_.serviceClient<std_srvs::Empty>("guarded/reset");
  ASSERT_TRUE(reset.waitForExistence(ros::Duration(kWaitLimit)));
  std_srvs::Empty call;
  ASSERT_TRUE(reset.call(call));
  const size_t first_after = odom.messages.size();
  ASSERT_TRUE(odom.waitForCount(first_after + 3));
  // Wrench cleared and state back to the initial one: at rest at (0, 0, 1).
  const nav_msgs::Odometry& after = odom.messages.back();
  EXPECT_EQ(position(after), Eigen::Vector3d(0.0, 0.0, 1.0));
  EXPECT_EQ(worldVelocity(after), Eigen::Vector3d::Zero());
  EXPECT_GT(after.header.stamp, before_reset);
  for (size_t i = 1; i < odom.messages.size(); ++i) {
    ASSERT_GT(odom.messages[i].header.stamp, odom.messages[i - 1].header.stamp) << i;
  }
}

// A counter of the guarded node's diagnostics, once it is reported.
long guardedCounter(Diagnostics& diagnostics, const std::string& key) {
  long value = -1;
  EXPECT_TRUE(diagnostics.waitFor("guarded_link", [&](const diagnostic_msgs::DiagnosticStatus& s) {
    const std::string text = Diagnostics::value(s, key);
    if (text.empty()) return false;
    value = std::stol(text);
    return true;
  }));
  return value;
}

TEST_F(NodeBehaviour, NonFiniteWrenchIsRejectedAndTheNodeKeepsPublishing) {
  Diagnostics diagnostics(nh_);
  const long rejected_before = guardedCounter(diagnostics, "rejected non_finite");
  const long applied_before = guardedCounter(diagnostics, "wrenches applied");
  Recorder<nav_msgs::Odometry> odom(nh_, "guarded/odom");
  ros::Publisher publisher = advertiseWrench("guarded");
  ros::ServiceClient reset = nh_.serviceClient<std_srvs::Empty>("guarded/reset");
  std_srvs::Empty call;
  ASSERT_TRUE(reset.call(call));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  publisher.publish(wrench("world", nan, 0.0, 0.0));
  publisher.publish(wrench("guarded_link", 0.0, inf, 0.0));
  geometry_msgs::WrenchStamped torque = wrench("world", 0.0, 0.0, 0.0);
  torque.wrench.torque.z = nan;
  publisher.publish(torque);
  ASSERT_TRUE(odom.waitForCount(1));
  const size_t count = odom.messages.size();
  ASSERT_TRUE(odom.waitForCount(count + 25));  // alive: half a second more of odometry
  for (const nav_msgs::Odometry& message : odom.messages) {
    ASSERT_TRUE(allFinite(message));
  }
  // Nothing of the rejected wrenches reached the state: still at rest where reset put it.
  EXPECT_EQ(worldVelocity(odom.messages.back()), Eigen::Vector3d::Zero());
  EXPECT_EQ(position(odom.messages.back()), Eigen::Vector3d(0.0, 0.0, 1.0));
  // They arrived, and were rejected for what they are: three counted, none applied.
  EXPECT_TRUE(diagnostics.waitFor("guarded_link", [&](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "rejected non_finite") == std::to_string(rejected_before + 3) &&
           Diagnostics::value(s, "wrenches applied") == std::to_string(applied_before);
  }));
}

TEST_F(NodeBehaviour, WrenchInATfFrameGetsItsMomentArmAndAnUnknownFrameIsRejected) {
  Recorder<rigid_body_sim::RigidBodyState> state(nh_, "guarded/state");
  ros::Publisher publisher = advertiseWrench("guarded");
  ros::ServiceClient reset = nh_.serviceClient<std_srvs::Empty>("guarded/reset");
  std_srvs::Empty call;
  ASSERT_TRUE(reset.call(call));

  // A frame nobody publishes: rejected and counted, the body stays at rest.
  Diagnostics diagnostics(nh_);
  const long unknown_before = guardedCounter(diagnostics, "rejected unknown_frame");
  publisher.publish(wrench("no_such_frame", 1.0, 0.0, 0.0));
  ASSERT_TRUE(state.waitForCount(25));
  EXPECT_EQ(state.messages.back().linear_momentum.x, 0.0);
  EXPECT_TRUE(diagnostics.waitFor("guarded_link", [&](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "rejected unknown_frame") == std::to_string(unknown_before + 1);
  }));

  // "lever": 0.5 m along world +y from the body's centre (0, 0, 1), axes turned 90° about z.
  tf2_ros::StaticTransformBroadcaster static_broadcaster;
  geometry_msgs::TransformStamped lever;
  lever.header.stamp = ros::Time::now();
  lever.header.frame_id = "world";
  lever.child_frame_id = "lever";
  lever.transform.translation.y = 0.5;
  lever.transform.translation.z = 1.0;
  lever.transform.rotation = tf2::toMsg(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())));
  static_broadcaster.sendTransform(lever);
  spinFor(0.5);  // let the node's tf listener receive it
  // Force along lever x = world y... would have no moment arm; along lever −y = world +x it has:
  // τ = (0, 0.5, 0) × (1, 0, 0) = (0, 0, −0.5) N m.
  geometry_msgs::WrenchStamped push = wrench("lever", 0.0, -1.0, 0.0);
  push.header.stamp = ros::Time(0);  // "latest transform"
  publisher.publish(push);
  ASSERT_TRUE(waitUntil([&] { return !state.messages.empty() && state.messages.back().linear_momentum.x > 0.0; }));
  const rigid_body_sim::RigidBodyState a = state.messages.back();
  rigid_body_sim::RigidBodyState b;
  ASSERT_TRUE(state.waitForStampAfter(a.header.stamp + ros::Duration(0.3), b));
  const double dt = (b.header.stamp - a.header.stamp).toSec();
  // Constant force and torque (the arm was taken when the wrench began to act): exact but for rounding.
  EXPECT_NEAR(b.linear_momentum.x - a.linear_momentum.x, 1.0 * dt, 1e-9 * dt);
  EXPECT_NEAR(b.angular_momentum.z - a.angular_momentum.z, -0.5 * dt, 1e-9 * 0.5 * dt);
  EXPECT_NEAR(b.applied_wrench.torque.z, -0.5, 1e-12);
  publisher.publish(wrench("world", 0.0, 0.0, 0.0));
}

TEST_F(NodeBehaviour, AWrenchInAFrameBelowTheBodyTurnsWithTheBody) {
  // "thruster" hangs below thrust_link, 0.5 m along body x: a force along its y is fixed in the body,
  // F_B = (0, 1, 0), with the fixed lever arm τ_B = (0.5, 0, 0) × (0, 1, 0) = (0, 0, 0.5) N m. While the
  // sphere spins about z, the world force must turn with it: F_W = R(q) F_B in every state message.
  Recorder<rigid_body_sim::RigidBodyState> state(nh_, "thruster/state");
  ros::Publisher publisher = advertiseWrench("thruster");
  tf2_ros::StaticTransformBroadcaster static_broadcaster;
  geometry_msgs::TransformStamped mount;
  mount.header.stamp = ros::Time::now();
  mount.header.frame_id = "thrust_link";
  mount.child_frame_id = "thruster";
  mount.transform.translation.x = 0.5;
  mount.transform.rotation.w = 1.0;
  static_broadcaster.sendTransform(mount);
  spinFor(0.5);  // let the node's tf listener receive it
  publisher.publish(wrench("thruster", 0.0, 1.0, 0.0));
  ASSERT_TRUE(waitUntil([&] { return !state.messages.empty() && state.messages.back().applied_wrench.force.y != 0.0; }));
  const std::size_t first = state.messages.size() - 1;
  ASSERT_TRUE(state.waitForCount(first + 40));  // 0.4 s at 100 Hz: the body turns by more than 0.8 rad
  Eigen::Vector3d first_force_W = Eigen::Vector3d::Zero();
  for (std::size_t i = first; i < state.messages.size(); ++i) {
    const rigid_body_sim::RigidBodyState& m = state.messages[i];
    Eigen::Quaterniond q;
    tf2::fromMsg(m.pose.orientation, q);
    Eigen::Vector3d force_W, torque_W;
    tf2::fromMsg(m.applied_wrench.force, force_W);
    tf2::fromMsg(m.applied_wrench.torque, torque_W);
    EXPECT_LT((force_W - q * Eigen::Vector3d(0.0, 1.0, 0.0)).norm(), 1e-9) << i;
    EXPECT_LT((torque_W - q * Eigen::Vector3d(0.0, 0.0, 0.5)).norm(), 1e-9) << i;
    if (i == first) first_force_W = force_W;
  }
  // And it did turn: a world-held force would have kept its first direction.
  Eigen::Vector3d last_force_W;
  tf2::fromMsg(state.messages.back().applied_wrench.force, last_force_W);
  EXPECT_GT(std::acos(std::min(1.0, first_force_W.dot(last_force_W))), 0.5);
  publisher.publish(wrench("world", 0.0, 0.0, 0.0));
}

TEST_F(NodeBehaviour, Dopri5UnderAWrenchChangingWithEveryMessageStaysExactWhereThePhysicsIs) {
  // A world force of 1 N along x on 2 kg, with a torque that flips sign with every message: each message
  // changes the input and restarts dopri5 from the current state. The translation is a constant acceleration
  // whatever the torque does, which dopri5 integrates exactly: Δv = F/M Δt between two stamps.
  Recorder<nav_msgs::Odometry> odom(nh_, "adaptive/odom");
  ros::Publisher publisher = advertiseWrench("adaptive");
  ros::Rate rate(200.0);
  nav_msgs::Odometry a;
  bool have_a = false;
  for (int i = 0; i < 200 && ros::ok(); ++i) {  // 1 s
    geometry_msgs::WrenchStamped message = wrench("world", 1.0, 0.0, 0.0);
    message.wrench.torque.z = i % 2 ? 0.01 : -0.01;
    publisher.publish(message);
    ros::spinOnce();
    if (!have_a && !odom.messages.empty() && worldVelocity(odom.messages.back()).x() > 0.0) {
      a = odom.messages.back();
      have_a = true;
    }
    rate.sleep();
  }
  ASSERT_TRUE(have_a);
  const nav_msgs::Odometry b = odom.messages.back();
  const double dt = (b.header.stamp - a.header.stamp).toSec();
  ASSERT_GT(dt, 0.5);
  EXPECT_NEAR(worldVelocity(b).x() - worldVelocity(a).x(), 0.5 * dt, 1e-9);
  for (const auto& message : odom.messages) ASSERT_TRUE(allFinite(message));
  publisher.publish(wrench("world", 0.0, 0.0, 0.0));
}

TEST_F(NodeBehaviour, WrenchDropsToZeroAfterTheTimeout) {
  Recorder<nav_msgs::Odometry> odom(nh_, "timed/odom");
  ros::Publisher publisher = advertiseWrench("timed");
  publisher.publish(wrench("world", 2.0, 0.0, 0.0));
  ASSERT_TRUE(waitUntil([&] { return !odom.messages.empty() && worldVelocity(odom.messages.back()).x() > 0.0; }));
  const ros::Time pushed = odom.messages.back().header.stamp;
  nav_msgs::Odometry later;
  ASSERT_TRUE(odom.waitForStampAfter(pushed + ros::Duration(0.5), later));
  // The wrench acted for wrench_timeout = 0.2 s: Δv = F/M · 0.2 = 0.4 m/s, to within one 1 ms step.
  EXPECT_NEAR(worldVelocity(later).x(), 0.4, 2.0 * 0.001 * 2.0);
  nav_msgs::Odometry latest;
  ASSERT_TRUE(odom.waitForStampAfter(later.header.stamp + ros::Duration(0.1), latest));
  EXPECT_EQ(worldVelocity(latest).x(), worldVelocity(later).x());  // no longer accelerating
}

TEST_F(NodeBehaviour, PublishClockOutsideLockstepStampsEveryOutputWithAClockValue) {
  // Catches a node that publishes no /clock outside lockstep, one behind or ahead of its outputs, and one
  // whose /clock goes backwards or repeats.
  std::vector<ros::Time> clock;
  ros::Subscriber clock_subscriber = nh_.subscribe<rosgraph_msgs::Clock>(
      "/clock", 1000, [&](const rosgraph_msgs::Clock::ConstPtr& m) { clock.push_back(m->clock); });
  Recorder<nav_msgs::Odometry> odom(nh_, "clocked/odom");
  ASSERT_TRUE(odom.waitForConnection());
  ASSERT_TRUE(waitUntil([&] { return clock_subscriber.getNumPublishers() > 0; }));
  ASSERT_TRUE(waitUntil([&] { return odom.messages.size() >= 20 && clock.size() >= 20; }));
  for (std::size_t k = 1; k < clock.size(); ++k) EXPECT_LT(clock[k - 1], clock[k]) << k;
  // Each odometry stamp (after the first /clock received) is a /clock value: the clock goes out first.
  std::size_t matched = 0;
  for (const auto& m : odom.messages) {
    if (m.header.stamp < clock.front()) continue;
    EXPECT_TRUE(std::binary_search(clock.begin(), clock.end(), m.header.stamp)) << m.header.stamp;
    ++matched;
  }
  EXPECT_GE(matched, 10u);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_behaviour_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
