// The Newton–Euler right-hand side Ẏ = f(Y, u) of the state-space form:
//   ẋ = v = P/M,   q̇ = ½ [0, ω] ⊗ q,   Ṗ = F,   L̇ = τ,   with ω = R I_Bcm_B⁻¹ Rᵀ L.
// (Baraff & Witkin, "Physically Based Modeling", rigid body dynamics, eqs. 2-43 and 4-2.)
// Every function takes the body's constant Model and the StepTerms assembled beside it: a term left out
// is not evaluated at all (see step_terms.hpp).
#pragma once

#include <Eigen/Core>

#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/rotation.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {

/// The constant description of one body: its mass properties and the force models acting on it. Set once
/// when the scene is made; what a step evaluates of it is the StepTerms kept beside it.
struct Model {
  MassProperties mass;
  ForceModel forces;
};

/// Ẏ, with the quaternion rate as Eigen's coefficient order (x, y, z, w).
struct Derivative {
  Eigen::Vector3d p_dot;  ///< ẋ [m/s]
  Eigen::Vector4d q_dot;  ///< q̇ [1/s], coefficients (x, y, z, w)
  Eigen::Vector3d P_dot;  ///< Ṗ = F [N]
  Eigen::Vector3d L_dot;  ///< L̇ = τ [N m]
  Eigen::Vector3d w_WB_W; ///< ω [rad/s], world axes: q̇ as an element of the Lie algebra (q̇ = ½[0, ω]⊗q)
};

/// The wrench that does not depend on the velocities, about the centre of mass in world axes: the applied
/// input (world part plus the body part turned by R_WB) and gravity M g, each only if its term is assembled.
Wrench externalWrench(const Model& model, const StepTerms& terms, const Eigen::Matrix3d& R_WB,
                      const AppliedWrench& input);

/// Total wrench about the centre of mass in world axes: externalWrench plus damping −c v, −c_ω ω (as assembled).
Wrench totalWrench(const Model& model, const StepTerms& terms, const Motion& motion, const AppliedWrench& input);

/// q̇ = ½ [0, ω] ⊗ q for a world-axes ω, as coefficients (x, y, z, w).
Eigen::Vector4d quaternionRate(const Eigen::Vector3d& w_WB_W, const Eigen::Quaterniond& q_WB);

/// Ẏ = f(Y, u).
Derivative derivative(const Model& model, const StepTerms& terms, const State& state, const AppliedWrench& input);

// ---------------------------------------------------------------------------------------------------------
// Definitions: inline, since they are the hot step of every integrator (a call per stage otherwise).

inline Wrench externalWrench(const Model& model, const StepTerms& terms, const Eigen::Matrix3d& R_WB,
                             const AppliedWrench& input) {
  Wrench external;
  if (terms.input) {
    external.force = input.world.force + R_WB * input.body.force;
    external.torque = input.world.torque + R_WB * input.body.torque;
  }
  if (terms.gravity) external.force += model.mass.mass() * model.forces.gravity_W;
  return external;
}

inline Wrench totalWrench(const Model& model, const StepTerms& terms, const Motion& motion,
                          const AppliedWrench& input) {
  Wrench total = externalWrench(model, terms, motion.R_WB, input);
  if (terms.linear_damping) total.force -= model.forces.linear_damping * motion.v_WB_W;
  if (terms.angular_damping) total.torque -= model.forces.angular_damping * motion.w_WB_W;
  return total;
}

inline Eigen::Vector4d quaternionRate(const Eigen::Vector3d& w_WB_W, const Eigen::Quaterniond& q_WB) {
  const Eigen::Quaterniond omega(0.0, w_WB_W.x(), w_WB_W.y(), w_WB_W.z());
  return 0.5 * (omega * q_WB).coeffs();
}

inline Derivative derivative(const Model& model, const StepTerms& terms, const State& state,
                             const AppliedWrench& input) {
  const Motion motion = motionOf(model.mass, state, terms);
  const Wrench wrench = totalWrench(model, terms, motion, input);
  Derivative rate;
  rate.p_dot = motion.v_WB_W;
  rate.P_dot = wrench.force;
  rate.w_WB_W = motion.w_WB_W;
  if (terms.rotation) {
    rate.q_dot = quaternionRate(motion.w_WB_W, state.q_WB);
    rate.L_dot = wrench.torque;
  } else {
    rate.q_dot.setZero();
    rate.L_dot.setZero();
  }
  return rate;
}

}  // namespace rigid_body
