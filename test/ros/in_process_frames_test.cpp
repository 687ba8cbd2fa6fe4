// The node's tf listener in a process it shares with other publishers (a nodelet manager): a frame another
// publisher of the process sends on /tf is found, while the node's own /tf stays out of the buffer
// (OwnTransforms tells the node's messages by address). The simulator is built here, in the test's process,
// beside a tf2_ros broadcaster: the same in-process delivery as between two nodelets.
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cmath>

#include "rigid_body_sim/ros/parameters.hpp"
#include "rigid_body_sim/ros/simulator_node.hpp"

namespace {

geometry_msgs::TransformStamped sensorFrame(const ros::Time& stamp) {
  // world → sensor: a quarter turn about z (x_S = y_W), at the world origin, where the body is.
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = stamp;
  transform.header.frame_id = "world";
  transform.child_frame_id = "sensor";
  transform.transform.rotation.z = std::sqrt(0.5);
  transform.transform.rotation.w = std::sqrt(0.5);
  return transform;
}

TEST(InProcessFrames, AWrenchInAFrameAnotherPublisherOfTheProcessSendsIsConvertedThroughIt) {
  XmlRpc::XmlRpcValue params;
  params["body_frame"] = "probe_link";
  const rigid_body_ros::NodeConfig config = rigid_body_ros::parseConfig(params);
  ros::NodeHandle nh("in_process");
  ros::NodeHandle private_nh("~");
  rigid_body_ros::SimulatorNode node(nh, private_nh, config);
  node.start(ros::Time::now());
  tf2_ros::TransformBroadcaster broadcaster;
  ros::Publisher wrench = nh.advertise<geometry_msgs::WrenchStamped>("wrench", 10);
  geometry_msgs::WrenchStamped push;
  push.header.frame_id = "sensor";  // stamp 0: the latest transform
  push.wrench.force.x = 1.0;
  const ros::WallTime start = ros::WallTime::now();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  while ((ros::WallTime::now() - start).toSec() < 10.0 && force.isZero()) {
    broadcaster.sendTransform(sensorFrame(ros::Time::now()));
    // Once the listener has had the frame for a while, the wrench goes out.
    if ((ros::WallTime::now() - start).toSec() > 0.5 && wrench.getNumSubscribers() > 0) wrench.publish(push);
    ros::WallDuration(0.02).sleep();
    ros::spinOnce();
    const rigid_body::AppliedWrench& input = node.world().scene().input(0);
    force = input.world.force + input.body.force;  // the body is unturned: both in world axes
  }
  EXPECT_NEAR(force.x(), 0.0, 1e-12);
  EXPECT_NEAR(force.y(), 1.0, 1e-12);
  EXPECT_NEAR(force.z(), 0.0, 1e-12);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "in_process_frames_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
