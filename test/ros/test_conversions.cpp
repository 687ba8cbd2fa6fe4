// Messages to and from the core without a master.
#include <gtest/gtest.h>

#include <tf2_eigen/tf2_eigen.h>

#include <cmath>

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/scene.hpp"
#include "rigid_body_sim/ros/conversions.hpp"
#include "rigid_body_sim/wrench_limits.hpp"

using namespace rigid_body_ros;

TEST(Conversions, WrenchFrameClassification) {
  EXPECT_EQ(classifyWrenchFrame("", "world", "base_link"), WrenchFrame::kBody);
  EXPECT_EQ(classifyWrenchFrame("base_link", "world", "base_link"), WrenchFrame::kBody);
  EXPECT_EQ(classifyWrenchFrame("world", "world", "base_link"), WrenchFrame::kWorld);
  EXPECT_EQ(classifyWrenchFrame("thruster", "world", "base_link"), WrenchFrame::kOther);
}

TEST(Conversions, NonFiniteWrenchIsDetectedInEveryComponent) {
  // The node's path: message → toWrench → checkWrench.
  for (int i = 0; i < 6; ++i) {
    geometry_msgs::Wrench wrench;
    double* fields[] = {&wrench.force.x, &wrench.force.y, &wrench.force.z,
                        &wrench.torque.x, &wrench.torque.y, &wrench.torque.z};
    EXPECT_EQ(rigid_body::checkWrench(toWrench(wrench), rigid_body::WrenchLimits()), rigid_body::WrenchVerdict::kAccepted);
    *fields[i] = (i % 2) ? std::numeric_limits<double>::infinity() : std::nan("");
    EXPECT_EQ(rigid_body::checkWrench(toWrench(wrench), rigid_body::WrenchLimits()), rigid_body::WrenchVerdict::kNonFinite)
        << i;
  }
}

TEST(Conversions, WrenchInAnotherFrameGetsRotatedAndTheMomentArm) {
  // Frame F: origin at (1, 0, 0) in W, turned 90° about z (F's x axis is W's y axis).
  Eigen::Isometry3d X_WF = Eigen::Isometry3d::Identity();
  X_WF.translate(Eigen::Vector3d(1.0, 0.0, 0.0));
  X_WF.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  geometry_msgs::Wrench wrench_F;
  wrench_F.force.x = 2.0;  // (0, 2, 0) in W
  wrench_F.torque.z = 0.5;
  // The core moves a wrench at a point to the centre of mass as τ = τ_Q + (p_WQ − x) × F_W.
  const auto wrenchInWorld = [](const geometry_msgs::Wrench& w, const Eigen::Isometry3d& X, const Eigen::Vector3d& p_WB,
                                const Eigen::Vector3d* p_FQ = nullptr) {
    const WrenchAtPoint at = wrenchAtPointInWorld(w, X, p_FQ);
    return rigid_body::wrenchAboutCentreOfMass(at.wrench_W.force, at.wrench_W.torque, at.p_WQ, p_WB);
  };
  const rigid_body::Wrench in_W = wrenchInWorld(wrench_F, X_WF, Eigen::Vector3d::Zero());
  EXPECT_TRUE(in_W.force.isApprox(Eigen::Vector3d(0.0, 2.0, 0.0), 1e-15));
  // τ = (0, 0, 0.5) + (1, 0, 0) × (0, 2, 0) = (0, 0, 2.5)
  EXPECT_TRUE(in_W.torque.isApprox(Eigen::Vector3d(0.0, 0.0, 2.5), 1e-15));
  // At F's point (0, 1, 0), which is the world origin (the centre of mass): no moment arm, τ = (0, 0, 0.5)
  // where F's origin gave 2.5.
  const Eigen::Vector3d p_FQ(0.0, 1.0, 0.0);
  const rigid_body::Wrench at_point = wrenchInWorld(wrench_F, X_WF, Eigen::Vector3d::Zero(), &p_FQ);
  EXPECT_TRUE(at_point.force.isApprox(Eigen::Vector3d(0.0, 2.0, 0.0), 1e-15));
  EXPECT_TRUE(at_point.torque.isApprox(Eigen::Vector3d(0.0, 0.0, 0.5), 1e-15)) << at_point.torque.transpose();
  // Seen from a centre of mass at (−1, 0, 0) the same point has arm (1, 0, 0): τ_z = 0.5 + 2.
  EXPECT_NEAR(wrenchInWorld(wrench_F, X_WF, Eigen::Vector3d(-1, 0, 0), &p_FQ).torque.z(), 2.5, 1e-15);
}

