// Wrenches and the force models a body is subject to.
#pragma once

#include <Eigen/Core>

#include "rigid_body_sim/state.hpp"

namespace rigid_body {

/// A force and a torque about the centre of mass, both in one set of axes (named by the holder).
struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< F [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< τ about the centre of mass [N m]

  Wrench& operator+=(const Wrench& other) {
    force += other.force;
    torque += other.torque;
    return *this;
  }
  bool isFinite() const { return force.allFinite() && torque.allFinite(); }
  bool operator==(const Wrench& other) const { return force == other.force && torque == other.torque; }
};

/// The commanded input, held constant over a step. Its two parts differ in what stays fixed while the
/// body turns: `world` keeps its world axes (a push from outside), `body` turns with the body (a thruster).
/// The total at any instant is world + R(q)·body, both about the centre of mass.
struct AppliedWrench {
  Wrench world;  ///< F_W, τ_W: fixed in world axes
  Wrench body;   ///< F_B, τ_B: fixed in body axes

  bool operator==(const AppliedWrench& other) const { return world == other.world && body == other.body; }
  AppliedWrench& operator+=(const AppliedWrench& other) {
    world += other.world;
    body += other.body;
    return *this;
  }
  bool isFinite() const { return world.isFinite() && body.isFinite(); }
  /// No input at all (every component exactly zero).
  bool isZero() const { return *this == AppliedWrench(); }
};

/// Force models of the scene, evaluated from the state at every stage of a step.
struct ForceModel {
  Eigen::Vector3d gravity_W = Eigen::Vector3d::Zero();  ///< g, uniform, world axes [m/s^2]; F = M g
  double linear_damping = 0.0;   ///< c ≥ 0 [N s/m]: F = −c v
  double angular_damping = 0.0;  ///< c_ω ≥ 0 [N m s/rad]: τ = −c_ω ω
};

/// A wrench (F, τ_O) given at a point O, moved to the centre of mass x: τ = τ_O + (O − x) × F.
/// All vectors in world axes; p_WO and p_WB are positions in W [m].
Wrench wrenchAboutCentreOfMass(const Eigen::Vector3d& force_W, const Eigen::Vector3d& torque_at_O_W,
                               const Eigen::Vector3d& p_WO, const Eigen::Vector3d& p_WB);

/// A force F_W applied at the world point p_WQ: τ = (p_WQ − x) × F (Baraff & Witkin, eq. 2-32).
Wrench forceAtPoint(const Eigen::Vector3d& force_W, const Eigen::Vector3d& p_WQ, const State& state);

/// A force F_W applied at a point given in body coordinates p_BQ_B: p_WQ = x + R p_BQ_B.
Wrench forceAtBodyPoint(const Eigen::Vector3d& force_W, const Eigen::Vector3d& p_BQ_B, const State& state);

}  // namespace rigid_body
