#include "rigid_body_sim/ros/own_transforms.hpp"

#include <algorithm>

#include <boost/make_shared.hpp>

namespace rigid_body_ros {

void OwnTransforms::advertise(ros::NodeHandle& nh) { publisher_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100); }

void OwnTransforms::publish(const std::vector<geometry_msgs::TransformStamped>& transforms) {
  auto message = boost::make_shared<tf2_msgs::TFMessage>();
  message->transforms = transforms;
  recent_.push_back(message);
  if (recent_.size() > kRemembered) recent_.pop_front();
  publisher_.publish(message);
}

bool OwnTransforms::isOwn(const tf2_msgs::TFMessage* message) const {
  // Newest first: a message the listener is not late for is found at once.
  return std::any_of(recent_.rbegin(), recent_.rend(),
                     [message](const tf2_msgs::TFMessageConstPtr& own) { return own.get() == message; });
}

}  // namespace rigid_body_ros
