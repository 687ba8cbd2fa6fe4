// A multi-body scene seen from outside: topics per body, one tf message for all, independence of the bodies.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <algorithm>
#include <set>
#include <string>

#include "rigid_body_sim/BodyStates.h"
#include "rigid_body_sim/BodyWrenches.h"
#include "rigid_body_sim/OdometryArray.h"
#include "test_helpers.hpp"

namespace {

using namespace test_helpers;

// Topics with a publisher (role 0) or a subscriber (role 1) on the master, from getSystemState.
std::set<std::string> topicsWith(int role) {
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  std::set<std::string> topics;
  if (!ros::master::execute("getSystemState", request, response, payload, true)) return topics;
  for (int i = 0; i < payload[role].size(); ++i) topics.insert(static_cast<std::string>(payload[role][i][0]));
  return topics;
}

}  // namespace

TEST(Scene, EachBodyHasItsTopicsAndOnlyTheEnabledOnes) {
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> box(nh, "scene/box/odom");
  ASSERT_TRUE(box.waitForCount(1));
  const std::set<std::string> published = topicsWith(0);
  const std::set<std::string> subscribed = topicsWith(1);
  for (const std::string body : {"box", "ball", "drifter"}) {
    EXPECT_TRUE(published.count("/scene/" + body + "/odom")) << body;
    EXPECT_TRUE(published.count("/scene/" + body + "/applied_wrench")) << body;
    EXPECT_FALSE(published.count("/scene/" + body + "/state")) << body << ": publish/state is false";
  }
  EXPECT_TRUE(subscribed.count("/scene/box/wrench"));
  EXPECT_TRUE(subscribed.count("/scene/ball/wrench"));
  EXPECT_FALSE(subscribed.count("/scene/drifter/wrench")) << "a body without wrench input has no subscriber";
  EXPECT_EQ(box.messages.back().child_frame_id, "box");
  Recorder<nav_msgs::Odometry> ball(nh, "scene/ball/odom");
  ASSERT_TRUE(ball.waitForCount(1));
  EXPECT_EQ(ball.messages.back().child_frame_id, "ball_link");
}

TEST(Scene, AllBodiesGoOutInOneTfMessagePerTick) {
  ros::NodeHandle nh;
  Recorder<tf2_msgs::TFMessage> tf(nh, "/tf");
  // Every node of this launch file publishes /tf: this node's messages start with its box.
  const auto fromScene = [](const tf2_msgs::TFMessage& m) {
    return !m.transforms.empty() && m.transforms[0].child_frame_id == "box";
  };
  ASSERT_TRUE(waitUntil([&] { return std::count_if(tf.messages.begin(), tf.messages.end(), fromScene) >= 5; }));
  int from_scene = 0;
  for (const tf2_msgs::TFMessage& message : tf.messages) {
    if (!fromScene(message)) continue;
    ++from_scene;
    ASSERT_EQ(message.transforms.size(), 3u);
    EXPECT_EQ(message.transforms[0].child_frame_id, "box");
    EXPECT_EQ(message.transforms[1].child_frame_id, "ball_link");
    EXPECT_EQ(message.transforms[2].child_frame_id, "drifter");
    for (const auto& transform : message.transforms) {
      EXPECT_EQ(transform.header.frame_id, "world");
      EXPECT_EQ(transform.header.stamp, message.transforms[0].header.stamp);
    }
  }
  EXPECT_GE(from_scene, 3);
}

TEST(Scene, EachBodyMovesOnlyUnderItsOwnWrench) {
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> box(nh, "scene/box/odom"), ball(nh, "scene/ball/odom"), drifter(nh, "scene/drifter/odom");
  ASSERT_TRUE(box.waitForCount(1) && ball.waitForCount(1) && drifter.waitForCount(1));
  ros::Publisher push = advertiseWrench(nh, "scene/box");
  const nav_msgs::Odometry drifter_before = drifter.messages.back();
  push.publish(wrench("world", 4.0, 0.0, 0.0));  // 2 m/s^2 on the 2 kg box
  ASSERT_TRUE(waitUntil([&] { return worldVelocity(box.messages.back()).x() > 0.0; }));
  const nav_msgs::Odometry a = box.messages.back();
  nav_msgs::Odometry b;
  ASSERT_TRUE(box.waitForStampAfter(a.header.stamp + ros::Duration(0.3), b));
  // 2 m/s² between two grid stamps: v and x of a constant acceleration, which rk4 integrates exactly.
  const double t = (b.header.stamp - a.header.stamp).toSec(), v_a = worldVelocity(a).x();
  EXPECT_NEAR(worldVelocity(b).x() - v_a, 2.0 * t, 1e-9);
  EXPECT_NEAR(position(b).x() - position(a).x(), v_a * t + 0.5 * 2.0 * t * t, 1e-9);
  EXPECT_NEAR(position(b).y(), position(a).y(), 1e-12);
  // The ball took no wrench and has no velocity: it has not moved at all.
  EXPECT_EQ(position(ball.messages.back()), Eigen::Vector3d(2.0, 0.0, 0.0));
  EXPECT_EQ(worldVelocity(ball.messages.back()), Eigen::Vector3d::Zero());
  // The drifter keeps its own constant velocity (no gravity in this scene), untouched by the push.
  const nav_msgs::Odometry& now = drifter.messages.back();
  const double elapsed = (now.header.stamp - drifter_before.header.stamp).toSec();
  EXPECT_NEAR(position(now).z() - position(drifter_before).z(), elapsed, 1e-9);
  EXPECT_NEAR(worldVelocity(now).z(), 1.0, 1e-12);
  EXPECT_NEAR(worldVelocity(now).x(), 0.0, 1e-12);
  push.publish(wrench("world", 0.0, 0.0, 0.0));
}

