// The mutable state of one rigid body in the classic state-space form Y = (x, q, P, L)
// (Baraff & Witkin, "Physically Based Modeling", SIGGRAPH course notes, rigid body dynamics §2).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rigid_body {

/// State Y of one rigid body. The body frame B has its origin at the centre of mass and its axes
/// are the axes in which the body inertia I_Bcm_B is given. W is the (inertial) world frame.
struct State {
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();            ///< x: position of B's origin (centre of mass) in W [m]
  Eigen::Quaterniond q_WB = Eigen::Quaterniond::Identity();  ///< q: orientation of B in W (maps body to world), unit
  Eigen::Vector3d P_W = Eigen::Vector3d::Zero();             ///< P: linear momentum, world axes [kg m/s]
  Eigen::Vector3d L_W = Eigen::Vector3d::Zero();             ///< L: angular momentum about the centre of mass, world axes [kg m^2/s]
  double t = 0.0;                                            ///< time since this state was set or reset [s]
};

/// True when every component of the state is finite (no NaN, no Inf).
bool isFinite(const State& state);

}  // namespace rigid_body
