#include "rigid_body_sim/ros/foreign_transforms.hpp"

#include <tf2/exceptions.h>

#include <string>

#include "rigid_body_sim/ros/time_conversion.hpp"

namespace rigid_body_ros {

namespace {
// Subscriber queues, as tf2_ros's listener has them.
constexpr uint32_t kQueueSize = 100;
// tf2's cache adds its storage time (10 s) to a transform's stamp, which ros::Time refuses, by throwing,
// past 2^32 s: a stamp this close to the end of ROS time is refused here instead [ns].
constexpr rigid_body::Nanoseconds kStampMargin = 3600LL * 1000000000LL;
}  // namespace

ForeignTransforms::ForeignTransforms(tf2::BufferCore& buffer, const OwnTransforms& own, ros::NodeHandle& nh)
    : buffer_(buffer), own_(own) {
  tf_ = nh.subscribe<tf2_msgs::TFMessage>(
      "/tf", kQueueSize, [this](const ros::MessageEvent<tf2_msgs::TFMessage const>& event) { onTransforms(event, false); });
  tf_static_ = nh.subscribe<tf2_msgs::TFMessage>(
      "/tf_static", kQueueSize,
      [this](const ros::MessageEvent<tf2_msgs::TFMessage const>& event) { onTransforms(event, true); });
}

void ForeignTransforms::onTransforms(const ros::MessageEvent<tf2_msgs::TFMessage const>& event, bool is_static) {
  // The node's own dynamic transforms stay out (its static ones, a mesh frame below a body, go in: frames of
  // the body are found through them). They arrive within the process as the very message published; a
  // sibling nodelet's, also within the process, are other messages and go in.
  if (!is_static && own_.isOwn(event.getConstMessage().get())) return;
  // Time went back (a simulation clock restarted): the buffer's history is from another run.
  const ros::Time now = ros::Time::now();
  if (now < last_update_) {
    ROS_WARN("rigid_body_node: time went back by %.3f s: the tf buffer is cleared", (last_update_ - now).toSec());
    buffer_.clear();
  }
  last_update_ = now;
  const std::string& authority = event.getPublisherName();
  for (const geometry_msgs::TransformStamped& transform : event.getConstMessage()->transforms) {
    if (toNanoseconds(transform.header.stamp) > kEndOfRosTime - kStampMargin) {
      ROS_WARN_THROTTLE(2.0, "rigid_body_node: a transform from %s refused: its stamp %.3f s is within an hour of "
                        "the end of ROS time (2^32 s)", authority.c_str(), transform.header.stamp.toSec());
      continue;
    }
    try {
      buffer_.setTransform(transform, authority, is_static);
    } catch (const std::exception& exception) {  // tf2's refusals, and ros::Time's arithmetic should it throw
      ROS_WARN_THROTTLE(2.0, "rigid_body_node: a transform from %s refused by tf2: %s", authority.c_str(),
                        exception.what());
    }
  }
}

}  // namespace rigid_body_ros