TEST(Conversions, OdometryTwistIsInTheBodyFrame) {
  const rigid_body::MassProperties box = rigid_body::MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1));
  const Eigen::Quaterniond yaw90(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  // Moving along world +x while yawed 90°: in body axes that is −y. Spinning about world z: body z.
  const rigid_body::State state = rigid_body::stateFromVelocities(box, Eigen::Vector3d(1, 2, 3), yaw90,
                                                                  Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 0.5));
  nav_msgs::Odometry odom;
  fillOdometry(box, state, odom);
  EXPECT_NEAR(odom.twist.twist.linear.x, 0.0, 1e-15);
  EXPECT_NEAR(odom.twist.twist.linear.y, -1.0, 1e-15);
  EXPECT_NEAR(odom.twist.twist.angular.z, 0.5, 1e-15);
  EXPECT_EQ(odom.pose.pose.position.y, 2.0);
  EXPECT_NEAR(odom.pose.pose.orientation.z, std::sqrt(0.5), 1e-15);

  rigid_body_sim::RigidBodyState message;
  rigid_body::AppliedWrench input;
  input.body.force = Eigen::Vector3d(1, 0, 0);
  fillStateMessage(rigid_body::Model{box, rigid_body::ForceModel{}}, state, input, message);
  EXPECT_NEAR(message.twist.linear.x, 1.0, 1e-15);  // world axes in the state message
  EXPECT_NEAR(message.applied_wrench.force.y, 1.0, 1e-15);
  EXPECT_NEAR(message.kinetic_energy, 0.5 * 1.0 + 0.5 * 0.25 * box.inertia()(2, 2), 1e-15);
}

TEST(Conversions, ThePublishedFramesTwistIsTheDerivativeOfItsPose) {
  // A body spinning and moving in zero g, its published frame P offset and turned from the centre of mass
  // (as a URDF link's): the twist publishedFrame reports must be what P's pose does, by central differences
  // over a fine rk4 run (error O(h²)), in world axes and in P's own (the odometry's).
  const rigid_body::MassProperties mass = rigid_body::MassProperties::box(2.0, Eigen::Vector3d(0.4, 0.3, 0.2));
  Eigen::Isometry3d X_BP = Eigen::Isometry3d::Identity();
  X_BP.linear() = Eigen::Matrix3d(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));
  X_BP.translation() = Eigen::Vector3d(-0.1, 0.25, 0.05);
  rigid_body::BodyDefinition definition;
  definition.model.mass = mass;
  definition.initial = rigid_body::stateFromVelocities(mass, Eigen::Vector3d(1, 2, 3),
                                                       Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())),
                                                       Eigen::Vector3d(0.4, -0.3, 0.2), Eigen::Vector3d(1.5, -0.5, 2.0));
  definition.takes_input = false;
  const double h = 1e-5;
  rigid_body::Scene scene({definition}, rigid_body::IntegratorType::kRk4, h);
  const FrameMotion before = publishedFrame(mass, scene.state(), X_BP);
  scene.step(1);
  const FrameMotion now = publishedFrame(mass, scene.state(), X_BP);
  scene.step(1);
  const FrameMotion after = publishedFrame(mass, scene.state(), X_BP);
  const Eigen::Vector3d velocity = (after.p_WP - before.p_WP) / (2.0 * h);
  EXPECT_LT((velocity - now.v_WP_W).norm(), 1e-8);
  // Angular velocity from the orientation: q̇ = ½ ω q.
  const Eigen::Quaterniond dq = after.q_WP * before.q_WP.conjugate();
  const Eigen::Vector3d w = Eigen::AngleAxisd(dq).angle() / (2.0 * h) * Eigen::AngleAxisd(dq).axis();
  EXPECT_LT((w - now.w_W).norm(), 1e-8);
  // The odometry carries both in P's axes.
  nav_msgs::Odometry odom;
  const FrameMotion last = publishedFrame(mass, scene.state(), X_BP);
  fillOdometry(last, odom);
  Eigen::Vector3d v_P;
  tf2::fromMsg(odom.twist.twist.linear, v_P);
  EXPECT_LT((last.q_WP * v_P - last.v_WP_W).norm(), 1e-12);
}

// bodies/states' entry: the published frame's pose, and its origin's velocity and the angular velocity in
// world axes (not body axes, as odometry): yawed 90°, moving along world +x and spinning about world z at
// 2 rad/s, with the published frame 0.5 m along body x (world +y here), so its origin moves at
// v + ω × (R p_BP) = (1, 0, 0) + (0, 0, 2) × (0, 0.5, 0) = (0, 0, 0).
TEST(Conversions, ABodyStateIsThePublishedFramesPoseAndWorldAxesTwist) {
  const rigid_body::MassProperties box = rigid_body::MassProperties::box(1.0, Eigen::Vector3d(0.4, 0.2, 0.1));
  const Eigen::Quaterniond yaw90(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const rigid_body::State state = rigid_body::stateFromVelocities(box, Eigen::Vector3d(1, 2, 3), yaw90,
                                                                  Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 2));
  Eigen::Isometry3d X_BP = Eigen::Isometry3d::Identity();
  X_BP.translation() = Eigen::Vector3d(0.5, 0, 0);
  geometry_msgs::Pose pose;
  geometry_msgs::Twist twist;
  fillBodyState(publishedFrame(box, state, X_BP), pose, twist);
  EXPECT_NEAR(pose.position.x, 1.0, 1e-15);
  EXPECT_NEAR(pose.position.y, 2.5, 1e-15);
  EXPECT_NEAR(twist.linear.x, 0.0, 1e-15);
  EXPECT_NEAR(twist.linear.y, 0.0, 1e-15);
  EXPECT_NEAR(twist.angular.z, 2.0, 1e-15);
  // The body frame itself: the centre of mass moving along world +x, in world axes, its pose the state's.
  fillBodyState(bodyFrame(box, state), pose, twist);
  EXPECT_EQ(pose.orientation.w, state.q_WB.w());
  EXPECT_NEAR(twist.linear.x, 1.0, 1e-15);
  EXPECT_NEAR(twist.linear.y, 0.0, 1e-15);
}
