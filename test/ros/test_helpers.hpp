// Helpers shared by the rostest nodes: bounded waits, a topic recorder, the latest /diagnostics.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace test_helpers {

// The longest any single wait may take [s, wall time]; rostest's time-limit bounds the whole file.
constexpr double kWaitLimit = 10.0;

inline bool waitUntil(const std::function<bool()>& condition, double timeout = kWaitLimit) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (!condition()) {
    if (ros::WallTime::now() > deadline || !ros::ok()) return false;
    ros::spinOnce();
    ros::WallDuration(0.001).sleep();
  }
  return true;
}

inline void spinFor(double seconds) {
  waitUntil([] { return false; }, seconds);
}

template <typename Message>
class Recorder {
 public:
  Recorder(ros::NodeHandle& nh, const std::string& topic)
      : subscriber_(nh.subscribe(topic, 1000, &Recorder::onMessage, this)) {}
  void onMessage(const Message& message) { messages.push_back(message); }
  /// Waits until a publisher is connected (before starting something fast).
  bool waitForConnection() {
    return waitUntil([&] { return subscriber_.getNumPublishers() > 0; });
  }
  bool waitForCount(size_t count) {
    return waitUntil([&] { return messages.size() >= count; });
  }
  /// Waits for the first message stamped after `stamp`.
  bool waitForStampAfter(const ros::Time& stamp, Message& out) {
    return waitUntil([&] {
      if (messages.empty() || messages.back().header.stamp <= stamp) return false;
      out = messages.back();
      return true;
    });
  }
  std::vector<Message> messages;

 private:
  ros::Subscriber subscriber_;
};

/// The latest status of every name on /diagnostics, with its key/value pairs.
class Diagnostics {
 public:
  explicit Diagnostics(ros::NodeHandle& nh) : subscriber_(nh.subscribe("/diagnostics", 100, &Diagnostics::onArray, this)) {}

  /// Waits until the status whose name contains `name` satisfies `condition`.
  bool waitFor(const std::string& name, const std::function<bool(const diagnostic_msgs::DiagnosticStatus&)>& condition,
               double timeout = kWaitLimit) {
    return waitUntil(
        [&] {
          for (const auto& entry : latest_) {
            if (entry.first.find(name) != std::string::npos && condition(entry.second)) return true;
          }
          return false;
        },
        timeout);
  }

  static std::string value(const diagnostic_msgs::DiagnosticStatus& status, const std::string& key) {
    for (const auto& pair : status.values) {
      if (pair.key == key) return pair.value;
    }
    return "";
  }

 private:
  void onArray(const diagnostic_msgs::DiagnosticArray& array) {
    for (const auto& status : array.status) latest_[status.name] = status;
  }
  ros::Subscriber subscriber_;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> latest_;
};

inline Eigen::Vector3d worldVelocity(const nav_msgs::Odometry& odom) {
  Eigen::Quaterniond q_WB;
  Eigen::Vector3d v_B;
  tf2::fromMsg(odom.pose.pose.orientation, q_WB);
  tf2::fromMsg(odom.twist.twist.linear, v_B);
  return q_WB * v_B;
}

inline Eigen::Vector3d position(const nav_msgs::Odometry& odom) {
  Eigen::Vector3d p;
  tf2::fromMsg(odom.pose.pose.position, p);
  return p;
}

inline bool allFinite(const nav_msgs::Odometry& odom) {
  const auto& p = odom.pose.pose;
  const auto& t = odom.twist.twist;
  for (double value : {p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z,
                       p.orientation.w, t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z}) {
    if (!std::isfinite(value)) return false;
  }
  return true;
}

inline geometry_msgs::WrenchStamped wrench(const std::string& frame, double fx, double fy, double fz) {
  geometry_msgs::WrenchStamped message;
  message.header.frame_id = frame;
  message.header.stamp = ros::Time::now();
  message.wrench.force.x = fx;
  message.wrench.force.y = fy;
  message.wrench.force.z = fz;
  return message;
}

inline ros::Publisher advertiseWrench(ros::NodeHandle& nh, const std::string& ns) {
  ros::Publisher publisher = nh.advertise<geometry_msgs::WrenchStamped>(ns + "/wrench", 10);
  waitUntil([&] { return publisher.getNumSubscribers() > 0; });
  return publisher;
}

}  // namespace test_helpers
