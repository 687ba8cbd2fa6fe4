#include "rigid_body_sim/kinematics.hpp"

namespace rigid_body {

Eigen::Vector3d linearVelocity(const MassProperties& mass, const State& state) { return mass.inverseMass() * state.P_W; }

Eigen::Vector3d angularVelocity(const MassProperties& mass, const State& state) { return motionOf(mass, state).w_WB_W; }

double kineticEnergy(const MassProperties& mass, const State& state) {
  const Motion motion = motionOf(mass, state);
  return 0.5 * motion.v_WB_W.dot(state.P_W) + 0.5 * motion.w_WB_W.dot(state.L_W);
}

double potentialEnergy(const MassProperties& mass, const ForceModel& forces, const State& state) {
  return -mass.mass() * forces.gravity_W.dot(state.p_WB);
}

double quaternionNormError(const State& state) { return state.q_WB.norm() - 1.0; }

State stateFromVelocities(const MassProperties& mass, const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& q_WB,
                          const Eigen::Vector3d& v_WB_W, const Eigen::Vector3d& w_WB_B) {
  State state;
  state.p_WB = p_WB;
  state.q_WB = q_WB.normalized();
  state.P_W = mass.mass() * v_WB_W;
  state.L_W = state.q_WB * (mass.inertia() * w_WB_B);
  return state;
}

}  // namespace rigid_body
