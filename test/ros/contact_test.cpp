// The node with contact: the shipped falling_box scene lands, rests on a face at half its height along the
// vertical, and publishes its contacts against the ground; a scene without colliders has no contacts topic.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <Eigen/Geometry>
#include <set>
#include <string>

#include <visualization_msgs/MarkerArray.h>

#include "rigid_body_sim/Contacts.h"
#include "rigid_body_sim/RigidBodyState.h"
#include "test_helpers.hpp"

namespace {

using namespace test_helpers;

const Eigen::Vector3d kBoxSize(0.4, 0.2, 0.1);  // config/falling_box.yaml
constexpr double kMass = 1.0, kG = 9.81, kDt = 0.001;

std::set<std::string> publishedTopics() {
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  std::set<std::string> topics;
  if (!ros::master::execute("getSystemState", request, response, payload, true)) return topics;
  for (int i = 0; i < payload[0].size(); ++i) topics.insert(static_cast<std::string>(payload[0][i][0]));
  return topics;
}

Eigen::Quaterniond orientation(const rigid_body_sim::RigidBodyState& s) {
  return Eigen::Quaterniond(s.pose.orientation.w, s.pose.orientation.x, s.pose.orientation.y, s.pose.orientation.z);
}

double speed(const rigid_body_sim::RigidBodyState& s) {
  return Eigen::Vector3d(s.twist.linear.x, s.twist.linear.y, s.twist.linear.z).norm() +
         Eigen::Vector3d(s.twist.angular.x, s.twist.angular.y, s.twist.angular.z).norm();
}

}  // namespace

TEST(Contact, TheFallingBoxLandsAndRestsOnAFaceAtHalfItsHeight) {
  ros::NodeHandle nh;
  Recorder<rigid_body_sim::RigidBodyState> state(nh, "landing/state");
  // Dropped from 1 m it lands after 0.45 s; it rests once it and its spin have stopped.
  ASSERT_TRUE(waitUntil([&] { return !state.messages.empty() && state.messages.back().header.stamp.toSec() > 0.0 &&
                                     state.messages.size() > 50 && speed(state.messages.back()) < 1e-4; },
                        30.0));
  const rigid_body_sim::RigidBodyState& s = state.messages.back();
  // Half the box's extent along the vertical, whatever face it rests on: ½ Σ |R_zi| size_i.
  const Eigen::Matrix3d R = orientation(s).toRotationMatrix();
  const double half_height = 0.5 * R.row(2).cwiseAbs().dot(kBoxSize);
  EXPECT_NEAR(s.pose.position.z, half_height, 1e-3);
  EXPECT_GE(s.contacts, 3u) << "a face resting on the ground touches it at its corners";
  // At rest on a face: one box axis is vertical.
  EXPECT_NEAR(R.row(2).cwiseAbs().maxCoeff(), 1.0, 1e-4);
}

TEST(Contact, ContactsComeWithTheGroundsNormalAndCarryTheWeight) {
  ros::NodeHandle nh;
  Recorder<rigid_body_sim::Contacts> contacts(nh, "landing/contacts");
  Recorder<rigid_body_sim::RigidBodyState> state(nh, "landing/state");
  ASSERT_TRUE(waitUntil([&] { return !state.messages.empty() && speed(state.messages.back()) < 1e-4 &&
                                     !contacts.messages.empty() && contacts.messages.back().contacts.size() >= 3; },
                        30.0));
  const rigid_body_sim::Contacts& last = contacts.messages.back();
  EXPECT_EQ(last.header.frame_id, "world");
  EXPECT_EQ(last.body_frame, "base_link");
  double normal_impulse = 0.0;
  for (const rigid_body_sim::Contact& contact : last.contacts) {
    EXPECT_EQ(contact.other, "ground");
    EXPECT_NEAR(contact.normal.z, 1.0, 1e-9);
    EXPECT_NEAR(contact.position.z, 0.0, 1e-3) << "a contact point lies on the ground";
    EXPECT_LE(contact.penetration, 1e-3);
    normal_impulse += contact.normal_impulse;
  }
  // At rest, the ground carries the weight: the normal impulses of one step add up to M g dt.
  EXPECT_NEAR(normal_impulse, kMass * kG * kDt, 0.01 * kMass * kG * kDt);
}