TEST(Scene, AWrenchInAnotherBodysFrameActsAtThatBodyAlongItsAxes) {
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> a(nh, "pair/a/odom");
  ASSERT_TRUE(a.waitForCount(1));
  ros::Publisher push = advertiseWrench(nh, "pair/a");
  // 1 N along b's x axis, world +y (b is yawed by 90°), at b's origin (2, 0, 0): on a (1 kg, I = 2/5 m r² =
  // 0.1 kg m², at the origin) a force along +y and a torque (2, 0, 0) × (0, 1, 0) = (0, 0, 2) N m, held in world
  // axes at that point while a moves along y (the lever arm's x stays 2). So v_y = t/m and ω_z = 2 t/I: ω_z/v_y
  // = 20 1/m. b's identity orientation would push along x with no torque; its origin taken as a's, no torque.
  push.publish(wrench("b", 1.0, 0.0, 0.0));
  ASSERT_TRUE(waitUntil([&] { return worldVelocity(a.messages.back()).y() > 0.2; }));
  const nav_msgs::Odometry& now = a.messages.back();
  const Eigen::Vector3d v = worldVelocity(now);
  EXPECT_NEAR(v.x(), 0.0, 1e-9);
  EXPECT_NEAR(v.z(), 0.0, 1e-9);
  EXPECT_NEAR(now.twist.twist.angular.z / v.y(), 20.0, 1e-6);  // about z: body and world z agree
  EXPECT_NEAR(now.twist.twist.angular.x, 0.0, 1e-9);
  EXPECT_NEAR(now.twist.twist.angular.y, 0.0, 1e-9);
  push.publish(wrench("world", 0.0, 0.0, 0.0));
}

TEST(Scene, DiagnosticsShowTheTermsEachBodysStepWasAssembledFrom) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  std::string box, ball, drifter;
  ASSERT_TRUE(diagnostics.waitFor("scene/node: rigid body scene (3 bodies)", [&](const diagnostic_msgs::DiagnosticStatus& status) {
    box = Diagnostics::value(status, "box: step terms");
    ball = Diagnostics::value(status, "ball_link: step terms");
    drifter = Diagnostics::value(status, "drifter: step terms");
    return Diagnostics::value(status, "bodies") == "3";
  }));
  // Zero g, no damping: neither term anywhere. The drifter has no input and no spin: translation only.
  EXPECT_EQ(drifter, "translation");
  EXPECT_EQ(box, "translation, rotation (w = R I^-1 R^T L), wrench input");
  EXPECT_EQ(ball, "translation, rotation (isotropic: w = L/I0), wrench input");
}

// bodies/states in a scene with per-body topics too (pair: a at the origin, b at (2, 0, 0) yawed 90°):
// every body by its body_frame, in the order of ~bodies, pose and world-axes twist at one stamp, the pose
// the same as the body's own odometry at that stamp.
TEST(Scene, BodiesStatesCarriesEveryBodyInEveryScene) {
  ros::NodeHandle nh;
  Recorder<rigid_body_sim::BodyStates> states(nh, "pair/bodies/states");
  Recorder<nav_msgs::Odometry> b_odom(nh, "pair/b/odom");
  ASSERT_TRUE(states.waitForCount(1));
  ASSERT_TRUE(b_odom.waitForCount(1));
  rigid_body_sim::BodyStates s;
  ASSERT_TRUE(states.waitForStampAfter(b_odom.messages.front().header.stamp, s));
  ASSERT_EQ(s.name.size(), 2u);
  EXPECT_EQ(s.name[0], "a");
  EXPECT_EQ(s.name[1], "b");
  ASSERT_EQ(s.pose.size(), 2u);
  ASSERT_EQ(s.twist.size(), 2u);
  EXPECT_EQ(s.header.frame_id, "world");
  EXPECT_EQ(s.pose[1].position.x, 2.0);
  EXPECT_NEAR(s.pose[1].orientation.z, 0.70710678118654752, 1e-15);
  ASSERT_TRUE(waitUntil([&] { return b_odom.messages.back().header.stamp >= s.header.stamp; }));
  std::size_t compared = 0;
  for (const auto& odom : b_odom.messages) {
    if (odom.header.stamp != s.header.stamp) continue;
    EXPECT_EQ(odom.pose.pose.position.x, s.pose[1].position.x);
    EXPECT_EQ(odom.pose.pose.orientation.w, s.pose[1].orientation.w);
    ++compared;
  }
  EXPECT_EQ(compared, 1u) << "b's odometry at the states' stamp";
}

