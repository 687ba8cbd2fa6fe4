#include "rigid_body_sim/forces.hpp"

namespace rigid_body {

Wrench wrenchAboutCentreOfMass(const Eigen::Vector3d& force_W, const Eigen::Vector3d& torque_at_O_W,
                               const Eigen::Vector3d& p_WO, const Eigen::Vector3d& p_WB) {
  Wrench wrench;
  wrench.force = force_W;
  wrench.torque = torque_at_O_W + (p_WO - p_WB).cross(force_W);
  return wrench;
}

Wrench forceAtPoint(const Eigen::Vector3d& force_W, const Eigen::Vector3d& p_WQ, const State& state) {
  return wrenchAboutCentreOfMass(force_W, Eigen::Vector3d::Zero(), p_WQ, state.p_WB);
}

Wrench forceAtBodyPoint(const Eigen::Vector3d& force_W, const Eigen::Vector3d& p_BQ_B, const State& state) {
  return forceAtPoint(force_W, state.p_WB + state.q_WB * p_BQ_B, state);
}

}  // namespace rigid_body
