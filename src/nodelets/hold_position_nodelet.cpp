// rigid_body_sim/HoldPositionNodelet: an example controller to load beside RigidBodyNodelet in one manager
// (launch/nodelet_lockstep.launch). It holds a body at a point with a PD law on its odometry, the weight fed
// forward, F = M (kp (target − x) − kd v − g), in the world frame, one wrench per odometry message, stamped
// with that message's stamp: the same law as examples/hold_position_example's Python node. Messages come and
// go as shared pointers, so within the manager nothing is serialised.
//
// Parameters: ~target [m] (0, 0, 1), ~kp [1/s²] (40), ~kd [1/s] (10), ~mass [kg] (1), ~gravity [m/s²]
// (0, 0, −9.81). Topics: odom in, wrench out (remap them to the body's).
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include <Eigen/Geometry>
#include <boost/make_shared.hpp>
#include <cmath>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

namespace rigid_body_ros {

class HoldPositionNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& private_nh = getPrivateNodeHandle();
    try {
      target_ = vector(private_nh, "target", Eigen::Vector3d(0.0, 0.0, 1.0));
      gravity_ = vector(private_nh, "gravity", Eigen::Vector3d(0.0, 0.0, -9.81));
      kp_ = positive(private_nh, "kp", 40.0);
      kd_ = positive(private_nh, "kd", 10.0);
      mass_ = positive(private_nh, "mass", 1.0);
    } catch (const std::invalid_argument& error) {
      // The manager reports only that the load failed: the reason goes to the log first.
      NODELET_FATAL("%s", error.what());
      throw;
    }
    publisher_ = nh.advertise<geometry_msgs::WrenchStamped>("wrench", 10);
    subscriber_ = nh.subscribe("odom", 10, &HoldPositionNodelet::onOdometry, this);
  }

  void onOdometry(const nav_msgs::Odometry::ConstPtr& odom) {
    const auto& p = odom->pose.pose.position;
    const auto& q = odom->pose.pose.orientation;
    const auto& v = odom->twist.twist.linear;  // nav_msgs/Odometry: the twist in the body frame
    const Eigen::Vector3d v_W = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized() * Eigen::Vector3d(v.x, v.y, v.z);
    const Eigen::Vector3d force = mass_ * (kp_ * (target_ - Eigen::Vector3d(p.x, p.y, p.z)) - kd_ * v_W - gravity_);
    auto wrench = boost::make_shared<geometry_msgs::WrenchStamped>();
    wrench->header.stamp = odom->header.stamp;
    wrench->header.frame_id = odom->header.frame_id;  // the world frame
    wrench->wrench.force.x = force.x();
    wrench->wrench.force.y = force.y();
    wrench->wrench.force.z = force.z();
    publisher_.publish(wrench);
  }

  // A parameter's value as the parameter server holds it, for a message.
  static std::string shown(ros::NodeHandle& nh, const std::string& name) {
    XmlRpc::XmlRpcValue raw;
    if (!nh.getParam(name, raw)) return "?";
    std::ostringstream text;
    text << raw;
    return text.str();
  }

  // A parameter that must be 3 finite numbers; a wrong one fails the load with a message naming it.
  static Eigen::Vector3d vector(ros::NodeHandle& nh, const std::string& name, const Eigen::Vector3d& fallback) {
    std::vector<double> value;
    if (!nh.hasParam(name)) return fallback;
    if (!nh.getParam(name, value) || value.size() != 3 || !std::isfinite(value[0] + value[1] + value[2])) {
      throw std::invalid_argument("parameter " + nh.resolveName(name) + " = " + shown(nh, name) +
                                  ": must be a list of 3 finite numbers");
    }
    return Eigen::Vector3d(value[0], value[1], value[2]);
  }

  static double positive(ros::NodeHandle& nh, const std::string& name, double fallback) {
    if (!nh.hasParam(name)) return fallback;
    double value = 0.0;
    if (!nh.getParam(name, value) || !(value > 0.0 && std::isfinite(value))) {
      throw std::invalid_argument("parameter " + nh.resolveName(name) + " = " + shown(nh, name) +
                                  ": must be a finite number > 0");
    }
    return value;
  }

  Eigen::Vector3d target_, gravity_;
  double kp_ = 0.0, kd_ = 0.0, mass_ = 0.0;
  ros::Publisher publisher_;
  ros::Subscriber subscriber_;
};

}  // namespace rigid_body_ros

PLUGINLIB_EXPORT_CLASS(rigid_body_ros::HoldPositionNodelet, nodelet::Nodelet)
