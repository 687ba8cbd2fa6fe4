// A multi-body scene seen from outside: topics per body, one tf message for all, independence of the bodies.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <set>
#include <string>

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
  ASSERT_TRUE(tf.waitForCount(5));
  for (const tf2_msgs::TFMessage& message : tf.messages) {
    ASSERT_EQ(message.transforms.size(), 3u);
    EXPECT_EQ(message.transforms[0].child_frame_id, "box");
    EXPECT_EQ(message.transforms[1].child_frame_id, "ball_link");
    EXPECT_EQ(message.transforms[2].child_frame_id, "drifter");
    for (const auto& transform : message.transforms) {
      EXPECT_EQ(transform.header.frame_id, "world");
      EXPECT_EQ(transform.header.stamp, message.transforms[0].header.stamp);
    }
  }
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

TEST(Scene, DiagnosticsShowTheTermsEachBodysStepWasAssembledFrom) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  std::string box, ball, drifter;
  ASSERT_TRUE(diagnostics.waitFor("rigid body scene (3 bodies)", [&](const diagnostic_msgs::DiagnosticStatus& status) {
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

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "scene_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