TEST(Contact, ASceneWithoutCollidersHasNoContactsTopicAndNoContactTerm) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  Recorder<rigid_body_sim::RigidBodyState> free_state(nh, "free/state");
  ASSERT_TRUE(free_state.waitForCount(1));
  EXPECT_EQ(free_state.messages.back().contacts, 0u);
  const std::set<std::string> topics = publishedTopics();
  EXPECT_TRUE(topics.count("/landing/contacts"));
  EXPECT_FALSE(topics.count("/free/contacts"));
  EXPECT_TRUE(diagnostics.waitFor("free_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    const std::string terms = Diagnostics::value(s, "step terms");
    return !terms.empty() && terms.find("contact") == std::string::npos;
  }));
  EXPECT_TRUE(diagnostics.waitFor("base_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "step terms").find("contact (box") != std::string::npos &&
           !Diagnostics::value(s, "contact points").empty();
  }));
}

TEST(Contact, MarkersShowTheBodyTheGroundAndTheContactsAtTheMarkerRate) {
  ros::NodeHandle nh;
  Recorder<visualization_msgs::MarkerArray> markers(nh, "landing/markers");
  Recorder<rigid_body_sim::RigidBodyState> state(nh, "landing/state");
  // At rest, so that the contact points are there.
  ASSERT_TRUE(waitUntil([&] { return !state.messages.empty() && speed(state.messages.back()) < 1e-4; }, 30.0));
  const std::size_t seen = markers.messages.size();
  ASSERT_TRUE(markers.waitForCount(seen + 3));
  const visualization_msgs::MarkerArray& last = markers.messages.back();
  const visualization_msgs::Marker* box = nullptr;
  const visualization_msgs::Marker* ground = nullptr;
  const visualization_msgs::Marker* points = nullptr;
  for (const visualization_msgs::Marker& m : last.markers) {
    if (m.ns == "bodies" && m.id == 0) box = &m;
    if (m.ns == "environment" && m.id == 0) ground = &m;
    if (m.ns == "contacts" && m.id == 0) points = &m;
  }
  ASSERT_TRUE(box && ground && points);
  // The box in its own frame, with its size: it moves with tf.
  EXPECT_EQ(box->header.frame_id, "base_link");
  EXPECT_EQ(box->type, visualization_msgs::Marker::CUBE);
  EXPECT_EQ(Eigen::Vector3d(box->scale.x, box->scale.y, box->scale.z), kBoxSize);
  // The ground plane: a thin slab in the world frame whose top face is z = 0.
  EXPECT_EQ(ground->header.frame_id, "world");
  EXPECT_NEAR(ground->pose.position.z + 0.5 * ground->scale.z, 0.0, 1e-12);
  // The contact points on the ground, as many as the state counts.
  EXPECT_EQ(points->points.size(), state.messages.back().contacts);
  for (const geometry_msgs::Point& p : points->points) EXPECT_NEAR(p.z, 0.0, 1e-3);
  // Stable ids, and the default marker rate of 20 Hz in simulated time: 0.05 s between arrays. Arrays go out
  // on the node's ticks (100 Hz), so one that a late tick delays comes up to a few ms late, but due times stay
  // on the 0.05 s grid: over 5 intervals the stamps span 0.25 s give or take that lateness (at 10 or 100 Hz
  // they would span 0.5 or 0.05 s).
  const visualization_msgs::MarkerArray& before = markers.messages[markers.messages.size() - 2];
  ASSERT_EQ(before.markers.size(), last.markers.size());
  for (std::size_t i = 0; i < last.markers.size(); ++i) {
    EXPECT_EQ(before.markers[i].ns, last.markers[i].ns);
    EXPECT_EQ(before.markers[i].id, last.markers[i].id);
  }
  const std::size_t count = markers.messages.size();
  ASSERT_TRUE(markers.waitForCount(count + 5));
  const ros::Time first = markers.messages[count - 1].markers[0].header.stamp;
  const ros::Time fifth = markers.messages[count + 4].markers[0].header.stamp;
  EXPECT_NEAR((fifth - first).toSec(), 0.25, 0.02);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "contact_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
