// Quantities derived from the state and the mass properties: velocities, world inertia, energy, momentum.
// One motionOf family serves the step and everything that reports the state: the same ω for the same state.
#pragma once

#include <Eigen/Core>

#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/rotation.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {

/// The motion of a body at one instant, derived once and shared by force evaluation and the derivative.
struct Motion {
  Eigen::Matrix3d R_WB;     ///< R(q/|q|): body to world rotation (identity when no assembled term uses it)
  Eigen::Vector3d v_WB_W;   ///< v = P/M [m/s], world axes
  Eigen::Vector3d w_WB_W;   ///< ω = I⁻¹(t) L [rad/s], world axes (zero without the rotation term)
};

/// I⁻¹(t) v_W = R I_Bcm_B⁻¹ Rᵀ v_W, applied as three matrix–vector products (never forming I⁻¹(t) nor
/// inverting I(t)); v_W/I₀ when the terms say the body is isotropic (terms.world_inertia false).
Eigen::Vector3d applyWorldInverseInertia(const MassProperties& mass, const StepTerms& terms, const Eigen::Matrix3d& R_WB,
                                         const Eigen::Vector3d& v_W);

/// R, v and ω of a state as the terms assemble them. R is that of q/|q| (rotationMatrix scales by 1/|q|²),
/// so the stage states of Runge–Kutta methods, whose |q| drifts within a step, still give a rotation.
/// StepTerms::all() (the default) is the general formula every report and message uses.
Motion motionOf(const MassProperties& mass, const State& state, const StepTerms& terms = StepTerms::all());

/// v = P/M [m/s], world axes.
Eigen::Vector3d linearVelocity(const MassProperties& mass, const State& state);
/// ω = I⁻¹(t) L [rad/s], world axes.
Eigen::Vector3d angularVelocity(const MassProperties& mass, const State& state);
/// T = ½ vᵀP + ½ ωᵀL [J].
double kineticEnergy(const MassProperties& mass, const State& state);
/// V = −M g·x [J] under uniform gravity (zero when g = 0), zero at the world origin.
double potentialEnergy(const MassProperties& mass, const ForceModel& forces, const State& state);
/// |q| − 1, the drift of the quaternion norm.
double quaternionNormError(const State& state);

/// State with the given pose and velocities (v in world axes, ω in body axes, as the node's parameters
/// give them): P = M v, L = R I_Bcm_B ω_B.
State stateFromVelocities(const MassProperties& mass, const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& q_WB,
                          const Eigen::Vector3d& v_WB_W, const Eigen::Vector3d& w_WB_B);

// ---------------------------------------------------------------------------------------------------------
// Definitions: inline, since they are the hot step of every integrator (a call per stage otherwise).

inline Eigen::Vector3d applyWorldInverseInertia(const MassProperties& mass, const StepTerms& terms,
                                                const Eigen::Matrix3d& R_WB, const Eigen::Vector3d& v_W) {
  if (!terms.world_inertia) return mass.inverseInertia()(0, 0) * v_W;  // isotropic: the same in any axes
  return R_WB * (mass.inverseInertia() * (R_WB.transpose() * v_W));
}

inline Motion motionOf(const MassProperties& mass, const State& state, const StepTerms& terms) {
  Motion motion;
  // R is not formed when nothing uses it (no rotation and no input to turn).
  if (terms.rotation || terms.input) {
    motion.R_WB = rotationMatrix(state.q_WB);
  } else {
    motion.R_WB.setIdentity();
  }
  motion.v_WB_W = mass.inverseMass() * state.P_W;
  if (terms.rotation) {
    motion.w_WB_W = applyWorldInverseInertia(mass, terms, motion.R_WB, state.L_W);
  } else {
    motion.w_WB_W.setZero();
  }
  return motion;
}

}  // namespace rigid_body
