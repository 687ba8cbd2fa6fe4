// The tf tree as the other nodes publish it: /tf and /tf_static into a tf2 buffer, like tf2_ros's
// TransformListener, except the node's own /tf messages (OwnTransforms knows them). The node publishes every
// body's pose on /tf at the output rate; taking them back in would insert each of them into the buffer again
// (for 10 000 bodies a million insertions a second, docs/performance_log.md#own-transforms), only to read back
// a pose the World holds exactly. Lookups through a body of this node use the World's pose instead (WrenchInput).
#pragma once

#include <ros/ros.h>
#include <tf2/buffer_core.h>
#include <tf2_msgs/TFMessage.h>

#include "rigid_body_sim/ros/own_transforms.hpp"

namespace rigid_body_ros {

class ForeignTransforms {
 public:
  /// Fills `buffer` from /tf (but for this node's own messages) and /tf_static, in callbacks on `nh`'s queue:
  /// the simulator's own, whose one thread also converts the wrenches that read the buffer and publishes the
  /// node's /tf. Not on a thread of their own, as tf2_ros's listener has them: the node's own /tf, handed
  /// straight back within the process, then woke that thread at every output only to be dropped
  /// (docs/performance_log.md, "Lockstep as a nodelet").
  ForeignTransforms(tf2::BufferCore& buffer, const OwnTransforms& own, ros::NodeHandle& nh);
  ForeignTransforms(const ForeignTransforms&) = delete;
  ForeignTransforms& operator=(const ForeignTransforms&) = delete;

 private:
  void onTransforms(const ros::MessageEvent<tf2_msgs::TFMessage const>& event, bool is_static);

  tf2::BufferCore& buffer_;
  const OwnTransforms& own_;
  ros::Subscriber tf_, tf_static_;
  ros::Time last_update_;
};

}  // namespace rigid_body_ros
