// Live parameters: gravity set through dynamic_reconfigure reaches the next steps (the body accelerates at
// g, in simulated time) and re-assembles the step terms; set back to zero, the term goes again.
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rigid_body_sim/ApplyWrench.h"
#include "rigid_body_sim/ros/parameters.hpp"
#include "test_helpers.hpp"

namespace {

using namespace test_helpers;

bool setDouble(const std::string& name, double value, const std::string& node = "live/node") {
  const std::string server = node + "/live";
  dynamic_reconfigure::Reconfigure request;
  dynamic_reconfigure::DoubleParameter parameter;
  parameter.name = name;
  parameter.value = value;
  request.request.config.doubles.push_back(parameter);
  return ros::service::waitForService(server + "/set_parameters", ros::Duration(10.0)) &&
         ros::service::call(server + "/set_parameters", request);
}

double vz(const nav_msgs::Odometry& odom) { return worldVelocity(odom).z(); }

}  // namespace

TEST(LiveParameters, GravityTurnedOnAcceleratesTheBodyAndAddsItsTerm) {
  ros::NodeHandle nh;
  Diagnostics diagnostics(nh);
  Recorder<nav_msgs::Odometry> odom(nh, "live/odom");
  ASSERT_TRUE(odom.waitForCount(5));
  EXPECT_EQ(vz(odom.messages.back()), 0.0);  // zero g: at rest
  ASSERT_TRUE(diagnostics.waitFor("live_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    const std::string terms = Diagnostics::value(s, "step terms");
    return !terms.empty() && terms.find("gravity") == std::string::npos;
  }));
  ASSERT_TRUE(setDouble("gravity_z", -9.81));
  // Falling: between two odometry messages v_z changes by g times the simulated time between them.
  ASSERT_TRUE(waitUntil([&] { return vz(odom.messages.back()) < -0.1; }));
  const std::size_t n = odom.messages.size();
  ASSERT_TRUE(odom.waitForCount(n + 5));
  const nav_msgs::Odometry& a = odom.messages[n];
  const nav_msgs::Odometry& b = odom.messages.back();
  const double elapsed = (b.header.stamp - a.header.stamp).toSec();
  EXPECT_NEAR(vz(b) - vz(a), -9.81 * elapsed, 1e-6);
  EXPECT_TRUE(diagnostics.waitFor("live_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    return Diagnostics::value(s, "step terms").find("gravity") != std::string::npos;
  }));
  // Off again: the velocity stays, the term goes.
  ASSERT_TRUE(setDouble("gravity_z", 0.0));
  EXPECT_TRUE(diagnostics.waitFor("live_link", [](const diagnostic_msgs::DiagnosticStatus& s) {
    const std::string terms = Diagnostics::value(s, "step terms");
    return !terms.empty() && terms.find("gravity") == std::string::npos;
  }));
  const std::size_t m = odom.messages.size();
  ASSERT_TRUE(odom.waitForCount(m + 3));
  EXPECT_EQ(vz(odom.messages[m]), vz(odom.messages.back()));
}

TEST(LiveParameters, AnOutOfRangeValueIsClampedByTheServerNotApplied) {
  // dynamic_reconfigure clamps to the .cfg's range: damping below 0 arrives as 0 (no pulling force).
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> odom(nh, "live/odom");
  ASSERT_TRUE(odom.waitForCount(2));
  ASSERT_TRUE(setDouble("linear_damping", -5.0));
  double value = -1.0;
  EXPECT_TRUE(waitUntil([&] { return ros::param::get("live/node/live/linear_damping", value) && value == 0.0; }));
}

TEST(LiveParameters, ANonFiniteValueIsRefusedAndTheValuesInForceKept) {
  // The server's range clamp lets a NaN through (it fails both comparisons); the node keeps the value in force
  // for every double of the request and goes on publishing finite odometry, noisy copy included.
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> truth(nh, "noisy/odom"), noisy(nh, "noisy/odom_noisy");
  ASSERT_TRUE(noisy.waitForCount(3));
  const std::vector<std::string> names = {"linear_damping", "gravity_z", "wrench_timeout", "max_force", "real_time_factor",
                                          "noise_position_stddev", "noise_angular_velocity_stddev", "marker_rate"};
  std::vector<double> before;
  dynamic_reconfigure::Reconfigure request;
  for (const std::string& name : names) {
    double value = 0.0;
    ASSERT_TRUE(ros::param::get("noisy/node/live/" + name, value)) << name;
    before.push_back(value);
    dynamic_reconfigure::DoubleParameter parameter;
    parameter.name = name;
    parameter.value = std::numeric_limits<double>::quiet_NaN();
    request.request.config.doubles.push_back(parameter);
  }
  ASSERT_TRUE(ros::service::call("noisy/node/live/set_parameters", request));
  for (const dynamic_reconfigure::DoubleParameter& reply : request.response.config.doubles) {
    EXPECT_FALSE(std::isnan(reply.value)) << reply.name << " came back as NaN";
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    double value = std::numeric_limits<double>::quiet_NaN();
    ASSERT_TRUE(ros::param::get("noisy/node/live/" + names[i], value)) << names[i];
    EXPECT_EQ(value, before[i]) << names[i];
  }
  const std::size_t n = noisy.messages.size(), m = truth.messages.size();
  ASSERT_TRUE(noisy.waitForCount(n + 5));
  ASSERT_TRUE(truth.waitForCount(m + 5));
  for (std::size_t i = n; i < noisy.messages.size(); ++i) {
    EXPECT_TRUE(position(noisy.messages[i]).allFinite() && worldVelocity(noisy.messages[i]).allFinite()) << i;
  }
  for (std::size_t i = m; i < truth.messages.size(); ++i) EXPECT_TRUE(position(truth.messages[i]).allFinite()) << i;
}