TEST(Scene, WithoutPerBodyTopicsOneArrayCarriesEveryBodyAndNamedWrenchesMoveTheirBodyOnly) {
  ros::NodeHandle nh;
  Recorder<rigid_body_sim::OdometryArray> all(nh, "many/bodies/odom");
  ASSERT_TRUE(all.waitForCount(2));
  // No per-body topic or service was set up: a few registrations for the whole scene.
  const std::set<std::string> published = topicsWith(0), subscribed = topicsWith(1);
  for (const char* name : {"first", "second", "third"}) {
    EXPECT_FALSE(published.count(std::string("/many/") + name + "/odom")) << name;
    EXPECT_FALSE(subscribed.count(std::string("/many/") + name + "/wrench")) << name;
  }
  EXPECT_TRUE(subscribed.count("/many/bodies/wrench"));
  const rigid_body_sim::OdometryArray first = all.messages.back();
  ASSERT_EQ(first.bodies.size(), 3u);
  EXPECT_EQ(first.header.frame_id, "world");
  EXPECT_EQ(first.bodies[0].child_frame_id, "first");
  EXPECT_EQ(first.bodies[1].child_frame_id, "second");
  for (const auto& odom : first.bodies) EXPECT_EQ(odom.header.stamp, first.header.stamp);
  EXPECT_EQ(first.bodies[1].pose.pose.position.x, 2.0);

  // A named wrench moves its body, exactly as on the body's own topic; an unknown name moves nothing.
  ros::Publisher publisher = nh.advertise<rigid_body_sim::BodyWrenches>("many/bodies/wrench", 10);
  ASSERT_TRUE(waitUntil([&] { return publisher.getNumSubscribers() > 0; }));
  rigid_body_sim::BodyWrenches wrenches;
  rigid_body_sim::BodyWrench push;
  push.body = "second";
  push.wrench.header.frame_id = "world";
  push.wrench.wrench.force.y = 1.0;
  wrenches.wrenches.push_back(push);
  push.body = "nobody";
  wrenches.wrenches.push_back(push);
  push.body = "third";  // takes no wrench
  wrenches.wrenches.push_back(push);
  publisher.publish(wrenches);
  ASSERT_TRUE(waitUntil([&] { return worldVelocity(all.messages.back().bodies[1]).y() > 0.0; }));
  const rigid_body_sim::OdometryArray a = all.messages.back();
  rigid_body_sim::OdometryArray b;
  ASSERT_TRUE(all.waitForStampAfter(a.header.stamp + ros::Duration(0.3), b));
  const double t = (b.header.stamp - a.header.stamp).toSec();
  // A sphere of 1 kg (the default mass) under 1 N: Δv = t exactly (rk4, constant force).
  EXPECT_NEAR(worldVelocity(b.bodies[1]).y() - worldVelocity(a.bodies[1]).y(), 1.0 * t, 1e-9);
  EXPECT_EQ(worldVelocity(b.bodies[0]), Eigen::Vector3d::Zero());
  EXPECT_EQ(worldVelocity(b.bodies[2]), Eigen::Vector3d::Zero());
  Diagnostics diagnostics(nh);
  EXPECT_TRUE(diagnostics.waitFor("many/node: rigid body scene", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "rejected unknown_body") == "2";
  }));
  // More wrenches than the scene has bodies: the message is refused whole, its push on `first` included.
  rigid_body_sim::BodyWrenches oversized;
  push.body = "first";
  oversized.wrenches.assign(4, push);
  publisher.publish(oversized);
  EXPECT_TRUE(diagnostics.waitFor("many/node: rigid body scene", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "rejected oversized") == "1";
  }));
  rigid_body_sim::OdometryArray c;
  ASSERT_TRUE(all.waitForStampAfter(all.messages.back().header.stamp + ros::Duration(0.1), c));
  EXPECT_EQ(worldVelocity(c.bodies[0]), Eigen::Vector3d::Zero());
}

// A namespace renames topics, not frames: the launch file's body_frame gives each copy a frame of its own.
TEST(Scene, TwoLaunchedCopiesUnderTwoNamespacesPublishTwoFrames) {
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> first(nh, "robot1/odom"), second(nh, "robot2/odom");
  ASSERT_TRUE(first.waitForCount(2));
  ASSERT_TRUE(second.waitForCount(2));
  EXPECT_EQ(first.messages.back().child_frame_id, "robot1/base_link");
  EXPECT_EQ(second.messages.back().child_frame_id, "robot2/base_link");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "scene_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
