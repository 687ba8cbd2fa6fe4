// The Newton–Euler right-hand side Ẏ = f(Y, u) of the state-space form:
//   ẋ = v = P/M,   q̇ = ½ [0, ω] ⊗ q,   Ṗ = F,   L̇ = τ,   with ω = R I_Bcm_B⁻¹ Rᵀ L.
// (Baraff & Witkin, "Physically Based Modeling", rigid body dynamics, eqs. 2-43 and 4-2.)
#pragma once

#include <Eigen/Core>

#include "rigid_body_sim/forces.hpp"
#include "rigid_body_sim/kinematics.hpp"
#include "rigid_body_sim/mass_properties.hpp"
#include "rigid_body_sim/state.hpp"
#include "rigid_body_sim/step_terms.hpp"

namespace rigid_body {

/// The constant description of one body: its mass properties, the force models acting on it and the terms
/// its step evaluates (every term unless the scene assembled fewer: assembleTerms).
struct Model {
  MassProperties mass;
  ForceModel forces;
  StepTerms terms = StepTerms::all();
};

/// The motion of a body at one instant as its step needs it: R only when the step uses it (rotation or a
/// body-fixed input), ω through the isotropic shortcut when the terms say so.
Motion motionOf(const Model& model, const State& state);

/// I⁻¹(t) v as the model's terms assemble it: R(I_Bcm_B⁻¹(Rᵀ v)), or v/I₀ for an isotropic body.
Eigen::Vector3d applyWorldInverseInertia(const Model& model, const Eigen::Matrix3d& R_WB, const Eigen::Vector3d& v_W);

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
Wrench externalWrench(const Model& model, const Eigen::Matrix3d& R_WB, const AppliedWrench& input);

/// Total wrench about the centre of mass in world axes: externalWrench plus damping −c v, −c_ω ω (as assembled).
Wrench totalWrench(const Model& model, const Motion& motion, const AppliedWrench& input);

/// q̇ = ½ [0, ω] ⊗ q for a world-axes ω, as coefficients (x, y, z, w).
Eigen::Vector4d quaternionRate(const Eigen::Vector3d& w_WB_W, const Eigen::Quaterniond& q_WB);

/// Ẏ = f(Y, u).
Derivative derivative(const Model& model, const State& state, const AppliedWrench& input);

}  // namespace rigid_body
