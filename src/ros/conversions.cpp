#include "rigid_body_sim/ros/conversions.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <cmath>

#include "rigid_body_sim/kinematics.hpp"

namespace rigid_body_ros {

WrenchFrame classifyWrenchFrame(const std::string& frame_id, const std::string& world_frame,
                                const std::string& body_frame) {
  if (frame_id.empty() || frame_id == body_frame) return WrenchFrame::kBody;
  if (frame_id == world_frame) return WrenchFrame::kWorld;
  return WrenchFrame::kOther;
}

rigid_body::Wrench toWrench(const geometry_msgs::Wrench& wrench) {
  rigid_body::Wrench result;
  tf2::fromMsg(wrench.force, result.force);
  tf2::fromMsg(wrench.torque, result.torque);
  return result;
}

WrenchAtPoint wrenchAtPointInWorld(const geometry_msgs::Wrench& wrench_F, const Eigen::Isometry3d& X_WF,
                                   const Eigen::Vector3d* p_FQ) {
  const rigid_body::Wrench in_F = toWrench(wrench_F);
  WrenchAtPoint result;
  result.wrench_W.force = X_WF.linear() * in_F.force;
  result.wrench_W.torque = X_WF.linear() * in_F.torque;
  result.p_WQ = p_FQ ? Eigen::Vector3d(X_WF * *p_FQ) : Eigen::Vector3d(X_WF.translation());
  return result;
}

void fillOdometry(const rigid_body::MassProperties& mass, const rigid_body::State& state, nav_msgs::Odometry& odom) {
  const rigid_body::Motion motion = rigid_body::motionOf(mass, state);
  odom.pose.pose.position = tf2::toMsg(state.p_WB);
  odom.pose.pose.orientation = tf2::toMsg(state.q_WB);
  const Eigen::Matrix3d R_BW = motion.R_WB.transpose();
  tf2::toMsg(Eigen::Vector3d(R_BW * motion.v_WB_W), odom.twist.twist.linear);
  tf2::toMsg(Eigen::Vector3d(R_BW * motion.w_WB_W), odom.twist.twist.angular);
}

FrameMotion publishedFrame(const rigid_body::MassProperties& mass, const rigid_body::State& state,
                           const Eigen::Isometry3d& X_BP) {
  const rigid_body::Motion motion = rigid_body::motionOf(mass, state);
  const Eigen::Vector3d p_BP_W = motion.R_WB * X_BP.translation();
  FrameMotion frame;
  frame.p_WP = state.p_WB + p_BP_W;
  frame.q_WP = (state.q_WB * Eigen::Quaterniond(X_BP.linear())).normalized();
  frame.v_WP_W = motion.v_WB_W + motion.w_WB_W.cross(p_BP_W);
  frame.w_W = motion.w_WB_W;
  return frame;
}

FrameMotion bodyFrame(const rigid_body::MassProperties& mass, const rigid_body::State& state) {
  const rigid_body::Motion motion = rigid_body::motionOf(mass, state);
  return FrameMotion{state.p_WB, state.q_WB, motion.v_WB_W, motion.w_WB_W};
}

void fillBodyState(const FrameMotion& frame, geometry_msgs::Pose& pose, geometry_msgs::Twist& twist) {
  pose.position = tf2::toMsg(frame.p_WP);
  pose.orientation = tf2::toMsg(frame.q_WP);
  tf2::toMsg(frame.v_WP_W, twist.linear);
  tf2::toMsg(frame.w_W, twist.angular);
}

void fillOdometry(const FrameMotion& frame, nav_msgs::Odometry& odom) {
  odom.pose.pose.position = tf2::toMsg(frame.p_WP);
  odom.pose.pose.orientation = tf2::toMsg(frame.q_WP);
  const Eigen::Matrix3d R_PW = frame.q_WP.toRotationMatrix().transpose();
  tf2::toMsg(Eigen::Vector3d(R_PW * frame.v_WP_W), odom.twist.twist.linear);
  tf2::toMsg(Eigen::Vector3d(R_PW * frame.w_W), odom.twist.twist.angular);
}

void fillTransform(const FrameMotion& frame, geometry_msgs::TransformStamped& transform) {
  transform.transform.translation.x = frame.p_WP.x();
  transform.transform.translation.y = frame.p_WP.y();
  transform.transform.translation.z = frame.p_WP.z();
  transform.transform.rotation = tf2::toMsg(frame.q_WP);
}

void fillStateMessage(const rigid_body::Model& model, const rigid_body::State& state, const FrameMotion& frame,
                      const rigid_body::AppliedWrench& input, rigid_body_sim::RigidBodyState& message) {
  fillStateMessage(model, state, input, message);
  message.pose.position = tf2::toMsg(frame.p_WP);
  message.pose.orientation = tf2::toMsg(frame.q_WP);
  tf2::toMsg(frame.v_WP_W, message.twist.linear);
}

void fillTransform(const rigid_body::State& state, geometry_msgs::TransformStamped& transform) {
  transform.transform.translation.x = state.p_WB.x();
  transform.transform.translation.y = state.p_WB.y();
  transform.transform.translation.z = state.p_WB.z();
  transform.transform.rotation = tf2::toMsg(state.q_WB);
}

void fillStateMessage(const rigid_body::Model& model, const rigid_body::State& state,
                      const rigid_body::AppliedWrench& input, rigid_body_sim::RigidBodyState& message) {
  const rigid_body::Motion motion = rigid_body::motionOf(model.mass, state);
  message.pose.position = tf2::toMsg(state.p_WB);
  message.pose.orientation = tf2::toMsg(state.q_WB);
  tf2::toMsg(motion.v_WB_W, message.twist.linear);
  tf2::toMsg(motion.w_WB_W, message.twist.angular);
  tf2::toMsg(state.P_W, message.linear_momentum);
  tf2::toMsg(state.L_W, message.angular_momentum);
  tf2::toMsg(Eigen::Vector3d(input.world.force + motion.R_WB * input.body.force), message.applied_wrench.force);
  tf2::toMsg(Eigen::Vector3d(input.world.torque + motion.R_WB * input.body.torque), message.applied_wrench.torque);
  message.kinetic_energy = rigid_body::kineticEnergy(model.mass, state);
  message.potential_energy = rigid_body::potentialEnergy(model.mass, model.forces, state);
  message.quaternion_norm_error = rigid_body::quaternionNormError(state);
}

}  // namespace rigid_body_ros
