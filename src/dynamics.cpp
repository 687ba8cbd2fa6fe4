#include "rigid_body_sim/dynamics.hpp"

#include "rigid_body_sim/rotation.hpp"

namespace rigid_body {

Eigen::Vector3d applyWorldInverseInertia(const Model& model, const Eigen::Matrix3d& R_WB, const Eigen::Vector3d& v_W) {
  if (!model.terms.world_inertia) return model.mass.inverseInertia()(0, 0) * v_W;  // isotropic: any axes
  return R_WB * (model.mass.inverseInertia() * (R_WB.transpose() * v_W));
}

Motion motionOf(const Model& model, const State& state) {
  Motion motion;
  const StepTerms& terms = model.terms;
  // R of the unnormalised stage quaternion (rotationMatrix scales by 1/|q|², no square root); not formed when
  // nothing uses it (no rotation and no input to turn).
  if (terms.rotation || terms.input) {
    motion.R_WB = rotationMatrix(state.q_WB);
  } else {
    motion.R_WB.setIdentity();
  }
  motion.v_WB_W = model.mass.inverseMass() * state.P_W;
  if (terms.rotation) {
    motion.w_WB_W = applyWorldInverseInertia(model, motion.R_WB, state.L_W);
  } else {
    motion.w_WB_W.setZero();
  }
  return motion;
}

Wrench externalWrench(const Model& model, const Eigen::Matrix3d& R_WB, const AppliedWrench& input) {
  Wrench external;
  if (model.terms.input) {
    external.force = input.world.force + R_WB * input.body.force;
    external.torque = input.world.torque + R_WB * input.body.torque;
  }
  if (model.terms.gravity) external.force += model.mass.mass() * model.forces.gravity_W;
  return external;
}

Wrench totalWrench(const Model& model, const Motion& motion, const AppliedWrench& input) {
  Wrench total = externalWrench(model, motion.R_WB, input);
  if (model.terms.linear_damping) total.force -= model.forces.linear_damping * motion.v_WB_W;
  if (model.terms.angular_damping) total.torque -= model.forces.angular_damping * motion.w_WB_W;
  return total;
}

Eigen::Vector4d quaternionRate(const Eigen::Vector3d& w_WB_W, const Eigen::Quaterniond& q_WB) {
  const Eigen::Quaterniond omega(0.0, w_WB_W.x(), w_WB_W.y(), w_WB_W.z());
  return 0.5 * (omega * q_WB).coeffs();
}

Derivative derivative(const Model& model, const State& state, const AppliedWrench& input) {
  const Motion motion = motionOf(model, state);
  const Wrench wrench = totalWrench(model, motion, input);
  Derivative rate;
  rate.p_dot = motion.v_WB_W;
  rate.P_dot = wrench.force;
  rate.w_WB_W = motion.w_WB_W;
  if (model.terms.rotation) {
    rate.q_dot = quaternionRate(motion.w_WB_W, state.q_WB);
    rate.L_dot = wrench.torque;
  } else {
    rate.q_dot.setZero();
    rate.L_dot.setZero();
  }
  return rate;
}

}  // namespace rigid_body
