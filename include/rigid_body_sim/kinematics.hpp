// Quantities derived from the state and the mass properties: velocities, world inertia, energy, momentum.
#pragma once

#include <Eigen/Core>

#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body {

/// The motion of a body at one instant, derived once and shared by force evaluation and the derivative.
struct Motion {
  Eigen::Matrix3d R_WB;     ///< R(q): body to world rotation of the normalised q
  Eigen::Vector3d v_WB_W;   ///< v = P/M [m/s], world axes
  Eigen::Vector3d w_WB_W;   ///< ω = I⁻¹(t) L [rad/s], world axes
};

/// I⁻¹(t) v = R I_Bcm_B⁻¹ Rᵀ v [1/(kg m^2)] · v: applied as three matrix–vector products, never forming
/// I⁻¹(t) (two matrix products) nor inverting I(t); for an isotropic body it is v/I₀, with no rotation at all.
Eigen::Vector3d applyWorldInverseInertia(const MassProperties& mass, const Eigen::Matrix3d& R_WB,
                                         const Eigen::Vector3d& v_W);

/// Derives R, I⁻¹(t), v and ω from the state (q is normalised first, so stage states of RK methods with
/// |q| ≠ 1 still give a rotation).
Motion motionOf(const MassProperties& mass, const State& state);

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

}  // namespace rigid_body
