#include "rigid_body_sim/dynamics.hpp"

namespace rigid_body {

Wrench externalWrench(const Model& model, const Eigen::Matrix3d& R_WB, const AppliedWrench& input) {
  Wrench external = input.world;
  external.force += R_WB * input.body.force + model.mass.mass() * model.forces.gravity_W;
  external.torque += R_WB * input.body.torque;
  return external;
}

Wrench totalWrench(const Model& model, const Motion& motion, const AppliedWrench& input) {
  Wrench total = externalWrench(model, motion.R_WB, input);
  total.force -= model.forces.linear_damping * motion.v_WB_W;
  total.torque -= model.forces.angular_damping * motion.w_WB_W;
  return total;
}

Eigen::Vector4d quaternionRate(const Eigen::Vector3d& w_WB_W, const Eigen::Quaterniond& q_WB) {
  const Eigen::Quaterniond omega(0.0, w_WB_W.x(), w_WB_W.y(), w_WB_W.z());
  return 0.5 * (omega * q_WB).coeffs();
}

Derivative derivative(const Model& model, const State& state, const AppliedWrench& input) {
  const Motion motion = motionOf(model.mass, state);
  const Wrench wrench = totalWrench(model, motion, input);
  Derivative rate;
  rate.p_dot = motion.v_WB_W;
  rate.q_dot = quaternionRate(motion.w_WB_W, state.q_WB);
  rate.P_dot = wrench.force;
  rate.L_dot = wrench.torque;
  rate.w_WB_W = motion.w_WB_W;
  return rate;
}

}  // namespace rigid_body
