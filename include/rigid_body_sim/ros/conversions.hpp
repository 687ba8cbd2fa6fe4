// Messages into core types and the core state into messages. Pure functions: no node, no master.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Wrench.h>
#include <nav_msgs/Odometry.h>

#include <Eigen/Geometry>
#include <string>

#include "rigid_body_sim/RigidBodyState.h"
#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body_ros {

/// How the frame_id of an incoming WrenchStamped is interpreted.
enum class WrenchFrame {
  kBody,   ///< empty or the body frame: body axes about the centre of mass, turning with the body
  kWorld,  ///< the world frame: world axes about the centre of mass
  kOther,  ///< any other frame: transformed through tf2 into world axes at the frame's origin
};

WrenchFrame classifyWrenchFrame(const std::string& frame_id, const std::string& world_frame,
                                const std::string& body_frame);

/// The message's force and torque as they are (no change of axes).
rigid_body::Wrench toWrench(const geometry_msgs::Wrench& wrench);

/// A wrench in world axes about a world point Q, as the core takes it (World::setWrench moves it to the
/// centre of mass at the step it acts: τ = τ_Q + (p_WQ − x) × F_W).
struct WrenchAtPoint {
  rigid_body::Wrench wrench_W;  ///< F_W [N] and τ_Q [N m] about Q, world axes
  Eigen::Vector3d p_WQ;         ///< Q in W [m]
};

/// A wrench given in frame F (force and torque in F's axes) in world axes: F_W = R_WF F_F, τ_Q = R_WF τ_F,
/// where Q is the point the force acts at: `p_FQ` (in F's coordinates) if given, else F's origin.
WrenchAtPoint wrenchAtPointInWorld(const geometry_msgs::Wrench& wrench_F, const Eigen::Isometry3d& X_WF,
                                   const Eigen::Vector3d* p_FQ = nullptr);

/// Pose and twist of an Odometry message (REP 105): pose of the body in the world frame, twist (linear
/// velocity of the origin of the body frame and angular velocity) in the body frame: v_B = Rᵀ v_W, ω_B = Rᵀ ω_W.
/// Header, frame ids and covariances are the caller's.
void fillOdometry(const rigid_body::MassProperties& mass, const rigid_body::State& state, nav_msgs::Odometry& odom);

/// The published frame P of a body (a URDF link frame) at X_BP in the body frame B at the centre of mass:
/// X_WP = X_WB X_BP; its origin moves at v_P = v_B + ω × (R_WB p_BP); ω is the body's.
struct FrameMotion {
  Eigen::Vector3d p_WP;
  Eigen::Quaterniond q_WP;
  Eigen::Vector3d v_WP_W;  ///< velocity of P's origin, world axes [m/s]
  Eigen::Vector3d w_W;     ///< angular velocity, world axes [rad/s]
};
FrameMotion publishedFrame(const rigid_body::MassProperties& mass, const rigid_body::State& state,
                           const Eigen::Isometry3d& X_BP);
/// The body frame B itself as a FrameMotion (pose and velocities exactly the state's, as odometry has them).
FrameMotion bodyFrame(const rigid_body::MassProperties& mass, const rigid_body::State& state);
/// Odometry, tf and the state message of the published frame P instead of B (pose of P, twist of P's
/// origin; the state's momenta stay about the centre of mass), from publishedFrame's result.
void fillOdometry(const FrameMotion& frame, nav_msgs::Odometry& odom);
void fillTransform(const FrameMotion& frame, geometry_msgs::TransformStamped& transform);
void fillStateMessage(const rigid_body::Model& model, const rigid_body::State& state, const FrameMotion& frame,
                      const rigid_body::AppliedWrench& input, rigid_body_sim::RigidBodyState& message);

/// One body's entry of bodies/states: the published frame's pose in the world frame, its origin's velocity
/// and the angular velocity, both in world axes (as gazebo_msgs/ModelStates).
void fillBodyState(const FrameMotion& frame, geometry_msgs::Pose& pose, geometry_msgs::Twist& twist);

/// Translation and rotation of the world → body transform.
void fillTransform(const rigid_body::State& state, geometry_msgs::TransformStamped& transform);

/// Every field of RigidBodyState but the header and child_frame_id. `input` is the commanded wrench,
/// reported in world axes at the current orientation.
void fillStateMessage(const rigid_body::Model& model, const rigid_body::State& state,
                      const rigid_body::AppliedWrench& input, rigid_body_sim::RigidBodyState& message);

}  // namespace rigid_body_ros
