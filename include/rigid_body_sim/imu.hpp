// What an ideal inertial measurement unit fixed on a body reads: the specific force and the angular velocity
// at its mounting point, in its own axes (REP 145: a body at rest on the ground reads +g upward).
//
// The sensor S sits at r = p_BS on the body. Its point's acceleration is that of the centre of mass plus the
// lever-arm terms of a rigid body (docs/references.md, "An accelerometer off the centre of mass"):
//   a_S = a + α × r + ω × (ω × r),   a = F / M,   α = I(t)⁻¹ (τ − ω × L),
// and an accelerometer reads the specific force f = a_S − g (gravity is the one force it cannot feel).
// Contact acts by impulses within a step: its force is their mean over the last step, Σ J / h (and its
// torque Σ (p − x) × J / h), which is the force a resting contact carries, M g up.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "rigid_body_sim/contact.hpp"
#include "rigid_body_sim/dynamics.hpp"
#include "rigid_body_sim/state.hpp"

namespace rigid_body {

/// Where the sensor is on the body: its origin and its axes in the body frame B (centre of mass, body axes).
struct ImuMount {
  Eigen::Vector3d p_BS_B = Eigen::Vector3d::Zero();           ///< [m]
  Eigen::Quaterniond q_BS = Eigen::Quaterniond::Identity();   ///< sensor axes in body axes
};

/// An ideal reading, every vector in the sensor's axes.
struct ImuReading {
  Eigen::Vector3d specific_force_S = Eigen::Vector3d::Zero();    ///< f = a_S − g [m/s²]
  Eigen::Vector3d angular_velocity_S = Eigen::Vector3d::Zero();  ///< ω [rad/s]
  Eigen::Quaterniond q_WS = Eigen::Quaterniond::Identity();      ///< the sensor's orientation in the world
};

/// The mean wrench a body's contacts exerted over the last step of length h, about its centre of mass x_W in
/// world axes: F = Σ J / h, τ = Σ (p − x) × J / h, with J = normal impulse n + friction impulse.
Wrench contactWrench(const std::vector<Contact>& contacts, const Eigen::Vector3d& x_W, double h);

/// The reading of a sensor mounted at `mount` on a body in `state`, under its model's forces (every term
/// evaluated, whatever the step assembles), the applied input and the contacts' mean wrench.
ImuReading imuReading(const Model& model, const State& state, const AppliedWrench& input, const Wrench& contact,
                      const ImuMount& mount);

}  // namespace rigid_body
