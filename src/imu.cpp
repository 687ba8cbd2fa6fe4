#include "rigid_body_sim/imu.hpp"

#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/rotation.hpp"

namespace rigid_body {

Wrench contactWrench(const std::vector<Contact>& contacts, const Eigen::Vector3d& x_W, double h) {
  Wrench wrench;
  for (const Contact& contact : contacts) {
    const Eigen::Vector3d impulse = contact.normal_impulse * contact.normal_W + contact.friction_impulse_W;
    wrench.force += impulse;
    wrench.torque += (contact.position_W - x_W).cross(impulse);
  }
  wrench.force /= h;
  wrench.torque /= h;
  return wrench;
}

ImuReading imuReading(const Model& model, const State& state, const AppliedWrench& input, const Wrench& contact,
                      const ImuMount& mount) {
  const StepTerms all = StepTerms::all();
  const Motion motion = motionOf(model.mass, state, all);
  // Every force but gravity: the accelerometer reads (F − M g) / M, so gravity is never added.
  StepTerms felt = all;
  felt.gravity = false;
  const Wrench wrench = totalWrench(model, felt, motion, input);
  const Eigen::Vector3d& w = motion.w_WB_W;
  const Eigen::Vector3d felt_force = wrench.force + contact.force;
  const Eigen::Vector3d torque = wrench.torque + contact.torque;
  // α = I(t)⁻¹ (τ − ω × L): the time derivative of ω = I(t)⁻¹ L with İ⁻¹ = [ω]I⁻¹ − I⁻¹[ω] (Euler's equations
  // in world axes).
  const Eigen::Vector3d alpha = applyWorldInverseInertia(model.mass, all, motion.R_WB, torque - w.cross(state.L_W));
  const Eigen::Vector3d r_W = motion.R_WB * mount.p_BS_B;
  const Eigen::Vector3d f_W = model.mass.inverseMass() * felt_force + alpha.cross(r_W) + w.cross(w.cross(r_W));
  const Eigen::Quaterniond q_WB = state.q_WB.normalized();
  ImuReading reading;
  reading.q_WS = (q_WB * mount.q_BS).normalized();
  const Eigen::Matrix3d R_SW = reading.q_WS.toRotationMatrix().transpose();
  reading.specific_force_S = R_SW * f_W;
  reading.angular_velocity_S = R_SW * w;
  return reading;
}

}  // namespace rigid_body