TEST(LiveParameters, NoiseSetToZeroMakesTheNoisyOdometryTheTruth) {
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> truth(nh, "noisy/odom"), noisy(nh, "noisy/odom_noisy");
  ASSERT_TRUE(noisy.waitForCount(3));
  EXPECT_NE(position(noisy.messages.back()), position(truth.messages.back()));  // 1 cm of noise at start-up
  ASSERT_TRUE(setDouble("noise_position_stddev", 0.0, "noisy/node"));
  // From the change on, the noisy copy is the truth, and so is its declared covariance.
  ASSERT_TRUE(waitUntil([&] { return !noisy.messages.empty() && noisy.messages.back().pose.covariance[0] == 0.0; }));
  const std::size_t n = noisy.messages.size();
  ASSERT_TRUE(noisy.waitForCount(n + 3));
  const nav_msgs::Odometry& last = noisy.messages.back();
  bool matched = false;
  for (const nav_msgs::Odometry& t : truth.messages) {
    if (t.header.stamp == last.header.stamp) matched = position(t) == position(last);
  }
  EXPECT_TRUE(matched) << "the noisy copy at its stamp is not the truth";
}

TEST(LiveParameters, AWrenchLimitOfZeroOrBelowIsRefusedNotReadAsNoLimit) {
  // A node that read 0 (or −5, which the server clamps to 0) as "no limit" would accept the 30 N wrench
  // after the refused change; one that applied it would reject every wrench, even 1 N.
  auto accepted = [](double force) {
    rigid_body_sim::ApplyWrench call;
    call.request.wrench.force.x = force;
    EXPECT_TRUE(ros::service::waitForService("live/apply_wrench", ros::Duration(10.0)));
    EXPECT_TRUE(ros::service::call("live/apply_wrench", call));
    return static_cast<bool>(call.response.success);
  };
  ASSERT_TRUE(setDouble("max_force", 20.0));
  EXPECT_FALSE(accepted(30.0));
  for (const double refused : {0.0, -5.0}) {
    ASSERT_TRUE(setDouble("max_force", refused));
    double value = 0.0;
    EXPECT_TRUE(ros::param::get("live/node/live/max_force", value));
    EXPECT_EQ(value, 20.0) << refused;
    EXPECT_FALSE(accepted(30.0)) << refused;
    EXPECT_TRUE(accepted(1.0)) << refused;
  }
  ASSERT_TRUE(setDouble("max_force", std::numeric_limits<double>::infinity()));  // .inf: no limit
  EXPECT_TRUE(accepted(1e9));
}

TEST(LiveParameters, EveryNodeStartsAgainFromWhatItLeftOnTheParameterServer) {
  // A respawned node (or a second rosrun against the same master) reads its private namespace as the last run
  // left it, servers' write-backs included: the start-up parser must take it. Checked after live changes.
  ASSERT_TRUE(setDouble("linear_damping", 0.25, "listed/node"));
  ASSERT_TRUE(setDouble("max_force", 20.0, "live/node"));
  ASSERT_TRUE(setDouble("max_force", std::numeric_limits<double>::infinity(), "live/node"));  // no limit
  for (const std::string node : {"live/node", "noisy/node", "listed/node"}) {
    XmlRpc::XmlRpcValue params;
    ASSERT_TRUE(ros::param::get(node, params)) << node;
    try {
      const rigid_body_ros::NodeConfig config = rigid_body_ros::parseConfig(params);
      EXPECT_TRUE(config.unknown_parameters.empty()) << node << ": " << config.unknown_parameters.front();
    } catch (const std::exception& error) {
      ADD_FAILURE() << node << " would not start again: " << error.what();
    }
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "live_parameters_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
