// The simulator's own /tf messages, told apart from everybody else's when they come back into its tf
// listener. They go out as shared pointers, and roscpp hands a subscriber in the same process the very
// message published, so its address names it. Other publishers in the process (sibling nodelets in a
// manager) deliver other addresses, and their transforms go into the buffer. Used by the simulator's one
// thread (it publishes, and its queue's callbacks ask), so nothing is locked.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>

#include <deque>
#include <vector>

namespace rigid_body_ros {

class OwnTransforms {
 public:
  /// Advertises /tf on `nh` as tf2_ros's broadcaster does (queue of 100, not latched).
  void advertise(ros::NodeHandle& nh);
  /// Publishes `transforms` as one message and remembers it.
  void publish(const std::vector<geometry_msgs::TransformStamped>& transforms);
  /// Whether `message` is one this simulator published (among the last kRemembered).
  bool isOwn(const tf2_msgs::TFMessage* message) const;

  /// More than the listener's subscriber queue holds (100), so that an own message still waiting in it is
  /// remembered; holding them also keeps their addresses from being reused.
  static constexpr std::size_t kRemembered = 256;

 private:
  ros::Publisher publisher_;
  std::deque<tf2_msgs::TFMessageConstPtr> recent_;
};

}  // namespace rigid_body_ros
