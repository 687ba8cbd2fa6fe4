// The benchmarks' general body: everything a step can meet, a full (non-diagonal) inertia tensor, spin,
// gravity, linear and angular damping, and an input with world and body parts. One definition for
// integrators_benchmark, scene_benchmark and step_anatomy, so that their numbers are of the same body.
#pragma once

#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/kinematics.hpp"

namespace rigid_body {
namespace bench_bodies {

inline Model generalModel() {
  Eigen::Matrix3d I;
  I << 0.02, 0.001, -0.002,  //
      0.001, 0.05, 0.003,    //
      -0.002, 0.003, 0.06;
  Model model{MassProperties::fromInertia(1.5, I), ForceModel{}};
  model.forces.gravity_W = Eigen::Vector3d(0.0, 0.0, -9.81);
  model.forces.linear_damping = 0.1;
  model.forces.angular_damping = 0.01;
  return model;
}

inline State spinningState(const MassProperties& mass) {
  return stateFromVelocities(mass, Eigen::Vector3d(0.0, 0.0, 1.0),
                             Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())),
                             Eigen::Vector3d(0.5, 0.0, 0.0), Eigen::Vector3d(1.0, 3.0, 0.5));
}

inline AppliedWrench generalInput() {
  AppliedWrench input;
  input.world.force = Eigen::Vector3d(0.1, 0.0, 15.0);
  input.body.torque = Eigen::Vector3d(0.001, 0.0, 0.002);
  return input;
}

}  // namespace bench_bodies
}  // namespace rigid_body
